// The job loop's throughput: jobs per second of the paper's protocol (a sweep over
// 12 <= Ur <= 25, sigma = -0.150298, 500 impacts discarded, 200 maxima kept, each point
// labelled) with 1 and 2 threads, through the library's sweep(): the call `vimpact sweep`
// makes, job loop included. The ratio of the two medians is the parallel speed-up (goal:
// >= 1.85 on 2 cores).
#include <benchmark/benchmark.h>

#include "vimpact/analysis/sweep.hpp"
#include "vimpact/model/model.hpp"

namespace {

void sweep_jobs(benchmark::State& state)
{
    constexpr long jobs = 64;
    const vimpact::model m = vimpact::model::builtin("wake_impact");
    vimpact::sweep_options so;
    so.parameter = m.info().parameter_index("Ur");
    so.values = vimpact::grid_values(12.0, 25.0, jobs);
    vimpact::job_options jo;
    jo.threads = static_cast<int>(state.range(0));
    for (auto _ : state) {
        const auto r = vimpact::sweep(m, so, jo);
        if (r.jobs.computed != jobs) state.SkipWithError("not every job ran");
        benchmark::DoNotOptimize(r.points.data());
    }
    state.SetItemsProcessed(state.iterations() * jobs);
}

}  // namespace

BENCHMARK(sweep_jobs)->Name("sweep_64_jobs/threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)
    ->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);

BENCHMARK_MAIN();
