// One bifurcation point of the paper's protocol (Ur = 16, sigma = -0.150298, paper preset,
// 500 impacts discarded, 200 maxima kept, rtol = atol = 1e-10), with each integrator, through
// the library's simulate() on the built-in model: the call every front end makes.
// Counters: steps per second and rhs calls. The peer baselines run in bench/run_benchmarks.sh.
#include <benchmark/benchmark.h>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/model/model.hpp"

namespace {

void protocol_point(benchmark::State& state, vimpact::integration_method method)
{
    vimpact::model m = vimpact::model::builtin("wake_impact");
    m = m.with_parameter(m.info().parameter_index("Ur"), 16.0);
    vimpact::protocol_options po;
    po.method = method;
    po.flow.integration.rtol = 1e-10;
    po.flow.integration.atol = 1e-10;
    const Eigen::VectorXd x0 = m.initial_state();
    vimpact::run_stats s;
    for (auto _ : state) {
        const auto r = vimpact::simulate(m, x0, po);
        benchmark::DoNotOptimize(r.points.values().data());
        s = r.stats;
    }
    state.counters["steps"] = static_cast<double>(s.steps);
    state.counters["rhs_calls"] = static_cast<double>(s.rhs_calls);
    state.counters["steps_per_s"] =
        benchmark::Counter(static_cast<double>(s.steps), benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK_CAPTURE(protocol_point, dop853, vimpact::integration_method::dop853)
    ->Name("protocol_Ur16/dop853")->Unit(benchmark::kMillisecond)->Repetitions(7)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(protocol_point, dopri5, vimpact::integration_method::dopri5)
    ->Name("protocol_Ur16/dopri5")->Unit(benchmark::kMillisecond)->Repetitions(7)->ReportAggregatesOnly(true);

BENCHMARK_MAIN();
