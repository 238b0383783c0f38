// Per-step time and heap allocations (malloc calls) of a 6-state model file,
// bench/models/two_oscillators.toml, on table_model<6> (fixed-size states) and on
// table_model<Eigen::Dynamic> (what the library runs for unlisted dimensions), both compiled
// here from the engine modules' definitions (src/engine_instances.ipp):
//   build/any_dimension_bench bench/models/two_oscillators.toml
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "engine_instances.ipp"
#include "vimpact/model/model.hpp"

// Every allocation of the process, the library's too: Eigen's and operator new's go through
// malloc.
static std::atomic<long> allocations{0};
extern "C" void* __libc_malloc(std::size_t);
extern "C" void* malloc(std::size_t n)
{
    ++allocations;
    return __libc_malloc(n);
}

using namespace vimpact;

template <class EM>
void run(const char* name, const EM& em, const Eigen::VectorXd& x0, const protocol_options& o, const floquet_options& fo,
         const model& m)
{
    double best = 1e9, best_f = 1e9;
    long steps = 0, impacts = 0, allocs = 0, fsteps = 0, fallocs = 0;
    for (int rep = 0; rep < 3; ++rep) {
        const long a0 = allocations;
        const auto t0 = std::chrono::steady_clock::now();
        const simulation s = detail::instance::run_simulate(em, x0, o);
        const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        steps = s.stats.steps;
        impacts = s.stats.impacts;
        allocs = allocations - a0;
        if (dt / static_cast<double>(steps) < best) best = dt / static_cast<double>(steps);
        const long a1 = allocations;
        const auto t1 = std::chrono::steady_clock::now();
        const floquet_result f = detail::instance::run_floquet(em, x0, fo, m.info());
        fallocs = allocations - a1;
        const double df = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
        fsteps = f.tangent_stats.steps;
        if (df < best_f) best_f = df;
    }
    std::printf("%-8s simulate: %ld steps, %ld impacts, %.1f ns/step, %.3f allocations/step (%ld); floquet: %.1f ms, %ld "
                "allocations (%ld tangent steps in its last map)\n",
                name, steps, impacts, best * 1e9, static_cast<double>(allocs) / static_cast<double>(steps), allocs, best_f * 1e3, fallocs, fsteps);
}

int main(int argc, char** argv)
{
    const model base = model::from_file(argc > 1 ? argv[1] : "bench/models/two_oscillators.toml");
    Eigen::VectorXd x0 = Eigen::VectorXd::Zero(6);
    x0[3] = 0.1;
    floquet_options fo;
    // Impacting (the stops at d = 1), and in free flight (stops at d = 100, never reached: the
    // run ends after quiet_time without an impact).
    for (const double d : {1.0, 100.0}) {
        model m = base.with_parameter(base.info().parameter_index("a1"), 1.01);
        m = m.with_parameter(m.info().parameter_index("d"), d);
        protocol_options o;
        o.transient_impacts = 4000;
        o.record_points = 400;
        o.quiet_time = 20000.0;
        std::printf("stops at d = %g\n", d);
        run("fixed", table_model<6>(m.table(), m.context()), x0, o, fo, m);
        run("dynamic", table_model<Eigen::Dynamic>(m.table(), m.context()), x0, o, fo, m);
    }
}
