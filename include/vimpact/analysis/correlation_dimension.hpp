#pragma once
// Correlation dimension of a point set (Grassberger & Procaccia 1983; the paper's Eq. 5 and
// Figure 6). Two estimators of the correlation curve C(r), one rule for its scaling region.
//
// (a) correlation_sum: the Grassberger–Procaccia sum over all pairs,
//         C(r) = #{ i < j, j - i > w : |x_i - x_j| < r } / #{ i < j, j - i > w },
//     w the Theiler window (pairs close in time are left out for time-ordered data). All
//     radii come from one pass: every pair closer than the cap r_cap is counted into a bin of
//     log |x_i - x_j| and C is the cumulative sum. The bins are read off the bits of the
//     squared distance (exponent and leading mantissa bits), so binning costs a shift, the
//     bin edges are exact doubles and C at each edge is an exact count. The pairs closer than
//     r_cap are found by a cell grid (default), a nanoflann k-d tree or brute force, with
//     identical counts; the grid is 4-5 times faster than the tree here
//     (bench/dimension_bench.cpp). Only pairs closer than r_cap cost much, so capping r_cap
//     where C reaches a few per cent makes the sum far cheaper than all N^2 / 2 pairs.
// (b) centres: the paper's variant. N_k(r) = number of points within r of centre k, averaged
//     over K centres (paper: 15) on a linear grid of radii (paper: 1e-4 .. 0.06 in steps of
//     1e-4); C(r) = sum_k N_k(r) / sum_k (eligible points of centre k). The centres are the
//     points with indices floor((2k + 1) N / (2K)), k = 0..K-1: evenly spaced along the
//     record, hence distributed like the attractor's natural measure, and deterministic.
//
// Scaling region (fit_scaling_region): the usable radii have at least `min_pairs` pairs
// closer than r (below that C is dominated by counting noise; the floor is 1 pair out of
// N^2/2) and C <= `max_correlation` (saturation: C = 1 beyond the diameter of the set is a
// plateau of slope 0 that must never pass for a scaling region; 0.5 still admits the plateau
// C = 1/p of a period-p orbit, p >= 2, whose dimension is 0). On them the local slope s(r)
// is the least-squares slope of log C vs log r over radii within a factor sqrt(slope_window)
// either side; the default window, a factor 4, is longer than the period (a factor 3) of the
// log-periodic wiggle of C for the middle-thirds Cantor set, so such lacunarity averages out.
// The scaling region is the longest range of r (in log r) over which all local slopes lie
// within 2 * slope_tolerance of each other (so saturation bends and floor noise end it), and
// it must span at least `min_extent` in r; the dimension is the least-squares slope of
// log C vs log r over it. If no range of that extent meets the tolerance, the range of that
// extent with the least spread of local slopes is fitted and reported with found = false. A
// user range (fit_range) replaces the rule.
// The implementation is compiled into the library (src/analysis/correlation_dimension.cpp).
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

#include "vimpact/analysis/dimension_points.hpp"
#include "vimpact/core/names.hpp"
#include "vimpact/core/option.hpp"

namespace vimpact {

enum class dimension_estimator { correlation_sum, centres };

constexpr std::string_view to_string(dimension_estimator e)
{
    switch (e) {
        case dimension_estimator::correlation_sum: return "correlation_sum";
        case dimension_estimator::centres: return "centres";
    }
    return "unknown";
}

inline constexpr std::array<dimension_estimator, 2> all_dimension_estimators{dimension_estimator::correlation_sum,
                                                                           dimension_estimator::centres};

// C(r) at increasing radii r[k]: pairs[k] counted pairs closer than r[k] out of total_pairs.
struct correlation_curve {
    std::vector<double> r;
    std::vector<std::uint64_t> pairs;
    std::uint64_t total_pairs = 0;

