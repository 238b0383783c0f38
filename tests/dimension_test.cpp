// Tests of the correlation dimension (correlation_dimension.hpp, dimension_points.hpp):
//  - the three pair searches (cell grid, nanoflann k-d tree, brute force) give identical
//    counts, which equal a count taken straight from the definition;
//  - the Theiler window excludes exactly the pairs at most w apart in time;
//  - the paper's centre counts equal a direct count;
//  - sets of known dimension: a line (1), a filled square (2), the Henon attractor (1.21),
//    the middle-thirds Cantor set (log 2 / log 3), and the paper's model on a period-2 orbit
//    (a finite set: 0);
//  - the scaling-region rule and its override, the point-file reader, and the coordinates of
//    a model's recorded states (phases as cos/sin pairs).
//
// Tolerances. For the line and the square C(r) is known in closed form, so the estimate is
// compared with the slope of the exact curve over the same radii; what is left is sampling
// noise. The counted pairs P(r) are, to leading order, a cumulative Poisson count in r
// (Grassberger 1988; Theiler 1990): Cov(P(r_k), P(r_l)) = P(r_min(k,l)), so
// Cov(ln P_k, ln P_l) = 1 / P_max(k,l), and the least-squares slope with weights
// w_k = (ln r_k - mean) / S_xx has variance sum_kl w_k w_l / P_max(k,l) (sampling_sd()).
// The other part of the U-statistic variance, 4 Var(c(X)) / (N C^2) with c(x) the mass
// within r of x, is left out for these homogeneous sets: c(x) = C(r) except within r of the
// boundary, which makes it below 1e-5 over the fitted radii, and a part that does not depend
// on r does not move a slope at all. The tests allow three standard deviations; the long
// test checks the scatter over 20 seeds against it. For the paper's centre counts the same
// formula is exact given the centres (the other points are independent).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "test_support.hpp"
#include "vimpact/analysis/correlation_dimension.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/input_error.hpp"

namespace {

using vimpact::correlation_curve;
using vimpact::dimension_options;
using vimpact::pair_search;
using vimpact::point_set;

constexpr double inf = std::numeric_limits<double>::infinity();

// Raw 64-bit outputs of mt19937_64 are fixed by the standard (its distributions are not):
// the same points on every platform.
double uniform01(std::mt19937_64& g) { return static_cast<double>(g() >> 11) * 0x1p-53; }

// Uniform on the segment u (1, 2, -1), u in [0, 1]: length sqrt(6), embedded in 3-D.
point_set line_points(std::size_t n, std::uint64_t seed)
{
    std::mt19937_64 g(seed);
    point_set p(3);
    for (std::size_t i = 0; i < n; ++i) {
        const double u = uniform01(g);
        p.push_back({u, 2.0 * u, -u});
    }
    return p;
}

point_set square_points(std::size_t n, std::uint64_t seed)
{
    std::mt19937_64 g(seed);
    point_set p(2);
    for (std::size_t i = 0; i < n; ++i) {
        const double a = uniform01(g);
        p.push_back({a, uniform01(g)});
    }
    return p;
}

point_set cube_points(std::size_t n, std::uint64_t seed, int dim = 3)
{
    std::mt19937_64 g(seed);
    point_set p(dim);
    std::vector<double> x(static_cast<std::size_t>(dim));
    for (std::size_t i = 0; i < n; ++i) {
        for (auto& v : x) v = uniform01(g);
        p.push_back(x.data());
    }
    return p;
}

// The Henon map (a = 1.4, b = 0.3) after 1000 discarded iterates: time-ordered points.
point_set henon_points(std::size_t n)
{
    point_set p(2);
    double x = 0.1, y = 0.1;
    for (std::size_t i = 0; i < n + 1000; ++i) {
        const double xn = 1.0 - 1.4 * x * x + y;
        y = 0.3 * x;
        x = xn;
        if (i >= 1000) p.push_back({x, y});
    }
    return p;
}

// The natural measure of the middle-thirds Cantor set: ternary digits 0 or 2 at random,
// 34 digits (3^-34 ~ 6e-17, below the resolution of a double near 1).
point_set cantor_points(std::size_t n, std::uint64_t seed)
{
    std::mt19937_64 g(seed);
    point_set p(1);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint64_t bits = g();
        double x = 0.0, scale = 1.0;
        for (int k = 0; k < 34; ++k) {
            scale /= 3.0;
            if ((bits >> k) & 1u) x += 2.0 * scale;
        }
        p.push_back({x});
    }
    return p;
}

