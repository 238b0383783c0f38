// The job loop's throughput: jobs per second of the paper's protocol (a sweep over
// 12 <= Ur <= 25, sigma = -0.150298, 500 impacts discarded, 200 maxima kept) with 1 and 2
// threads. The ratio of the two medians is the parallel speed-up (goal: >= 1.85 on 2 cores).
#include <benchmark/benchmark.h>

#include "vimpact/analysis/sweep.hpp"
#include "vimpact/jobs/job_loop.hpp"
#include "vimpact/model/wake_impact.hpp"

namespace {

void sweep_jobs(benchmark::State& state)
{
    const int threads = static_cast<int>(state.range(0));
    constexpr long jobs = 64;
    const auto values = vimpact::grid_values(12.0, 25.0, jobs);
    const vimpact::wake_impact base{};
    const vimpact::vec<4> x0(0.0, 0.0, 0.0, 0.1);
    vimpact::job_loop_options opt;
    opt.threads = threads;
    for (auto _ : state) {
        long labelled = 0;
        vimpact::run_jobs<int>(
            vimpact::job_schedule{jobs, 0}, opt, {},
            [&](long j, const int*) {
                const auto m = base.with("Ur", values[static_cast<std::size_t>(j)]);
                return vimpact::run_and_classify(m, x0, vimpact::protocol_options{}, 1e-8).label.period;
            },
            [&](long, int&&) { ++labelled; });
        benchmark::DoNotOptimize(labelled);
    }
    state.SetItemsProcessed(state.iterations() * jobs);
}

}  // namespace

BENCHMARK(sweep_jobs)->Name("sweep_64_jobs/threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)
    ->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);

BENCHMARK_MAIN();