    [[nodiscard]] std::size_t size() const { return r.size(); }
    [[nodiscard]] double c(std::size_t k) const
    {
        return total_pairs ? static_cast<double>(pairs[k]) / static_cast<double>(total_pairs) : 0.0;
    }
};

// How the pairs closer than the cap are found. All three give identical counts (they bin
// the same squared distances); they differ only in speed (bench/dimension_bench.cpp).
enum class pair_search {
    grid,         // cells of side r_cap, each pair of neighbouring cells scanned once (default)
    kd_tree,      // nanoflann k-d tree, a radius search around every point
    brute_force,  // every pair (the reference of the tests)
};

constexpr std::string_view to_string(pair_search s)
{
    switch (s) {
        case pair_search::grid: return "grid";
        case pair_search::kd_tree: return "kd_tree";
        case pair_search::brute_force: return "brute_force";
    }
    return "unknown";
}

inline constexpr std::array<pair_search, 3> all_pair_searches{pair_search::grid, pair_search::kd_tree,
                                                              pair_search::brute_force};

struct correlation_sum_options {
    long theiler_window = 0;  // a pair (i, j) counts only if |i - j| > theiler_window
    // Pairs at distance >= r_max are not binned (they still count in the denominator);
    // rounded up to the next bin edge. Infinite: every pair.
    double r_max = std::numeric_limits<double>::infinity();
    int bins_per_octave = 16;  // bins per factor 2 in r; a power of two, 2..128
    double range = 0x1p40;     // bins cover [r_max / range, r_max); closer pairs go to the first point
    pair_search search = pair_search::grid;
    int threads = 1;  // counts are integers: the result does not depend on this
};

struct centre_count_options {
    int centres = 15;
    double r_min = 1e-4;  // the paper's radii: 1e-4 .. 0.06 in steps of 1e-4
    double r_max = 0.06;
    double r_step = 1e-4;
    long theiler_window = 0;  // points with |j - centre| <= theiler_window are not counted
};

struct scaling_options {
    double slope_tolerance = 0.1;    // local slopes within +- this of each other
    double slope_window = 4.0;       // local slope over radii within a factor sqrt(this) either side
    double min_extent = 4.0;         // the region spans at least this factor in r
    std::uint64_t min_pairs = 100;   // floor: fewer pairs closer than r are counting noise
    double max_correlation = 0.5;    // saturation: radii with C above this are not used
    std::optional<std::array<double, 2>> fit_range;  // [r_min, r_max] replaces the rule
};

struct scaling_fit {
    bool automatic = true;  // false: fit_range was given
    bool found = false;     // automatic rule met the tolerance over min_extent (or user range fitted)
    double dimension = std::numeric_limits<double>::quiet_NaN();
    double intercept = std::numeric_limits<double>::quiet_NaN();  // of ln C = intercept + dimension ln r
    double r2 = std::numeric_limits<double>::quiet_NaN();         // NaN when C is constant over the range
    double slope_error = std::numeric_limits<double>::quiet_NaN(); // least-squares standard error
    double slope_spread = std::numeric_limits<double>::quiet_NaN(); // max - min local slope in range
    double r_min = std::numeric_limits<double>::quiet_NaN();
    double r_max = std::numeric_limits<double>::quiet_NaN();
    std::size_t first = 0, last = 0;  // indices of the fitted radii (inclusive)
    std::size_t fitted = 0;           // radii in the fit
    // Usable radii (floor and saturation rule), inclusive; usable_count == 0: none.
    std::size_t usable_first = 0, usable_last = 0, usable_count = 0;
    std::vector<double> local_slope;  // per radius; NaN where not evaluated
};

struct dimension_options {
    dimension_estimator estimator = dimension_estimator::correlation_sum;
    // Both estimators' (their own theiler_window is set from it): pairs at most this many
    // rows apart are not counted.
    long theiler_window = 0;
    correlation_sum_options correlation;
    centre_count_options centre;
    scaling_options scaling;
    // correlation_sum with an infinite r_max: if there are more eligible pairs than this, r_max
    // is set where about this many pairs are closer (a quantile of the distances between an
    // evenly spaced subsample of 2048 points). Caps cost, never changes C below r_max.
    std::uint64_t max_pairs = 100'000'000;
};

// The options a user sets (core/option.hpp); the centres' radii and a fit range, pairs of
// numbers, and the threads are the front ends' own.
template <class V, record_of<dimension_options> O>
void declare(V& v, O& o)
{
    v(option{"estimator", "the estimator of C(r): correlation_sum (Grassberger-Procaccia) or centres (the paper's)"},
      o.estimator, all_dimension_estimators);
    v(option{"theiler", "Theiler window: pairs of points at most this many rows apart are not counted", at_least(0)},
      o.theiler_window);
    v(option{"centres", "the number of centres of the centres estimator (the paper's 15)", at_least(1)}, o.centre.centres);
    v(option{"slope_tolerance", "scaling region: local slopes within +- this of each other", above(0)},
      o.scaling.slope_tolerance);
    v(option{"slope_window", "a local slope is fitted over a factor of this in r", above(1)}, o.scaling.slope_window);
    v(option{"min_extent", "the scaling region spans at least this factor in r", above(1)}, o.scaling.min_extent);
    v(option{"min_pairs", "floor: radii with fewer pairs closer than r are not used", at_least(1)}, o.scaling.min_pairs);
    v(option{"max_correlation", "saturation: radii with C above this are not used", value_range{0.0, 1.0, false, true}},
      o.scaling.max_correlation);
    v(option{"r_max", "the correlation sum counts pairs closer than this only (inf: set from max_pairs)",
             or_infinite(above(0))},
      o.correlation.r_max);
    v(option{"max_pairs", "the correlation sum caps r so that about this many pairs are counted", at_least(1)}, o.max_pairs);
    v(option{"bins_per_octave", "radii of the correlation sum per factor 2 in r (a power of two)", between(2, 128)},
      o.correlation.bins_per_octave);
    v(option{"search", "how the correlation sum finds pairs (grid, kd_tree or brute_force: the same counts)"},
      o.correlation.search, all_pair_searches);
}

struct dimension_result {
    dimension_estimator estimator = dimension_estimator::correlation_sum;
    std::size_t points = 0;
    int embedding = 0;                 // coordinates per point
    correlation_curve curve;
    scaling_fit fit;
    std::vector<std::size_t> centres;  // centres estimator: the centre indices
    double r_cap = std::numeric_limits<double>::infinity();  // correlation_sum: pairs counted below
    bool all_pairs = true;             // correlation_sum: r_cap exceeds every pair distance
};

// The Grassberger–Procaccia correlation sum at the bin edges below opt.r_max (see the top).
// Throws input_error for options out of range or too few points.
correlation_curve correlation_sum(const point_set& ps, const correlation_sum_options& opt);

// The paper's centres: indices floor((2k + 1) n / (2K)), k = 0..K-1.
std::vector<std::size_t> centre_indices(std::size_t n, int centres);
// The paper's linear grid of radii r_min, r_min + step, ... <= r_max (at most 1e6).
std::vector<double> centre_radii(const centre_count_options& o);
// N(r) summed over the centres: pairs[m] = sum_k #{ j eligible for centre k : |x_j - x_k| < r_m }.
correlation_curve centre_counts(const point_set& ps, const centre_count_options& opt,
                                std::vector<std::size_t>* centres_used = nullptr);

void validate(const scaling_options& o);
scaling_fit fit_scaling_region(const correlation_curve& curve, const scaling_options& opt);

// Radius below which about `fraction` of the pairs lie, from the distances between an evenly
// spaced subsample of at most 2048 points (deterministic).
double pair_distance_quantile(const point_set& ps, double fraction);

// Throws input_error for options no point set can satisfy (what correlation_dimension checks
// before it counts: the declared ranges, then what they cannot say, such as a power of two),
// so that a front end can refuse them before it makes the points.
void validate(const dimension_options& o);

dimension_result correlation_dimension(const point_set& ps, const dimension_options& opt);

namespace detail {

// log2 of the mantissa bins per exponent step for `bins_per_octave` (a power of two in
// [2, 128]); throws input_error otherwise.
int mantissa_bits(int bins_per_octave);
// Pairs (i, j), i < j, with j - i > w among n points.
std::uint64_t eligible_pairs(std::size_t n, long w);

}  // namespace detail

}  // namespace vimpact
