// One bifurcation point of the paper's protocol (Ur = 16, sigma = -0.150298, paper preset,
// 500 impacts discarded, 200 maxima kept, rtol = atol = 1e-10), with each integrator.
// Counters: steps per second and rhs calls. The peer baselines run in bench/run_benchmarks.sh.
#include <benchmark/benchmark.h>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/model/wake_impact.hpp"

namespace {

template <template <int> class Method>
void protocol_point(benchmark::State& state)
{
    const vimpact::wake_impact model{};
    vimpact::protocol_options po;
    po.flow.integration.rtol = 1e-10;
    po.flow.integration.atol = 1e-10;
    const vimpact::vec<4> x0(0.0, 0.0, 0.0, 0.1);
    long steps = 0, rhs = 0;
    for (auto _ : state) {
        auto r = vimpact::run_protocol<Method>(model, x0, po);
        benchmark::DoNotOptimize(r.points.data());
        steps = r.stats.steps;
        rhs = r.stats.rhs_calls;
    }
    state.counters["steps"] = static_cast<double>(steps);
    state.counters["rhs_calls"] = static_cast<double>(rhs);
    state.counters["steps_per_s"] =
        benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(protocol_point<vimpact::dop853>)->Name("protocol_Ur16/dop853")->Unit(benchmark::kMillisecond)->Repetitions(7)->ReportAggregatesOnly(true);
BENCHMARK(protocol_point<vimpact::dopri5>)->Name("protocol_Ur16/dopri5")->Unit(benchmark::kMillisecond)->Repetitions(7)->ReportAggregatesOnly(true);

BENCHMARK_MAIN();
