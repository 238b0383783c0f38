// The Grassberger–Procaccia correlation sum (correlation_dimension.hpp): points per second at
// 10 000 and 50 000 points, for each pair search, and the whole estimate with its default
// pair budget. The points: a 3-D embedding of the Henon attractor (x, y, x + y), a fractal
// set like the sections of the paper's model.
//
// Two regimes: with a fixed cap r_max = 0.05 (about 1.7 % of the pairs closer, the part of
// C(r) a scaling region lives in) the pairs to count grow like N^2, so the time does too; the
// default estimate caps the count at 1e8 pairs, so above ~14 000 points its cost stops
// growing like N^2 and grows like the cost of finding 1e8 pairs. Time against N is in
// docs/dimension.md (exponent from the 10k and 50k rows).
#include <benchmark/benchmark.h>

#include "vimpact/analysis/correlation_dimension.hpp"

namespace {

vimpact::point_set henon3(std::size_t n)
{
    vimpact::point_set p(3);
    double x = 0.1, y = 0.1;
    for (std::size_t i = 0; i < n + 1000; ++i) {
        const double xn = 1.0 - 1.4 * x * x + y;
        y = 0.3 * x;
        x = xn;
        if (i >= 1000) p.push_back({x, y, x + y});
    }
    return p;
}

void correlation_sum_capped(benchmark::State& state, vimpact::pair_search search)
{
    const auto n = static_cast<std::size_t>(state.range(0));
    const auto ps = henon3(n);
    vimpact::correlation_sum_options o;
    o.search = search;
    o.r_max = 0.05;
    std::uint64_t pairs = 0;
    for (auto _ : state) {
        const auto c = vimpact::correlation_sum(ps, o);
        pairs = c.pairs.back();
        benchmark::DoNotOptimize(pairs);
    }
    state.counters["points_per_s"] = benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["pairs_per_s"] = benchmark::Counter(static_cast<double>(pairs), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["pairs_counted"] = static_cast<double>(pairs);
}

void whole_estimate(benchmark::State& state)
{
    const auto n = static_cast<std::size_t>(state.range(0));
    const auto ps = henon3(n);
    const vimpact::dimension_options o;  // grid search, 1e8 pair budget, automatic region
    double nu = 0.0;
    std::uint64_t pairs = 0;
    for (auto _ : state) {
        const auto r = vimpact::correlation_dimension(ps, o);
        nu = r.fit.dimension;
        pairs = r.curve.pairs.back();
    }
    state.counters["points_per_s"] = benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["pairs_counted"] = static_cast<double>(pairs);
    state.counters["dimension"] = nu;
}

}  // namespace

BENCHMARK_CAPTURE(correlation_sum_capped, grid, vimpact::pair_search::grid)
    ->Name("correlation_sum_r0.05/grid")->Arg(10000)->Arg(20000)->Arg(50000)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK_CAPTURE(correlation_sum_capped, kd_tree, vimpact::pair_search::kd_tree)
    ->Name("correlation_sum_r0.05/kd_tree")->Arg(10000)->Arg(20000)->Arg(50000)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK_CAPTURE(correlation_sum_capped, brute_force, vimpact::pair_search::brute_force)
    ->Name("correlation_sum_r0.05/brute_force")->Arg(10000)->Arg(50000)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(whole_estimate)->Name("dimension_default")->Arg(10000)->Arg(20000)->Arg(50000)->Unit(benchmark::kMillisecond)->MinTime(1.0);

BENCHMARK_MAIN();