// Exact slope of ln C vs ln r, by least squares over the fitted radii of `res`, for a
// closed-form C(r).
template <class F>
double exact_slope(const vimpact::dimension_result& res, F&& c_exact)
{
    double mx = 0, my = 0, sxx = 0, sxy = 0;
    const auto m = static_cast<double>(res.fit.fitted);
    for (std::size_t k = res.fit.first; k <= res.fit.last; ++k) {
        mx += std::log(res.curve.r[k]);
        my += std::log(c_exact(res.curve.r[k]));
    }
    mx /= m;
    my /= m;
    for (std::size_t k = res.fit.first; k <= res.fit.last; ++k) {
        const double x = std::log(res.curve.r[k]) - mx;
        sxx += x * x;
        sxy += x * (std::log(c_exact(res.curve.r[k])) - my);
    }
    return sxy / sxx;
}

// Standard deviation of the fitted slope from the counting noise (see the top of the file).
double sampling_sd(const vimpact::dimension_result& res)
{
    const std::size_t a = res.fit.first, b = res.fit.last;
    double mean = 0.0;
    for (std::size_t k = a; k <= b; ++k) mean += std::log(res.curve.r[k]);
    mean /= static_cast<double>(b - a + 1);
    double sxx = 0.0;
    for (std::size_t k = a; k <= b; ++k) sxx += (std::log(res.curve.r[k]) - mean) * (std::log(res.curve.r[k]) - mean);
    double var = 0.0;
    for (std::size_t k = a; k <= b; ++k)
        for (std::size_t l = a; l <= b; ++l) {
            const double wk = (std::log(res.curve.r[k]) - mean) / sxx;
            const double wl = (std::log(res.curve.r[l]) - mean) / sxx;
            var += wk * wl / static_cast<double>(res.curve.pairs[std::max(k, l)]);
        }
    return std::sqrt(var);
}

// Closed forms: uniform on a segment of length L = sqrt(6) (line_points), C = 2 r / L - (r / L)^2;
// uniform on the unit square, C = pi r^2 - 8 r^3 / 3 + r^4 / 2 (r <= 1).
double exact_line(double r)
{
    const double L = std::sqrt(6.0);
    return 2.0 * r / L - (r / L) * (r / L);
}
double exact_square(double r) { return std::numbers::pi * r * r - 8.0 * r * r * r / 3.0 + r * r * r * r / 2.0; }

vimpact::dimension_result estimate(const point_set& ps, dimension_options o = {})
{
    return vimpact::correlation_dimension(ps, o);
}

correlation_curve sum_with(const point_set& ps, pair_search s, long w = 0, double r_max = inf, int threads = 1)
{
    vimpact::correlation_sum_options o;
    o.search = s;
    o.theiler_window = w;
    o.r_max = r_max;
    o.threads = threads;
    return vimpact::correlation_sum(ps, o);
}

}  // namespace

// ---- exact counts -------------------------------------------------------------------------

// The grid and the k-d tree find exactly the pairs brute force finds, bin for bin, with and
// without a cap and a Theiler window, in 1 to 5 dimensions, with several threads.
TEST(CorrelationSum, GridAndKdTreeCountsEqualBruteForceExactly)
{
    for (int dim : {1, 2, 3, 5}) {
        const point_set ps = cube_points(1500, 11 + static_cast<std::uint64_t>(dim), dim);
        for (long w : {0L, 7L})
            // The smallest cap still holds pairs in 5-D (typical neighbour distance ~0.1).
            for (double r_max : {inf, 0.3, dim < 5 ? 0.02 : 0.15}) {
                const auto ref = sum_with(ps, pair_search::brute_force, w, r_max);
                const auto grid = sum_with(ps, pair_search::grid, w, r_max);
                const auto tree = sum_with(ps, pair_search::kd_tree, w, r_max);
                const auto grid2 = sum_with(ps, pair_search::grid, w, r_max, 3);
                SCOPED_TRACE("dim " + std::to_string(dim) + " w " + std::to_string(w) + " r_max " + std::to_string(r_max));
                ASSERT_EQ(ref.r, grid.r);
                ASSERT_EQ(ref.r, tree.r);
                EXPECT_EQ(ref.pairs, grid.pairs);
                EXPECT_EQ(ref.pairs, tree.pairs);
                EXPECT_EQ(ref.pairs, grid2.pairs);
                EXPECT_EQ(ref.total_pairs, vimpact::detail::eligible_pairs(ps.size(), w));
                EXPECT_GT(ref.pairs.back(), 0u);
            }
    }
}

