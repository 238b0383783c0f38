// Cost of continuation (paper preset, sigma = -0.150298, the maxima of y), through the library:
//  - the whole P1 branch over 12 <= Ur <= 15.1 from the attractor at Ur = 12, its period
//    doubling located to 1e-10 (counters: points, bifurcations, map evaluations);
//  - the same branch from a point of the orbit (the continuation alone, no protocol first);
//  - per point of that branch (its time over its points) against a Floquet point at the same
//    tolerances: Newton shooting and the monodromy from a point near the orbit
//    (floquet_from_point, the like-for-like part: no transient), and the whole Floquet analysis
//    of a stability sweep (floquet: the protocol's 500 + 200 impacts first).
// bench/run_continuation_bench.sh prints the ratios of docs/continuation.md.
#include <benchmark/benchmark.h>

#include "vimpact/analysis/continuation.hpp"
#include "vimpact/analysis/floquet.hpp"
#include "vimpact/model/model.hpp"

namespace {

vimpact::model paper(double Ur)
{
    const vimpact::model m = vimpact::model::builtin("wake_impact");
    return m.with_parameter(m.info().parameter_index("Ur"), Ur);
}

vimpact::continuation_options p1_branch()
{
    vimpact::continuation_options o;
    o.parameter = paper(12.0).info().parameter_index("Ur");
    o.start = 12.0;
    o.end = 15.1;
    return o;
}

void p1_branch_with_its_period_doubling(benchmark::State& state)
{
    const auto m = paper(12.0);
    const auto o = p1_branch();
    vimpact::continuation_result r;
    for (auto _ : state) {
        r = vimpact::continuation(m, {m.initial_state()}, o, 1);
        benchmark::DoNotOptimize(r);
    }
    const auto& b = r.branches.at(0);
    state.counters["points"] = static_cast<double>(b.points.size());
    state.counters["bifurcations"] = static_cast<double>(r.bifurcations.size());
    state.counters["tangent_maps"] = static_cast<double>(r.tangent_maps);
    state.counters["plain_maps"] = static_cast<double>(r.plain_maps);
    state.counters["pd_Ur"] = r.bifurcations.empty() ? 0.0 : r.bifurcations[0].parameter;
}
BENCHMARK(p1_branch_with_its_period_doubling)->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();

// The same branch from a point of the orbit (no protocol first): the continuation alone;
// without the bifurcation tests (`detect` false, no period doubling located) the cost of the
// points alone.
void branch_from_a_point(benchmark::State& state, bool detect)
{
    const auto m = paper(12.0);
    auto o = p1_branch();
    o.from_attractor = false;
    o.returns = 1;
    o.detect = detect;
    const auto start = vimpact::floquet(m, m.initial_state(), {}).orbit_point;
    vimpact::continuation_result r;
    for (auto _ : state) {
        r = vimpact::continuation(m, {start}, o, 1);
        benchmark::DoNotOptimize(r);
    }
    state.counters["points"] = static_cast<double>(r.branches.at(0).points.size());
    state.counters["tangent_maps"] = static_cast<double>(r.tangent_maps);
    state.counters["plain_maps"] = static_cast<double>(r.plain_maps);
}

void p1_branch_from_a_point(benchmark::State& state) { branch_from_a_point(state, true); }
BENCHMARK(p1_branch_from_a_point)->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();

void p1_branch_from_a_point_points_only(benchmark::State& state) { branch_from_a_point(state, false); }
BENCHMARK(p1_branch_from_a_point_points_only)->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();

// A Floquet point on the same branch (Ur = 14, P1): Newton and monodromy from a point of the
// orbit's neighbourhood on the section.
void floquet_from_a_point(benchmark::State& state)
{
    const auto m = paper(14.0);
    const auto near = vimpact::floquet(m, m.initial_state(), {}).orbit_point;
    vimpact::floquet_result r;
    for (auto _ : state) {
        r = vimpact::floquet_from_point(m, near, 1, {});
        benchmark::DoNotOptimize(r);
    }
    state.counters["map_evaluations"] = static_cast<double>(r.map_evaluations);
}
BENCHMARK(floquet_from_a_point)->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();

// The whole Floquet analysis of one sweep value: the protocol, then the above.
void floquet_with_its_protocol(benchmark::State& state)
{
    const auto m = paper(14.0);
    vimpact::floquet_result r;
    for (auto _ : state) {
        r = vimpact::floquet(m, m.initial_state(), {});
        benchmark::DoNotOptimize(r);
    }
}
BENCHMARK(floquet_with_its_protocol)->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
