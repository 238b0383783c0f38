// The SIMD lanes against one job at a time, per instruction set: the protocol (500 impacts
// discarded, 200 maxima kept) of an n x n grid of the paper's model over Ur 12..25 x sigma
// -0.2..0, run by the library's engine templates compiled into this program (so that the
// same source, built for AVX-512 and for AVX2, measures each), first job by job, then in
// lanes (hybrid/flow_lanes.hpp). Checks that every job's section points agree bit for bit.
// Process CPU time (what a loaded machine does not inflate), one thread.
//
// Usage: build/lanes_bench [N]   (default 16)
// Built four times by bench/CMakeLists.txt: lanes_bench (the build's instruction set and lane
// width), lanes_bench_256 (256-bit lanes) and lanes_bench_512_split (512-bit lanes moved in
// 32-byte halves) where AVX-512 is available, and lanes_bench_avx2 (-march=haswell), all
// without fp contraction, as the library's built-ins; each names its build in the output.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <ctime>
#include <memory>
#include <vector>

#include "vimpact/analysis/sweep.hpp"
#include "vimpact/engine/protocol.hpp"
#include "vimpact/hybrid/flow_lanes.hpp"
#include "vimpact/integrate/runge_kutta.hpp"
#include "vimpact/model/builtin/wake_impact.hpp"
#include "vimpact/model/native_model.hpp"

#ifndef VIMPACT_BENCH_BUILD
#define VIMPACT_BENCH_BUILD "default"
#endif

using namespace vimpact;
using wake = native_model<wake_impact>;

int main(int argc, char** argv)
{
    const long n = argc > 1 ? std::atol(argv[1]) : 16;
    std::vector<std::vector<double>> params;
    std::vector<double> base;
    for (const auto& p : wake_impact::parameters) base.push_back(p.default_value);
    const auto us = grid_values(12.0, 25.0, n), ss = grid_values(-0.2, 0.0, n);
    for (long iy = 0; iy < n; ++iy)
        for (long ix = 0; ix < n; ++ix) {
            auto p = base;
            p[0] = us[static_cast<std::size_t>(ix)];
            p[1] = ss[static_cast<std::size_t>(iy)];
            params.push_back(p);
        }
    const protocol_options po;
    const vec<4> x0(wake_impact::initial_state.data());
    const auto jobs = static_cast<long>(params.size());

    std::vector<simulation> alone, together(static_cast<std::size_t>(jobs));
    const std::clock_t c0 = std::clock();
    for (long j = 0; j < jobs; ++j)
        alone.push_back(engine::run_protocol<dop853>(wake(params[static_cast<std::size_t>(j)]), x0, po));
    const std::clock_t c1 = std::clock();
    long given = 0;
    run_in_lanes<wake_impact, dop853>(
        lane_width, [&]() { return given < jobs ? std::optional<long>(given++) : std::nullopt; },
        [&](long j) {
            return std::make_unique<engine::protocol_run<dop853, wake>>(wake(params[static_cast<std::size_t>(j)]), x0, po);
        },
        [&](long j) { return std::span<const double>(params[static_cast<std::size_t>(j)]); },
        [&](long j, simulation&& s) { together[static_cast<std::size_t>(j)] = std::move(s); });
    const std::clock_t c2 = std::clock();

    long differ = 0, steps = 0;
    for (long j = 0; j < jobs; ++j) {
        const auto& a = alone[static_cast<std::size_t>(j)].points;
        const auto& b = together[static_cast<std::size_t>(j)].points;
        steps += alone[static_cast<std::size_t>(j)].stats.steps;
        bool same = a.size() == b.size();
        for (std::size_t k = 0; same && k < a.size(); ++k) {
            const double ta = a.t(k), tb = b.t(k);
            same = std::memcmp(&ta, &tb, sizeof ta) == 0;
            for (int i = 0; same && i < 4; ++i) {
                const double u = a.x(k)[i], v = b.x(k)[i];
                same = std::memcmp(&u, &v, sizeof u) == 0;
            }
        }
        differ += same ? 0 : 1;
    }
    const double scalar = static_cast<double>(c1 - c0) / CLOCKS_PER_SEC, lanes_s = static_cast<double>(c2 - c1) / CLOCKS_PER_SEC;
    std::printf("{\"build\": \"%s\", \"isa_lanes\": %d, \"jobs\": %ld, \"steps\": %ld, \"scalar_cpu_s\": %.3f, \"lanes_cpu_s\": %.3f, "
                "\"speedup\": %.2f, \"jobs_differing\": %ld}\n",
                VIMPACT_BENCH_BUILD, lane_width, jobs, steps, scalar, lanes_s, scalar / lanes_s, differ);
    return differ == 0 ? 0 : 1;
}