// Clustered data with a huge spread of scales (many cells, most empty, points far apart
// and duplicates): still identical.
TEST(CorrelationSum, ClusteredDataAndDuplicatesCountedExactly)
{
    std::mt19937_64 g(5);
    point_set ps(3);
    for (int i = 0; i < 2000; ++i) {
        const double cx = static_cast<double>(i % 7) * 1e3;
        ps.push_back({cx + 1e-6 * uniform01(g), 1e-3 * uniform01(g), uniform01(g) * 1e-9});
    }
    for (int i = 0; i < 50; ++i) ps.push_back(ps.point(static_cast<std::size_t>(i)));  // exact duplicates
    for (double r_max : {inf, 1e-3, 1e-7}) {
        const auto ref = sum_with(ps, pair_search::brute_force, 0, r_max);
        EXPECT_EQ(ref.pairs, sum_with(ps, pair_search::grid, 0, r_max).pairs);
        EXPECT_EQ(ref.pairs, sum_with(ps, pair_search::kd_tree, 0, r_max).pairs);
    }
    // The 50 duplicate pairs are closer than any positive radius.
    const auto c = sum_with(ps, pair_search::grid);
    EXPECT_GE(c.pairs.front(), 50u);
}

// The counts are those of the definition: pairs with |x_i - x_j| < r at every radius
// reported (random data: no distance falls on a radius).
TEST(CorrelationSum, CountsMatchTheDefinition)
{
    const point_set ps = cube_points(600, 3);
    const auto c = sum_with(ps, pair_search::grid);
    ASSERT_GT(c.size(), 100u);
    for (std::size_t k = c.size() - 100; k < c.size(); k += 9) {
        std::uint64_t count = 0;
        for (std::size_t i = 0; i < ps.size(); ++i)
            for (std::size_t j = i + 1; j < ps.size(); ++j)
                count += std::sqrt(vimpact::squared_distance(ps.point(i), ps.point(j), 3)) < c.r[k];
        EXPECT_EQ(c.pairs[k], count) << "r = " << c.r[k];
    }
    EXPECT_EQ(c.pairs.back(), c.total_pairs);  // the last radius is above the diameter
    for (std::size_t k = 1; k < c.size(); ++k) {
        EXPECT_GT(c.r[k], c.r[k - 1]);
        EXPECT_GE(c.pairs[k], c.pairs[k - 1]);
    }
    // 16 radii per factor 2 (the default).
    EXPECT_NEAR(std::log2(c.r[c.size() - 1] / c.r[c.size() - 17]), 1.0, 1e-12);
}

// Points x_i = i on a line, in time order: pairs (i, j) are at distance |i - j| exactly.
// With Theiler window w, the pairs closer than r are those with w < |i - j| < r, so
// pairs(r) = sum over gaps g = w+1 .. ceil(r)-1 of (n - g). The gaps <= w are excluded and
// nothing else.
TEST(CorrelationSum, TheilerWindowExcludesExactlyThePairsCloseInTime)
{
    const std::size_t n = 400;
    point_set ps(1);
    for (std::size_t i = 0; i < n; ++i) ps.push_back({static_cast<double>(i)});
    for (long w : {0L, 1L, 5L, 30L}) {
        for (pair_search s : {pair_search::grid, pair_search::kd_tree, pair_search::brute_force}) {
            const auto c = sum_with(ps, s, w);
            EXPECT_EQ(c.total_pairs, (n - static_cast<std::size_t>(w) - 1) * (n - static_cast<std::size_t>(w)) / 2);
            for (std::size_t k = 0; k < c.size(); ++k) {
                std::uint64_t expect = 0;
                for (std::size_t gap = static_cast<std::size_t>(w) + 1; gap < n && static_cast<double>(gap) < c.r[k]; ++gap)
                    expect += n - gap;
                ASSERT_EQ(c.pairs[k], expect) << "w " << w << " r " << c.r[k] << " " << to_string(s);
            }
        }
    }
    EXPECT_THROW(sum_with(ps, pair_search::grid, static_cast<long>(n) - 1), vimpact::input_error);
    EXPECT_THROW(sum_with(ps, pair_search::grid, -1), vimpact::input_error);
}

// ---- the paper's centre counts ----------------------------------------------------------

