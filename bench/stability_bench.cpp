// Cost of the stability analyses against plain simulations of the same length (paper preset,
// sigma = -0.150298, DOP853):
//  - one period with the tangent (the section map, 4 + 16 + 1 components) against one period
//    of the state alone, both at the shooting tolerance 1e-12: the pure price of the tangent.
//    A period alone is not a library call, so both runs are the engine templates on
//    native_model<wake_impact>, the instantiation the library runs for the built-in model;
//  - a Floquet point (protocol, Newton shooting, monodromy) against the protocol alone, both
//    through the library (floquet, simulate);
//  - a Lyapunov point (500 transient impacts, then 800 impacts with QR every pi) with each
//    impact mapping, through the library (lyapunov), against one state-only run over the
//    same total time at the same tolerance (1e-10), the engine's flow with no event.
// Points: Ur = 16 (P2) and, for Lyapunov, Ur = 25, sigma = -0.146 (chaotic).
// Counters: steps and rhs calls of the measured run. The ratios are in docs/stability.md.
#include <benchmark/benchmark.h>

#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/lyapunov.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/hybrid/flow.hpp"
#include "vimpact/model/builtin/wake_impact.hpp"
#include "vimpact/model/model.hpp"
#include "vimpact/model/native_model.hpp"
#include "vimpact/tangent/section_map.hpp"

namespace {

using vimpact::vec;
using native = vimpact::native_model<vimpact::wake_impact>;

vimpact::model paper(double Ur, double sigma = -0.150298)
{
    const vimpact::model m = vimpact::model::builtin("wake_impact");
    return m.with_parameter(m.info().parameter_index("Ur"), Ur).with_parameter(m.info().parameter_index("sigma"), sigma);
}

void set_counters(benchmark::State& state, const vimpact::run_stats& s)
{
    state.counters["steps"] = static_cast<double>(s.steps);
    state.counters["rhs_calls"] = static_cast<double>(s.rhs_calls);
}

// The refined P2 orbit point at Ur = 16 (computed once).
const vimpact::floquet_result& ur16_orbit()
{
    static const auto r = [] {
        const auto m = paper(16.0);
        return vimpact::floquet(m, m.initial_state(), vimpact::floquet_options{});
    }();
    return r;
}

void one_period_with_tangent(benchmark::State& state)
{
    const auto m = paper(16.0);
    const native em(m.parameters());
    const auto& orb = ur16_orbit();
    const vec<4> x(orb.orbit_point);
    vimpact::section_return<4> r;
    for (auto _ : state) {
        r = vimpact::section_map<vimpact::dop853>(em, x, orb.section_returns);
        benchmark::DoNotOptimize(r.monodromy.data());
    }
    set_counters(state, r.stats);
}

struct count_returns : vimpact::flow_observer {
    int seen = 0, wanted = 0;
    template <class X>
    vimpact::flow_control on_section(int, vimpact::crossing, double, const X&)
    {
        return ++seen >= wanted ? vimpact::flow_control::stop : vimpact::flow_control::proceed;
    }
};

// The same returns as the section map, with its flow options and start, without the tangent.
void one_period_state_only(benchmark::State& state)
{
    const auto m = paper(16.0);
    const native em(m.parameters());
    const auto& orb = ur16_orbit();
    const vimpact::section_map_options mo;
    vimpact::flow_options fo = mo.flow;
    fo.surfaces = true;
    fo.events = {vimpact::flow_event::section(mo.section, em.section_direction(mo.section))};
    const vec<4> x0 = vimpact::detail::past_section(em, mo.section, vec<4>(orb.orbit_point));
    vimpact::run_stats s;
    for (auto _ : state) {
        vimpact::hybrid_flow<native, vimpact::dop853> flow(em, fo);
        flow.start(0.0, x0);
        count_returns obs;
        obs.wanted = orb.section_returns;
        benchmark::DoNotOptimize(flow.run(obs));
        s = flow.stats();
    }
    set_counters(state, s);
}

void floquet_point(benchmark::State& state)
{
    const auto m = paper(16.0);
    const Eigen::VectorXd x0 = m.initial_state();
    const vimpact::floquet_options fo;
    vimpact::floquet_result r;
    for (auto _ : state) {
        r = vimpact::floquet(m, x0, fo);
        benchmark::DoNotOptimize(r.multipliers.data());
    }
    vimpact::run_stats s = r.protocol_stats;
    s.add(r.tangent_stats);
    set_counters(state, s);
    state.counters["map_evaluations"] = static_cast<double>(r.map_evaluations);
}

void protocol_point(benchmark::State& state)
{
    const auto m = paper(16.0);
    const Eigen::VectorXd x0 = m.initial_state();
    const vimpact::floquet_options fo;  // the protocol the Floquet point runs
    vimpact::run_stats s;
    for (auto _ : state) {
        const auto r = vimpact::simulate(m, x0, fo.protocol);
        benchmark::DoNotOptimize(r.points.values().data());
        s = r.stats;
    }
    set_counters(state, s);
}

vimpact::model lyapunov_model(int which) { return which == 0 ? paper(16.0) : paper(25.0, -0.146); }

void lyapunov_point(benchmark::State& state)
{
    const auto m = lyapunov_model(static_cast<int>(state.range(0)));
    const Eigen::VectorXd x0 = m.initial_state();
    vimpact::lyapunov_options lo;
    lo.tdm = static_cast<vimpact::lyapunov_tdm>(state.range(1));
    vimpact::lyapunov_result r;
    for (auto _ : state) {
        r = vimpact::lyapunov(m, x0, lo);
        benchmark::DoNotOptimize(r.exponents.data());
    }
    vimpact::run_stats s = r.transient_stats;
    s.add(r.stats);
    set_counters(state, s);
    state.counters["t_final"] = r.t_start + r.time;
}

// The same total time as the saltation Lyapunov run, state only, in one run.
void plain_run_of_lyapunov_length(benchmark::State& state)
{
    const auto m = lyapunov_model(static_cast<int>(state.range(0)));
    const native em(m.parameters());
    const Eigen::VectorXd x0 = m.initial_state();
    const auto L = vimpact::lyapunov(m, x0, vimpact::lyapunov_options{});
    vimpact::flow_options fo;
    fo.t_max = L.t_start + L.time;
    vimpact::run_stats s;
    for (auto _ : state) {
        vimpact::hybrid_flow<native, vimpact::dop853> flow(em, fo);
        flow.start(0.0, vec<4>(x0));
        vimpact::flow_observer obs;
        benchmark::DoNotOptimize(flow.run(obs));
        s = flow.stats();
    }
    set_counters(state, s);
    state.counters["t_final"] = fo.t_max;
}

}  // namespace

BENCHMARK(one_period_with_tangent)->Name("period_Ur16/tangent")->Unit(benchmark::kMicrosecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(one_period_state_only)->Name("period_Ur16/state_only")->Unit(benchmark::kMicrosecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(floquet_point)->Name("floquet_Ur16/point")->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(protocol_point)->Name("floquet_Ur16/protocol_only")->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(lyapunov_point)
    ->Name("lyapunov")
    ->ArgNames({"chaotic", "tdm"})
    ->ArgsProduct({{0, 1}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);
BENCHMARK(plain_run_of_lyapunov_length)
    ->Name("lyapunov_plain_same_length")
    ->ArgNames({"chaotic"})
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);

BENCHMARK_MAIN();
