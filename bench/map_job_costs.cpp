// The cost of each job of a real map: the paper's map over Ur x sigma (paper preset, the full
// protocol: 500 impacts discarded, 200 maxima kept), each cell's protocol run and
// classification timed on its own (one job at a time per thread, --batch 1 work), with its
// deterministic work counters. Feeds the cost-per-job figure of docs/performance.md and the
// projection of distributed runs (a job's cost is its steps times the cost of a step).
//
// Usage: build/map_job_costs NX NY OUT.csv [THREADS] [UR_MIN UR_MAX SIGMA_MIN SIGMA_MAX]
//   (defaults: 2 threads, Ur 12..25, sigma -0.2..0)
// CSV: job,ix,iy,Ur,sigma,label,status,steps,rejected,rhs_calls,impacts,seconds,cpu_seconds
// (seconds: wall time of the job; cpu_seconds: its thread's CPU time, which a loaded machine
// does not inflate).
#include <time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <unordered_map>

#include "vimpact/analysis/map.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/jobs/job_loop.hpp"
#include "vimpact/model/model.hpp"

namespace {

struct job_cost {
    std::string label, status;
    long steps = 0, rejected = 0, rhs_calls = 0, impacts = 0;
    double seconds = 0.0, cpu_seconds = 0.0;
};

double thread_cpu_seconds()
{
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

int main(int argc, char** argv)
{
    if (argc < 4) {
        std::fprintf(stderr, "usage: %s NX NY OUT.csv [THREADS] [UR_MIN UR_MAX SIGMA_MIN SIGMA_MAX]\n", argv[0]);
        return 2;
    }
    const long nx = std::atol(argv[1]), ny = std::atol(argv[2]);
    const int threads = argc > 4 ? std::atoi(argv[4]) : 2;
    const double u0 = argc > 8 ? std::atof(argv[5]) : 12.0, u1 = argc > 8 ? std::atof(argv[6]) : 25.0;
    const double s0 = argc > 8 ? std::atof(argv[7]) : -0.2, s1 = argc > 8 ? std::atof(argv[8]) : 0.0;
    const vimpact::model m = vimpact::model::builtin("wake_impact");
    const int ur = m.info().parameter_index("Ur"), sigma = m.info().parameter_index("sigma");
    const auto us = vimpact::grid_values(u0, u1, nx), ss = vimpact::grid_values(s0, s1, ny);
    const vimpact::protocol_options po;
    vimpact::job_loop_options lo;
    lo.threads = threads;
    std::ofstream out(argv[3]);
    out << "job,ix,iy,Ur,sigma,label,status,steps,rejected,rhs_calls,impacts,seconds,cpu_seconds\n";
    const auto wall0 = std::chrono::steady_clock::now();
    const auto summary = vimpact::run_jobs<job_cost>(
        {nx * ny, 0}, lo, {},
        [&](long job, const job_cost*) {
            const auto t0 = std::chrono::steady_clock::now();
            const double c0 = thread_cpu_seconds();
            const vimpact::model mj = m.with_parameter(ur, us[static_cast<std::size_t>(job % nx)])
                                          .with_parameter(sigma, ss[static_cast<std::size_t>(job / nx)]);
            const auto r = vimpact::run_and_classify(mj, m.initial_state(), po, vimpact::default_period_tolerance);
            job_cost c{r.label.label, std::string(vimpact::to_string(r.run.status)), r.run.stats.steps,
                       r.run.stats.rejected, r.run.stats.rhs_calls, r.run.stats.impacts, 0.0, 0.0};
            c.cpu_seconds = thread_cpu_seconds() - c0;
            c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            return c;
        },
        [&](long job, job_cost&& c) {
            char line[512];
            std::snprintf(line, sizeof line, "%ld,%ld,%ld,%.17g,%.17g,%s,%s,%ld,%ld,%ld,%ld,%.6e,%.6e\n", job,
                          job % nx, job / nx, us[static_cast<std::size_t>(job % nx)],
                          ss[static_cast<std::size_t>(job / nx)], c.label.c_str(), c.status.c_str(), c.steps,
                          c.rejected, c.rhs_calls, c.impacts, c.seconds, c.cpu_seconds);
            out << line;
        });
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    std::printf("{\"jobs\": %ld, \"threads\": %d, \"wall_s\": %.3f}\n", summary.computed, summary.threads, wall);
    return 0;
}