TEST(CentreCounts, CentresAreEvenlySpacedAndCountsAreDirect)
{
    EXPECT_EQ(vimpact::centre_indices(100, 4), (std::vector<std::size_t>{12, 37, 62, 87}));
    EXPECT_EQ(vimpact::centre_indices(15, 15).back(), 14u);
    const point_set ps = cube_points(3000, 9);
    vimpact::centre_count_options o;
    o.centres = 15;
    o.r_min = 0.01;
    o.r_max = 0.5;
    o.r_step = 0.01;
    o.theiler_window = 3;
    std::vector<std::size_t> centres;
    const auto c = vimpact::centre_counts(ps, o, &centres);
    ASSERT_EQ(c.size(), 50u);
    EXPECT_NEAR(c.r.back(), 0.5, 1e-15);
    EXPECT_EQ(c.total_pairs, 15u * (3000u - 7u));  // each centre: all but itself and 3 either side
    for (std::size_t m = 0; m < c.size(); m += 7) {
        std::uint64_t count = 0;
        for (auto k : centres)
            for (std::size_t j = 0; j < ps.size(); ++j) {
                const std::size_t gap = j > k ? j - k : k - j;
                count += gap > 3 && std::sqrt(vimpact::squared_distance(ps.point(k), ps.point(j), 3)) < c.r[m];
            }
        EXPECT_EQ(c.pairs[m], count);
    }
}

// The one Theiler window a user sets reaches both estimators: the whole estimate's totals are
// the eligible pairs counted by hand (all pairs farther apart than w rows; per centre, all
// points but those within w rows of it).
TEST(CorrelationDimension, TheilerWindowReachesBothEstimators)
{
    const point_set ps = cube_points(600, 5);
    const std::uint64_t n = 600, w = 7;
    vimpact::dimension_options o;
    o.theiler_window = static_cast<long>(w);
    o.scaling.min_pairs = 1;
    EXPECT_EQ(vimpact::correlation_dimension(ps, o).curve.total_pairs, (n - w - 1) * (n - w) / 2);
    o.estimator = vimpact::dimension_estimator::centres;
    o.centre.centres = 4;
    const auto res = vimpact::correlation_dimension(ps, o);
    std::uint64_t eligible = 0;
    for (const auto k : res.centres) eligible += n - 1 - std::min<std::uint64_t>(k, w) - std::min<std::uint64_t>(n - 1 - k, w);
    EXPECT_EQ(res.curve.total_pairs, eligible);
}

// The paper's estimator on a filled square whose centres (by index) lie in the interior,
// at least 0.06 (the largest radius) from the edges: each centre's neighbourhood is a whole
// disc, E N(r) = (N - 1) pi r^2, and the dimension is 2 up to the Poisson noise of the
// summed counts (sampling_sd, top of the file).
TEST(CentreCounts, PaperVariantOnASquareGivesTwo)
{
    const std::size_t n = 50000;
    point_set raw = square_points(n, 21);
    const auto centres = vimpact::centre_indices(n, 15);
    // Swap an interior point into each centre slot.
    std::vector<std::size_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = i;
    std::size_t next = 0;
    for (auto c : centres) {
        while (!(raw.coordinate(next, 0) > 0.07 && raw.coordinate(next, 0) < 0.93 && raw.coordinate(next, 1) > 0.07 &&
                 raw.coordinate(next, 1) < 0.93))
            ++next;
        std::swap(order[c], order[next++]);
    }
    point_set ps(2);
    for (auto i : order) ps.push_back(raw.point(i));
    dimension_options o;
    o.estimator = vimpact::dimension_estimator::centres;  // the paper's 15 centres, radii 1e-4..0.06
    const auto res = estimate(ps, o);
    ASSERT_TRUE(res.fit.found);
    const double sd = sampling_sd(res);
    std::printf("centres on a square: nu = %.4f, sampling sd %.4f, fit %.3g .. %.3g\n", res.fit.dimension, sd,
                res.fit.r_min, res.fit.r_max);
    EXPECT_NEAR(res.fit.dimension, 2.0, 3.0 * sd) << "fit " << res.fit.r_min << " .. " << res.fit.r_max;
    EXPECT_LT(3.0 * sd, 0.12);  // the test can tell 2 from the 1.5 or 2.5 of a broken count
}

// ---- sets of known dimension ----------------------------------------------------------------

// Uniform on a segment: C(r) known exactly (exact_line).
TEST(CorrelationDimension, LineIsOne)
{
    const auto res = estimate(line_points(10000, 1));
    ASSERT_TRUE(res.fit.found);
    const double theory = exact_slope(res, exact_line);
    std::printf("line: nu = %.4f, exact-curve slope %.4f, sampling sd %.4f, fit %.3g .. %.3g\n", res.fit.dimension,
                theory, sampling_sd(res), res.fit.r_min, res.fit.r_max);
    EXPECT_NEAR(res.fit.dimension, theory, 3.0 * sampling_sd(res));
    EXPECT_NEAR(theory, 1.0, 0.02);  // the rule stops before the saturation bend costs more
    EXPECT_NEAR(res.fit.dimension, 1.0, 0.03);
    EXPECT_GT(res.fit.r_max / res.fit.r_min, 1e3);
}

