// Cost of the stability analyses against plain simulations of the same length (paper preset,
// sigma = -0.150298, DOP853):
//  - one period with the tangent (the section map, 4 + 16 + 1 components) against one period
//    of the state alone, both at the shooting tolerance 1e-12: the pure price of the tangent;
//  - a Floquet point (protocol, Newton shooting, monodromy) against the protocol alone;
//  - a Lyapunov point (500 transient impacts, then 800 impacts with QR every pi) with each
//    impact mapping, against one state-only run over the same total time at the same
//    tolerance (1e-10).
// Counters: steps and rhs calls of the measured run. The ratios are in docs/stability.md.
#include <benchmark/benchmark.h>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/model/wake_impact.hpp"
#include "vimpact/stability/floquet.hpp"
#include "vimpact/stability/lyapunov.hpp"

namespace {

using vimpact::vec;

vimpact::wake_impact paper(double Ur, double sigma = -0.150298)
{
    vimpact::wake_impact_parameters p;
    p.Ur = Ur;
    p.sigma = sigma;
    return vimpact::wake_impact(p);
}

const vec<4> paper_ic(0.0, 0.0, 0.0, 0.1);

void set_counters(benchmark::State& state, const vimpact::run_stats& s)
{
    state.counters["steps"] = static_cast<double>(s.steps);
    state.counters["rhs_calls"] = static_cast<double>(s.rhs_calls);
}

// The refined P2 orbit point at Ur = 16 (computed once).
const vimpact::floquet_result<4>& ur16_orbit()
{
    static const auto r = vimpact::floquet_analysis(paper(16.0), paper_ic);
    return r;
}

void one_period_with_tangent(benchmark::State& state)
{
    const auto m = paper(16.0);
    const auto& orb = ur16_orbit();
    vimpact::section_return<4> r;
    for (auto _ : state) {
        r = vimpact::section_map(m, orb.orbit_point, orb.section_returns);
        benchmark::DoNotOptimize(r.monodromy.data());
    }
    set_counters(state, r.stats);
}

struct count_returns : vimpact::flow_observer {
    int seen = 0, wanted = 0;
    vimpact::flow_control on_section(vimpact::section_kind k, double, const vec<4>&)
    {
        return (k == vimpact::section_kind::maximum && ++seen >= wanted) ? vimpact::flow_control::stop
                                                                         : vimpact::flow_control::proceed;
    }
};

void one_period_state_only(benchmark::State& state)
{
    const auto m = paper(16.0);
    const auto& orb = ur16_orbit();
    const vimpact::section_map_options mo;
    vimpact::run_stats s;
    for (auto _ : state) {
        vimpact::hybrid_flow<vimpact::wake_impact> flow(m, mo.flow);
        flow.start(0.0, orb.orbit_point);
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
    vimpact::floquet_result<4> r;
    for (auto _ : state) {
        r = vimpact::floquet_analysis(m, paper_ic);
        benchmark::DoNotOptimize(r.multipliers.data());
    }
    vimpact::run_stats s = r.protocol_stats;
    s.steps += r.tangent_stats.steps;
    s.rhs_calls += r.tangent_stats.rhs_calls;
    set_counters(state, s);
}

void protocol_point(benchmark::State& state)
{
    const auto m = paper(16.0);
    const vimpact::protocol_options po;
    vimpact::protocol_result<4> r;
    for (auto _ : state) {
        r = vimpact::run_protocol(m, paper_ic, po);
        benchmark::DoNotOptimize(r.points.data());
    }
    set_counters(state, r.stats);
}

// Lyapunov points: Ur = 16 (periodic) and Ur = 25, sigma = -0.146 (chaotic).
vimpact::wake_impact lyapunov_model(int which) { return which == 0 ? paper(16.0) : paper(25.0, -0.146); }

void lyapunov_point(benchmark::State& state)
{
    const auto m = lyapunov_model(static_cast<int>(state.range(0)));
    vimpact::lyapunov_options lo;
    lo.tdm = static_cast<vimpact::lyapunov_tdm>(state.range(1));
    vimpact::lyapunov_result<4> r;
    for (auto _ : state) {
        r = vimpact::lyapunov_spectrum(m, paper_ic, lo);
        benchmark::DoNotOptimize(r.exponents.data());
    }
    vimpact::run_stats s = r.transient_stats;
    s.steps += r.stats.steps;
    s.rhs_calls += r.stats.rhs_calls;
    set_counters(state, s);
    state.counters["t_final"] = r.t_start + r.time;
}

// The same total time as the saltation Lyapunov run, state only, in one run.
void plain_run_of_lyapunov_length(benchmark::State& state)
{
    const auto m = lyapunov_model(static_cast<int>(state.range(0)));
    const auto L = vimpact::lyapunov_spectrum(m, paper_ic, vimpact::lyapunov_options{});
    vimpact::flow_options fo;
    fo.t_max = L.t_start + L.time;
    vimpact::run_stats s;
    for (auto _ : state) {
        vimpact::hybrid_flow<vimpact::wake_impact> flow(m, fo);
        flow.start(0.0, paper_ic);
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