// Uniform on the unit square: C(r) known exactly (exact_square).
TEST(CorrelationDimension, FilledSquareIsTwo)
{
    const auto res = estimate(square_points(10000, 2));
    ASSERT_TRUE(res.fit.found);
    ASSERT_LE(res.fit.r_max, 1.0);
    const double theory = exact_slope(res, exact_square);
    std::printf("square: nu = %.4f, exact-curve slope %.4f, sampling sd %.4f, fit %.3g .. %.3g\n", res.fit.dimension,
                theory, sampling_sd(res), res.fit.r_min, res.fit.r_max);
    EXPECT_NEAR(res.fit.dimension, theory, 3.0 * sampling_sd(res));
    EXPECT_NEAR(theory, 2.0, 0.05);
    EXPECT_NEAR(res.fit.dimension, 2.0, 0.06);
}

// Henon attractor: nu = 1.21 +- 0.01 (Grassberger & Procaccia 1983, Physica D 9, 189), 1.22
// in later work. Its scaling is not exactly a power law (nu varies slightly with the range),
// so the band is the literature value +- 0.03, about three times the sampling bound.
TEST(CorrelationDimension, HenonAttractorIsAbout121)
{
    const auto res = estimate(henon_points(10000));
    ASSERT_TRUE(res.fit.found);
    std::printf("henon: nu = %.4f, sampling sd %.4f, fit %.3g .. %.3g\n", res.fit.dimension, sampling_sd(res),
                res.fit.r_min, res.fit.r_max);
    EXPECT_LT(sampling_sd(res), 0.01);
    EXPECT_NEAR(res.fit.dimension, 1.215, 0.035) << "fit " << res.fit.r_min << " .. " << res.fit.r_max;
    // Time-ordered data: a Theiler window of 10 steps changes nothing material for a map this
    // chaotic (consecutive points are not close).
    dimension_options o;
    o.theiler_window = 10;
    EXPECT_NEAR(estimate(henon_points(10000), o).fit.dimension, res.fit.dimension, 0.02);
}

// Middle-thirds Cantor set: log 2 / log 3 = 0.6309. C(r) has a log-periodic wiggle of period
// ln 3 (lacunarity); the local slope window (a factor 4 > 3) and a fit over many periods
// average it, so the sampling bound plus 0.01 for the leftover of a partial period.
TEST(CorrelationDimension, CantorSetIsLog2OverLog3)
{
    const auto res = estimate(cantor_points(10000, 3));
    ASSERT_TRUE(res.fit.found);
    std::printf("cantor: nu = %.4f (log2/log3 = %.4f), sampling sd %.4f, fit %.3g .. %.3g\n", res.fit.dimension,
                std::log(2.0) / std::log(3.0), sampling_sd(res), res.fit.r_min, res.fit.r_max);
    EXPECT_GT(std::log(res.fit.r_max / res.fit.r_min) / std::log(3.0), 5.0);  // several periods
    EXPECT_NEAR(res.fit.dimension, std::log(2.0) / std::log(3.0), 3.0 * sampling_sd(res) + 0.01);
}

// The three searches give the same dimension (identical counts) on a chaotic set.
TEST(CorrelationDimension, SearchMethodDoesNotChangeTheResult)
{
    const point_set ps = henon_points(4000);
    dimension_options o;
    const auto a = estimate(ps, o);
    o.correlation.search = pair_search::kd_tree;
    const auto b = estimate(ps, o);
    EXPECT_EQ(a.curve.pairs, b.curve.pairs);
    EXPECT_EQ(a.fit.dimension, b.fit.dimension);
}

// The pair budget caps r_max: fewer pairs are counted, C below the cap is unchanged.
TEST(CorrelationDimension, PairBudgetCapsTheRadiusNotTheCounts)
{
    const point_set ps = henon_points(6000);
    dimension_options all;
    all.max_pairs = 1'000'000'000;
    dimension_options capped;
    capped.max_pairs = 1'000'000;
    const auto a = estimate(ps, all);
    const auto b = estimate(ps, capped);
    EXPECT_TRUE(a.all_pairs);
    EXPECT_FALSE(b.all_pairs);
    EXPECT_LT(b.curve.pairs.back(), 3'000'000u);
    EXPECT_GT(b.curve.pairs.back(), 300'000u);
    // Same bins (same edges) where both exist: identical counts.
    std::size_t matched = 0;
    for (std::size_t k = 0; k < b.curve.size(); ++k)
        for (std::size_t m = 0; m < a.curve.size(); ++m)
            if (a.curve.r[m] == b.curve.r[k] && k + 1 < b.curve.size()) {
                EXPECT_EQ(a.curve.pairs[m], b.curve.pairs[k]);
                ++matched;
            }
    EXPECT_GT(matched, 100u);
    EXPECT_NEAR(a.fit.dimension, b.fit.dimension, 0.05);
}

// The paper's model on its period-2 orbit (Ur = 16, the paper's Figure 2e): the section points are two
// points repeated (to the integration accuracy), C(r) = 1/2 from the accuracy up to the
// distance between them, and the dimension is 0.
TEST(CorrelationDimension, PaperModelPeriodicOrbitIsZero)
{
    const vimpact::model model = vimpact::test::paper(16.0);
    vimpact::protocol_options po;
    po.record_points = 2000;
    const auto run = vimpact::simulate(model, vimpact::test::paper_ic(), po);
    ASSERT_EQ(run.status, vimpact::outcome::ok);
    ASSERT_EQ(vimpact::classify_period(model, run, 1e-8).label, "P2");
    // Every state column; ydot is 0 on the section and adds nothing to a distance.
    const auto table = vimpact::state_point_table(model.info(), run.points);
    EXPECT_EQ(table.header, (std::vector<std::string>{"y", "ydot", "x", "xdot"}));
    const point_set ps = vimpact::make_point_set(table, vimpact::select_columns(table.header, "", "the run"));
    ASSERT_EQ(ps.size(), 2000u);
    const auto res = estimate(ps);
    ASSERT_TRUE(std::isfinite(res.fit.dimension));
    std::printf("paper model, Ur = 16 (P2): nu = %.2g, C = %.4f over the fit %.3g .. %.3g\n", res.fit.dimension,
                res.curve.c(res.fit.last), res.fit.r_min, res.fit.r_max);
    EXPECT_NEAR(res.fit.dimension, 0.0, 0.02);
    EXPECT_NEAR(res.curve.c(res.fit.last), 0.5, 0.01);
    EXPECT_GT(res.fit.r_max / res.fit.r_min, 100.0);
    // The same points without the constant column: the same counts.
    const auto yxw = estimate(vimpact::make_point_set(table, vimpact::select_columns(table.header, "y,x,xdot", "the run")));
    EXPECT_EQ(yxw.curve.pairs, res.curve.pairs);
}

// A phase becomes a (cos, sin) pair scaled by period / 2 pi: states a period apart are the
// same point, and a small phase difference keeps its size.
TEST(StatePointTable, PhasesAreCosSinPairs)
{
    const vimpact::model m = vimpact::model::builtin("two_sided_impact_oscillator");
    vimpact::state_series s(3);
    s.push_back(0.0, Eigen::Vector3d(0.5, -0.25, 0.3));
    s.push_back(1.0, Eigen::Vector3d(0.5, -0.25, 0.3 + 4.0 * std::numbers::pi));
    s.push_back(2.0, Eigen::Vector3d(0.5, -0.25, 0.3 + 1e-6));
    const auto t = vimpact::state_point_table(m.info(), s);
    EXPECT_EQ(t.header, (std::vector<std::string>{"x", "v", "phi_cos", "phi_sin"}));
    ASSERT_EQ(t.columns.size(), 4u);
    EXPECT_EQ(t.columns[0], (std::vector<double>{0.5, 0.5, 0.5}));
    EXPECT_EQ(t.columns[2][0], std::cos(0.3));
    EXPECT_EQ(t.columns[3][0], std::sin(0.3));
    const point_set ps = vimpact::make_point_set(t, {0, 1, 2, 3});
    EXPECT_LT(std::sqrt(vimpact::squared_distance(ps.point(0), ps.point(1), 4)), 1e-14);
    EXPECT_NEAR(std::sqrt(vimpact::squared_distance(ps.point(0), ps.point(2), 4)), 1e-6, 1e-12);
}

// Options no point set can satisfy are refused before any points exist.
TEST(CorrelationDimension, OptionsAreValidatedWithoutPoints)
{
    dimension_options o;
    EXPECT_NO_THROW(vimpact::validate(o));
    o.correlation.bins_per_octave = 12;
    EXPECT_THROW(vimpact::validate(o), vimpact::input_error);
    o = {};
    o.scaling.slope_tolerance = 0.0;
    EXPECT_THROW(vimpact::validate(o), vimpact::input_error);
    o = {};
    o.estimator = vimpact::dimension_estimator::centres;
    o.centre.r_min = 0.0;
    EXPECT_THROW(vimpact::validate(o), vimpact::input_error);
}

// ---- the scaling-region rule -------------------------------------------------------------

namespace {

// A synthetic curve with C(1) = 0.4: slope d2 above r_break, d1 below it; radii 16 per
// octave from 1e-8 to 1.
correlation_curve broken_power_law(double d1, double d2, double r_break, std::uint64_t total = 1'000'000'000'000)
{
    correlation_curve c;
    c.total_pairs = total;
    for (double lr = std::log(1e-8); lr <= 1e-12; lr += std::log(2.0) / 16.0) {
        const double r = std::exp(lr);
        const double lc = std::log(0.4) + (r >= r_break ? d2 * lr : d2 * std::log(r_break) + d1 * std::log(r / r_break));
        c.r.push_back(r);
        c.pairs.push_back(static_cast<std::uint64_t>(std::exp(lc) * static_cast<double>(total)));
    }
    return c;
}

}  // namespace

// The longest constant-slope range wins; the floor and the saturation cut are applied.
TEST(ScalingRegion, LongestConstantSlopeRangeWins)
{
    {
        const auto c = broken_power_law(2.0, 0.7, 1e-5);  // 2 over 3 decades, 0.7 over 5
        const auto f = vimpact::fit_scaling_region(c, {});
        EXPECT_TRUE(f.found);
        EXPECT_NEAR(f.dimension, 0.7, 0.01);
        EXPECT_GT(f.r_min, 1e-5);
    }
    {
        const auto c = broken_power_law(2.0, 0.7, 1e-2);  // 2 over 6 decades, 0.7 over 2
        const auto f = vimpact::fit_scaling_region(c, {});
        EXPECT_NEAR(f.dimension, 2.0, 0.01);
        EXPECT_LT(f.r_max, 1e-2);
    }
    {
        // Saturation: C = 0.8 beyond 1e-3, a slope-0 plateau over three decades (longer
        // than the two decades of slope 1.5 above the floor) that must not be fitted.
        correlation_curve c = broken_power_law(1.5, 0.0, 1e-3);
        for (auto& p : c.pairs) p = std::min<std::uint64_t>(p * 2, c.total_pairs);
        const auto f = vimpact::fit_scaling_region(c, {});
        EXPECT_NEAR(f.dimension, 1.5, 0.01);
        EXPECT_LE(f.r_max, 1e-3);
    }
    {
        // Counting floor: below 100 pairs nothing is used.
        const auto c = broken_power_law(1.0, 1.0, 1.0, 1'000'000);
        const auto f = vimpact::fit_scaling_region(c, {});
        EXPECT_GE(c.pairs[f.first], 100u);
        EXPECT_LT(c.pairs[f.first - 1], 100u);
    }
}

// No range of the minimum extent has constant slope: the least bad one is fitted and the
// result says so.
TEST(ScalingRegion, NoConstantRangeIsReportedNotHidden)
{
    // Local slope 2 + 0.2 ln r on r in [1e-4, 1]: it changes by 0.28 over the minimum
    // extent (a factor 4), more than the 2 * 0.1 allowed.
    correlation_curve c;
    c.total_pairs = 1'000'000'000'000;
    for (double lr = std::log(1e-4); lr <= 1e-12; lr += std::log(2.0) / 16.0) {
        c.r.push_back(std::exp(lr));
        c.pairs.push_back(static_cast<std::uint64_t>(0.4 * std::exp(2.0 * lr + 0.1 * lr * lr) * 1e12));
    }
    const auto f = vimpact::fit_scaling_region(c, {});
    EXPECT_FALSE(f.found);
    EXPECT_TRUE(std::isfinite(f.dimension));
    EXPECT_GT(f.slope_spread, 0.2);
}

TEST(ScalingRegion, UserRangeOverridesAndIsChecked)
{
    const auto c = broken_power_law(2.0, 0.7, 1e-5);
    vimpact::scaling_options o;
    o.fit_range = {{1e-7, 1e-6}};
    const auto f = vimpact::fit_scaling_region(c, o);
    EXPECT_FALSE(f.automatic);
    EXPECT_NEAR(f.dimension, 2.0, 0.01);
    EXPECT_GE(f.r_min, 1e-7);
    EXPECT_LE(f.r_max, 1e-6);
    o.fit_range = {{1e-3, 1e-4}};
    EXPECT_THROW(vimpact::fit_scaling_region(c, o), vimpact::input_error);
    o.fit_range = {{10.0, 20.0}};  // beyond every radius
    try {
        (void)vimpact::fit_scaling_region(c, o);
        ADD_FAILURE() << "no error";
    } catch (const vimpact::input_error& e) {
        EXPECT_NE(std::string(e.what()).find("span"), std::string::npos) << e.what();
    }
}

// ---- point files ------------------------------------------------------------------------

TEST(PointFiles, ReadSelectAndReject)
{
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("vimpact_dimension_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path good = dir / "good.csv";
    std::ofstream(good) << "t,y,ydot,x,xdot\n0,1,2,3,4\n1,5,6,7,8\n\n2,9,10,11,12e-1\n";
    const auto t = vimpact::read_point_table(good);
    ASSERT_EQ(t.header.size(), 5u);
    EXPECT_EQ(t.columns[4][2], 1.2);
    auto all = vimpact::select_columns(t.header, "", "f");  // every column but t
    EXPECT_EQ(all, (std::vector<std::size_t>{1, 2, 3, 4}));
    auto yx = vimpact::select_columns(t.header, "x,y", "f");
    EXPECT_EQ(yx, (std::vector<std::size_t>{3, 1}));
    const auto ps = vimpact::make_point_set(t, yx);
    EXPECT_EQ(ps.dim(), 2);
    EXPECT_EQ(ps.size(), 3u);
    EXPECT_EQ(ps.coordinate(1, 0), 7.0);
    EXPECT_EQ(ps.coordinate(1, 1), 5.0);

    auto message = [](auto&& f) {
        try {
            f();
        } catch (const vimpact::input_error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(message([&] { vimpact::select_columns(t.header, "y,speed", "f"); }).find("speed"), std::string::npos);
    EXPECT_NE(message([&] { vimpact::select_columns(t.header, "y,speed", "f"); }).find("t, y, ydot, x, xdot"),
              std::string::npos);
    EXPECT_NE(message([&] { vimpact::read_point_table(dir / "missing.csv"); }).find("missing.csv"), std::string::npos);
    const fs::path bad = dir / "bad.csv";
    std::ofstream(bad) << "a,b\n1,2\n3,x\n";
    EXPECT_NE(message([&] { vimpact::read_point_table(bad); }).find("line 3, column 'b'"), std::string::npos);
    std::ofstream(bad) << "a,b\n1,2\n3\n";
    EXPECT_NE(message([&] { vimpact::read_point_table(bad); }).find("line 3"), std::string::npos);
    std::ofstream(bad) << "a,b\n1,nan\n";
    EXPECT_NE(message([&] { vimpact::read_point_table(bad); }).find("finite"), std::string::npos);
    fs::remove_all(dir);
}

// ---- long checks (VIMPACT_LONG_TESTS=1) --------------------------------------------------

// The sampling standard deviation used above describes the real scatter: over 20 seeds the
// deviations from the exact-curve slope, in units of sampling_sd, have an RMS near 1 (a sample
// RMS of 20 values has a relative spread of about 16 %, so 1.5 is a three-sigma limit).
TEST(CorrelationDimensionLong, ScatterAcrossSeedsMatchesTheSamplingSd)
{
    if (!std::getenv("VIMPACT_LONG_TESTS")) GTEST_SKIP() << "set VIMPACT_LONG_TESTS=1";
    for (int kind = 0; kind < 2; ++kind) {
        double z2 = 0.0, sd_mean = 0.0;
        const int seeds = 20;
        for (int s = 0; s < seeds; ++s) {
            const auto res = estimate(kind == 0 ? line_points(10000, 100 + static_cast<std::uint64_t>(s))
                                                : square_points(10000, 200 + static_cast<std::uint64_t>(s)));
            const double theory = kind == 0 ? exact_slope(res, exact_line) : exact_slope(res, exact_square);
            const double sd = sampling_sd(res);
            z2 += (res.fit.dimension - theory) * (res.fit.dimension - theory) / (sd * sd);
            sd_mean += sd / seeds;
        }
        const double rms = std::sqrt(z2 / seeds);
        std::printf("%s: RMS of (nu - exact) / sampling_sd over %d seeds = %.3f (mean sampling_sd %.4f)\n",
                    kind ? "square" : "line", seeds, rms, sd_mean);
        EXPECT_LT(rms, 1.5);
        EXPECT_GT(rms, 0.3);  // not a uselessly loose bound either
    }
}
