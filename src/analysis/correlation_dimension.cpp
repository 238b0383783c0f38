// The correlation dimension (include/vimpact/analysis/correlation_dimension.hpp states the
// method): the correlation sum by cell grid, k-d tree or brute force, the paper's centre
// counts, and the scaling-region rule.
#include "vimpact/analysis/correlation_dimension.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>
#include <thread>

#include <nanoflann.hpp>

#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"

namespace vimpact {

// ---- correlation sum -----------------------------------------------------------------------

namespace detail {

int mantissa_bits(int bins_per_octave)
{
    // A factor 2 in r is a factor 4 in r^2: two exponent steps of 2^k mantissa bins each.
    for (int k = 0; k <= 6; ++k)
        if ((2 << k) == bins_per_octave) return k;
    throw input_error("bins per octave must be a power of two in [2, 128] (got " +
                      std::to_string(bins_per_octave) + ")");
}

std::uint64_t eligible_pairs(std::size_t n, long w)
{
    const auto m = static_cast<std::uint64_t>(n);
    const auto ww = static_cast<std::uint64_t>(w);
    if (m <= ww + 1) return 0;
    return (m - ww - 1) * (m - ww) / 2;
}

namespace {

// Monotone key of a non-negative squared distance: exponent and k leading mantissa bits.
std::uint64_t bin_key(double d2, int k) { return std::bit_cast<std::uint64_t>(d2) >> (52 - k); }
double key_edge(std::uint64_t key, int k) { return std::bit_cast<double>(key << (52 - k)); }

// Squared diagonal of the bounding box: rounding is monotone, so no pair's squared distance
// (computed by squared_distance) exceeds it.
double bounding_diagonal2(const point_set& ps)
{
    const int d = ps.dim();
    std::vector<double> lo(ps.point(0), ps.point(0) + d), hi = lo;
    for (std::size_t i = 1; i < ps.size(); ++i)
        for (int k = 0; k < d; ++k) {
            lo[k] = std::min(lo[k], ps.coordinate(i, k));
            hi[k] = std::max(hi[k], ps.coordinate(i, k));
        }
    return squared_distance(lo.data(), hi.data(), d);
}

struct point_set_adaptor {
    const point_set& ps;
    [[nodiscard]] std::size_t kdtree_get_point_count() const { return ps.size(); }
    [[nodiscard]] double kdtree_get_pt(std::size_t i, std::size_t k) const
    {
        return ps.coordinate(i, static_cast<int>(k));
    }
    template <class Box>
    bool kdtree_get_bbox(Box&) const { return false; }
};

// nanoflann's metric, evaluated by our squared_distance so that tree and brute force agree
// to the bit.
struct canonical_l2 {
    using ElementType = double;
    using DistanceType = double;
    const point_set_adaptor& source;
    explicit canonical_l2(const point_set_adaptor& s) : source(s) {}
    [[nodiscard]] double evalMetric(const double* a, std::uint32_t b, std::size_t size) const
    {
        return squared_distance(a, source.ps.point(b), static_cast<int>(size));
    }
    template <class U, class V>
    [[nodiscard]] double accum_dist(U a, V b, std::size_t) const
    {
        return (a - b) * (a - b);
    }
};

using kd_tree = nanoflann::KDTreeSingleIndexAdaptor<canonical_l2, point_set_adaptor, -1, std::uint32_t>;

// The histogram of pair distances: hist[0] counts pairs below the first edge, hist[1 + b]
// those in [edge(low + b), edge(low + b + 1)).
struct pair_binner {
    std::uint64_t low_key = 0;
    std::uint64_t cap_key = 0;
    double cap2 = 0.0;  // edge(cap_key): pairs at d2 >= cap2 are not binned
    int k = 3;

    void add(std::vector<std::uint64_t>& hist, double d2) const
    {
        if (!(d2 < cap2)) return;
        const std::uint64_t key = bin_key(d2, k);
        ++hist[key >= low_key ? key - low_key + 1 : 0];
    }
};

// nanoflann result set that bins instead of storing: no allocation per query.
struct binning_result_set {
    const pair_binner& binner;
    std::vector<std::uint64_t>& hist;
    double search2;            // slightly above cap2: the tree's pruning is done in rounded arithmetic
    std::uint32_t min_index;   // partner index must be >= this (i + w + 1): each pair once
    [[nodiscard]] bool full() const { return true; }
    [[nodiscard]] double worstDist() const { return search2; }
    bool addPoint(double d2, std::uint32_t j)
    {
        if (j >= min_index) binner.add(hist, d2);
        return true;
    }
};

template <class Work>
void run_threads(int threads, Work&& work)
{
    if (threads <= 1) {
        work(0, 1);
        return;
    }
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) pool.emplace_back([&work, t, threads] { work(t, threads); });
    for (auto& th : pool) th.join();
}

void validate_points(const point_set& ps, std::size_t at_least, const std::string& what)
{
    if (ps.size() < at_least)
        throw input_error(what + " needs at least " + std::to_string(at_least) + " points (got " +
                          std::to_string(ps.size()) + ")");
    if (ps.size() > std::numeric_limits<std::uint32_t>::max())
        throw input_error(what + ": at most 4294967295 points");
}

// ---- the cell grid ----
// Points are sorted into cubic cells of side >= r_cap on (up to) the three coordinates of
// largest extent, so every pair closer than r_cap lies in one cell or in two adjacent ones.
// Each cell is paired with itself and with the 13 (3-D; 4 in 2-D, 1 in 1-D) neighbours that
// follow it in lexicographic order, so each pair of cells, hence each pair of points, is
// scanned once, over contiguous copies of the points.
struct cell_grid {
    int dim = 0;
    std::vector<double> x;             // points sorted by cell, row-major
    std::vector<std::uint32_t> index;  // original index of each sorted point
    std::vector<std::uint64_t> key;    // key of each non-empty cell, increasing
    std::vector<std::size_t> begin;    // its points: [begin[c], begin[c + 1])
    std::vector<std::array<int, 3>> neighbour_steps;  // the half stencil
    int grid_axes = 0;
};

constexpr int cell_bits = 21;  // three 21-bit cell coordinates in one 64-bit key

std::uint64_t cell_component(std::uint64_t key, int a)
{
    return (key >> (cell_bits * (2 - a))) & ((std::uint64_t{1} << cell_bits) - 1);
}

cell_grid build_cell_grid(const point_set& ps, double cap2)
{
    cell_grid g;
    g.dim = ps.dim();
    const std::size_t n = ps.size();
    const int d = ps.dim();
    std::vector<double> lo(ps.point(0), ps.point(0) + d), hi = lo;
    for (std::size_t i = 1; i < n; ++i)
        for (int k = 0; k < d; ++k) {
            lo[k] = std::min(lo[k], ps.coordinate(i, k));
            hi[k] = std::max(hi[k], ps.coordinate(i, k));
        }
    std::vector<int> axes(static_cast<std::size_t>(d));
    for (int k = 0; k < d; ++k) axes[static_cast<std::size_t>(k)] = k;
    std::stable_sort(axes.begin(), axes.end(), [&](int a, int b) { return hi[a] - lo[a] > hi[b] - lo[b]; });
    g.grid_axes = std::min(d, 3);
    double extent = 0.0;
    for (int a = 0; a < g.grid_axes; ++a) extent = std::max(extent, hi[axes[a]] - lo[axes[a]]);
    // Cells no smaller than the cap (a little above it, so rounding in the division cannot
    // put two points closer than r_cap two cells apart), and few enough to fit the key.
    const double side = std::max({std::sqrt(cap2) * (1.0 + 1e-6), extent / 0x1p20, std::numeric_limits<double>::min()});
    std::vector<std::pair<std::uint64_t, std::uint32_t>> order(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::uint64_t key = 0;
        for (int a = 0; a < 3; ++a) {
            std::uint64_t c = 0;
            if (a < g.grid_axes) {
                const double f = std::floor((ps.coordinate(i, axes[a]) - lo[axes[a]]) / side);
                c = static_cast<std::uint64_t>(std::clamp(f, 0.0, 0x1p20));
            }
            key = (key << cell_bits) | c;
        }
        order[i] = {key, static_cast<std::uint32_t>(i)};
    }
    std::sort(order.begin(), order.end());
    g.x.resize(n * static_cast<std::size_t>(d));
    g.index.resize(n);
    for (std::size_t s = 0; s < n; ++s) {
        g.index[s] = order[s].second;
        std::copy(ps.point(order[s].second), ps.point(order[s].second) + d, g.x.begin() + static_cast<std::ptrdiff_t>(s) * d);
        if (s == 0 || order[s].first != order[s - 1].first) {
            g.key.push_back(order[s].first);
            g.begin.push_back(s);
        }
    }
    g.begin.push_back(n);
    // Half stencil: steps whose first non-zero component is positive.
    for (int s0 = -1; s0 <= 1; ++s0)
        for (int s1 = -1; s1 <= 1; ++s1)
            for (int s2 = -1; s2 <= 1; ++s2) {
                const std::array<int, 3> st{s0, s1, s2};
                bool used = true;
                for (int a = g.grid_axes; a < 3; ++a) used = used && st[a] == 0;
                int first = 0;
                for (int a = 0; a < 3 && first == 0; ++a) first = st[a];
                if (used && first > 0) g.neighbour_steps.push_back(st);
            }
    return g;
}

template <int D>
void scan_cell_pair(const cell_grid& g, std::size_t a0, std::size_t a1, std::size_t b0, std::size_t b1, bool same,
                    const pair_binner& binner, std::uint64_t w, std::vector<std::uint64_t>& hist)
{
    const int d = D > 0 ? D : g.dim;
    for (std::size_t i = a0; i < a1; ++i) {
        const double* xi = g.x.data() + i * static_cast<std::size_t>(d);
        const std::uint64_t ii = g.index[i];
        for (std::size_t j = same ? i + 1 : b0; j < b1; ++j) {
            const double d2 = squared_distance(xi, g.x.data() + j * static_cast<std::size_t>(d), d);
            if (d2 < binner.cap2) {
                const std::uint64_t jj = g.index[j];
                if ((ii > jj ? ii - jj : jj - ii) > w) binner.add(hist, d2);
            }
        }
    }
}

template <int D>
void grid_pairs_dim(const cell_grid& g, const pair_binner& binner, std::uint64_t w, int threads,
                    std::vector<std::vector<std::uint64_t>>& hists)
{
    const std::size_t cells = g.key.size();
    run_threads(threads, [&](int t, int nt) {
        auto& h = hists[static_cast<std::size_t>(t)];
        for (std::size_t c = static_cast<std::size_t>(t); c < cells; c += static_cast<std::size_t>(nt)) {
            scan_cell_pair<D>(g, g.begin[c], g.begin[c + 1], g.begin[c], g.begin[c + 1], true, binner, w, h);
            for (const auto& st : g.neighbour_steps) {
                std::uint64_t target = 0;
                bool inside = true;
                for (int a = 0; a < 3; ++a) {
                    const auto comp = static_cast<std::int64_t>(cell_component(g.key[c], a)) + st[a];
                    inside = inside && comp >= 0;
                    target = (target << cell_bits) | static_cast<std::uint64_t>(std::max<std::int64_t>(comp, 0));
                }
                if (!inside) continue;
                const auto it = std::lower_bound(g.key.begin() + static_cast<std::ptrdiff_t>(c) + 1, g.key.end(), target);
                if (it == g.key.end() || *it != target) continue;
                const auto b = static_cast<std::size_t>(it - g.key.begin());
                scan_cell_pair<D>(g, g.begin[c], g.begin[c + 1], g.begin[b], g.begin[b + 1], false, binner, w, h);
            }
        }
    });
}

void grid_pairs(const point_set& ps, const pair_binner& binner, std::uint64_t w, int threads,
                       std::vector<std::vector<std::uint64_t>>& hists)
{
    const cell_grid g = build_cell_grid(ps, binner.cap2);
    switch (ps.dim()) {
        case 1: grid_pairs_dim<1>(g, binner, w, threads, hists); break;
        case 2: grid_pairs_dim<2>(g, binner, w, threads, hists); break;
        case 3: grid_pairs_dim<3>(g, binner, w, threads, hists); break;
        default: grid_pairs_dim<0>(g, binner, w, threads, hists); break;
    }
}

}  // namespace
}  // namespace detail

// The Grassberger–Procaccia correlation sum at the bin edges below opt.r_max (see the top).
correlation_curve correlation_sum(const point_set& ps, const correlation_sum_options& opt)
{
    detail::validate_points(ps, 2, "the correlation sum");
    if (opt.theiler_window < 0)
        throw input_error("Theiler window must be >= 0 (got " + std::to_string(opt.theiler_window) + ")");
    if (!(opt.r_max > 0.0)) throw input_error("r_max must be > 0 (got " + format_double(opt.r_max) + ")");
    if (!(opt.range > 1.0) || !std::isfinite(opt.range) || opt.range > 0x1p200)
        throw input_error("bin range must be in (1, 2^200] (got " + format_double(opt.range) + ")");
    const int k = detail::mantissa_bits(opt.bins_per_octave);
    const std::size_t n = ps.size();
    const auto w = static_cast<std::uint64_t>(opt.theiler_window);

    correlation_curve curve;
    curve.total_pairs = detail::eligible_pairs(n, opt.theiler_window);
    if (curve.total_pairs == 0)
        throw input_error("Theiler window " + std::to_string(opt.theiler_window) + " leaves no pairs among " +
                          std::to_string(n) + " points (valid: 0 <= window <= " + std::to_string(n - 2) + ")");

    const double diag2 = detail::bounding_diagonal2(ps);
    detail::pair_binner binner;
    binner.k = k;
    {
        // Cap at an exact bin edge at or above min(r_max^2, anything above the diagonal).
        const double want2 = std::isfinite(opt.r_max) ? std::min(opt.r_max * opt.r_max, diag2) : diag2;
        std::uint64_t cap = detail::bin_key(want2, k);
        if (!(detail::key_edge(cap, k) >= want2)) ++cap;
        if (want2 >= diag2 && detail::key_edge(cap, k) <= diag2) ++cap;  // strictly above every pair
        binner.cap_key = cap;
        binner.cap2 = detail::key_edge(cap, k);
        const auto span = static_cast<std::uint64_t>(std::ceil(std::log2(opt.range) * opt.bins_per_octave));
        binner.low_key = cap > span ? cap - span : 0;
    }
    const std::size_t nbins = static_cast<std::size_t>(binner.cap_key - binner.low_key);

    const int threads = std::max(1, opt.threads);
    std::vector<std::vector<std::uint64_t>> hists(static_cast<std::size_t>(threads),
                                                  std::vector<std::uint64_t>(nbins + 1, 0));
    switch (opt.search) {
        case pair_search::brute_force:
            detail::run_threads(threads, [&](int t, int nt) {
                auto& h = hists[static_cast<std::size_t>(t)];
                for (std::size_t i = static_cast<std::size_t>(t); i < n; i += static_cast<std::size_t>(nt))
                    for (std::size_t j = i + w + 1; j < n; ++j)
                        binner.add(h, squared_distance(ps.point(i), ps.point(j), ps.dim()));
            });
            break;
        case pair_search::kd_tree: {
            const detail::point_set_adaptor source{ps};
            // Large leaves: below them the search is a contiguous scan, which is what
            // counting many neighbours per point needs (measured: 64 beats 10 and 16).
            const detail::kd_tree tree(ps.dim(), source, nanoflann::KDTreeSingleIndexAdaptorParams(64));
            // Pruning compares sums of rounded squares: a margin far above their rounding
            // error (depth * eps * diagonal^2) keeps every pair below cap2 in the search.
            const double search2 = binner.cap2 * (1.0 + 1e-9) + 1e-12 * diag2;
            detail::run_threads(threads, [&](int t, int nt) {
                auto& h = hists[static_cast<std::size_t>(t)];
                const nanoflann::SearchParams params(32, 0.0f, false);
                for (std::size_t i = static_cast<std::size_t>(t); i + w + 1 < n; i += static_cast<std::size_t>(nt)) {
                    detail::binning_result_set rs{binner, h, search2, static_cast<std::uint32_t>(i + w + 1)};
                    tree.findNeighbors(rs, ps.point(i), params);
                }
            });
            break;
        }
        case pair_search::grid: detail::grid_pairs(ps, binner, w, threads, hists); break;
    }
    std::vector<std::uint64_t> hist(nbins + 1, 0);
    for (const auto& h : hists)
        for (std::size_t b = 0; b <= nbins; ++b) hist[b] += h[b];

    curve.r.reserve(nbins + 1);
    curve.pairs.reserve(nbins + 1);
    // C at edge(low + b) counts the pairs with d2 below it: the first bin and bins 1..b.
    std::uint64_t cum = hist[0];
    for (std::size_t b = 0; b <= nbins; ++b) {
        const double edge2 = detail::key_edge(binner.low_key + b, k);
        if (edge2 > 0.0) {
            curve.r.push_back(std::sqrt(edge2));
            curve.pairs.push_back(cum);
        }
        if (b < nbins) cum += hist[b + 1];
    }
    return curve;
}

// ---- the paper's centre counts -------------------------------------------------------------

std::vector<std::size_t> centre_indices(std::size_t n, int centres)
{
    std::vector<std::size_t> c;
    const auto kk = static_cast<std::uint64_t>(centres);
    for (std::uint64_t k = 0; k < kk; ++k) c.push_back(static_cast<std::size_t>((2 * k + 1) * n / (2 * kk)));
    return c;
}

std::vector<double> centre_radii(const centre_count_options& o)
{
    if (!(o.r_min > 0.0) || !std::isfinite(o.r_min))
        throw input_error("radii: r_min must be > 0 (got " + format_double(o.r_min) + ")");
    if (!(o.r_max >= o.r_min) || !std::isfinite(o.r_max))
        throw input_error("radii: r_max must be >= r_min = " + format_double(o.r_min) + " (got " +
                          format_double(o.r_max) + ")");
    if (!(o.r_step > 0.0) || !std::isfinite(o.r_step))
        throw input_error("radii: step must be > 0 (got " + format_double(o.r_step) + ")");
    const double count = std::floor((o.r_max - o.r_min) / o.r_step * (1.0 + 1e-12)) + 1.0;
    if (count > 1e6) throw input_error("radii: at most 10^6 radii (got " + format_double(count) + ")");
    std::vector<double> r;
    for (long i = 0; i < static_cast<long>(count); ++i) r.push_back(o.r_min + static_cast<double>(i) * o.r_step);
    return r;
}

// N(r) summed over the centres: pairs[m] = sum_k #{ j eligible for centre k : |x_j - x_k| < r_m }.
correlation_curve centre_counts(const point_set& ps, const centre_count_options& opt,
                                       std::vector<std::size_t>* centres_used)
{
    detail::validate_points(ps, 2, "the centre counts");
    const std::size_t n = ps.size();
    if (opt.centres < 1 || static_cast<std::size_t>(opt.centres) > n)
        throw input_error("centres must be in [1, " + std::to_string(n) + "] (the number of points; got " +
                          std::to_string(opt.centres) + ")");
    if (opt.theiler_window < 0)
        throw input_error("Theiler window must be >= 0 (got " + std::to_string(opt.theiler_window) + ")");
    const auto w = static_cast<std::size_t>(opt.theiler_window);
    correlation_curve curve;
    curve.r = centre_radii(opt);
    curve.pairs.assign(curve.r.size(), 0);
    const auto centres = centre_indices(n, opt.centres);
    std::vector<double> d2;
    d2.reserve(n);
    for (const std::size_t c : centres) {
        d2.clear();
        for (std::size_t j = 0; j < n; ++j) {
            const std::size_t gap = j > c ? j - c : c - j;
            if (gap > w) d2.push_back(squared_distance(ps.point(c), ps.point(j), ps.dim()));
        }
        std::sort(d2.begin(), d2.end());
        curve.total_pairs += d2.size();
        for (std::size_t m = 0; m < curve.r.size(); ++m)
            curve.pairs[m] += static_cast<std::uint64_t>(
                std::lower_bound(d2.begin(), d2.end(), curve.r[m] * curve.r[m]) - d2.begin());
    }
    if (curve.total_pairs == 0)
        throw input_error("Theiler window " + std::to_string(opt.theiler_window) + " leaves no points to count around the centres");
    if (centres_used) *centres_used = centres;
    return curve;
}

// ---- scaling region ------------------------------------------------------------------------

namespace detail {
namespace {

struct line_fit {
    double slope = std::numeric_limits<double>::quiet_NaN();
    double intercept = std::numeric_limits<double>::quiet_NaN();
    double r2 = std::numeric_limits<double>::quiet_NaN();
    double slope_error = std::numeric_limits<double>::quiet_NaN();
};

line_fit least_squares(const std::vector<double>& x, const std::vector<double>& y, std::size_t a, std::size_t b)
{
    line_fit f;
    const auto m = static_cast<double>(b - a + 1);
    if (b < a + 1) return f;
    double mx = 0.0, my = 0.0;
    for (std::size_t i = a; i <= b; ++i) {
        mx += x[i];
        my += y[i];
    }
    mx /= m;
    my /= m;
    double sxx = 0.0, sxy = 0.0, syy = 0.0;
    for (std::size_t i = a; i <= b; ++i) {
        sxx += (x[i] - mx) * (x[i] - mx);
        sxy += (x[i] - mx) * (y[i] - my);
        syy += (y[i] - my) * (y[i] - my);
    }
    if (!(sxx > 0.0)) return f;
    f.slope = sxy / sxx;
    f.intercept = my - f.slope * mx;
    const double ssr = std::max(0.0, syy - f.slope * sxy);
    // r2 says how much of the variation of ln C the line explains: undefined when ln C does
    // not vary (a periodic orbit's plateau), where syy is only rounding of identical values.
    if (syy > 1e-24 * m * (1.0 + my * my)) f.r2 = 1.0 - ssr / syy;
    if (m > 2.0) f.slope_error = std::sqrt(ssr / (m - 2.0) / sxx);
    return f;
}

}  // namespace
}  // namespace detail

void validate(const scaling_options& o)
{
    if (!(o.slope_tolerance > 0.0) || !std::isfinite(o.slope_tolerance))
        throw input_error("slope tolerance must be > 0 (got " + format_double(o.slope_tolerance) + ")");
    if (!(o.slope_window > 1.0) || !std::isfinite(o.slope_window))
        throw input_error("slope window must be a factor > 1 (got " + format_double(o.slope_window) + ")");
    if (!(o.min_extent > 1.0) || !std::isfinite(o.min_extent))
        throw input_error("minimum extent must be a factor > 1 (got " + format_double(o.min_extent) + ")");
    if (!(o.max_correlation > 0.0 && o.max_correlation <= 1.0))
        throw input_error("maximum correlation must be in (0, 1] (got " + format_double(o.max_correlation) + ")");
    if (o.fit_range) {
        const auto [a, b] = *o.fit_range;
        if (!(a > 0.0) || !(b > a) || !std::isfinite(b))
            throw input_error("fit range " + format_double(a) + ":" + format_double(b) +
                              " is invalid (valid: 0 < r_min < r_max, finite)");
    }
}

scaling_fit fit_scaling_region(const correlation_curve& curve, const scaling_options& opt)
{
    validate(opt);
    scaling_fit fit;
    const std::size_t n = curve.size();
    fit.local_slope.assign(n, std::numeric_limits<double>::quiet_NaN());
    std::vector<double> x(n), y(n);
    for (std::size_t k = 0; k < n; ++k) {
        x[k] = std::log(curve.r[k]);
        y[k] = curve.pairs[k] > 0 ? std::log(curve.c(k)) : -std::numeric_limits<double>::infinity();
    }
    // Both conditions are monotone in r (pairs and C only grow), so the usable radii are
    // one contiguous range.
    std::size_t lo = n, hi = 0;
    for (std::size_t k = 0; k < n; ++k)
        if (curve.pairs[k] > 0 && curve.pairs[k] >= opt.min_pairs && curve.c(k) <= opt.max_correlation) {
            lo = std::min(lo, k);
            hi = k;
        }
    if (lo < n) {
        fit.usable_first = lo;
        fit.usable_last = hi;
        fit.usable_count = hi - lo + 1;
        const double half = 0.5 * std::log(opt.slope_window);
        std::size_t a = lo;
        for (std::size_t k = lo; k <= hi; ++k) {
            while (x[a] < x[k] - half) ++a;
            std::size_t b = k;
            while (b + 1 <= hi && x[b + 1] <= x[k] + half) ++b;
            if (b >= a + 2) fit.local_slope[k] = detail::least_squares(x, y, a, b).slope;
        }
    }
    auto spread = [&](std::size_t a, std::size_t b) {
        double mn = std::numeric_limits<double>::infinity(), mx = -mn;
        for (std::size_t k = a; k <= b; ++k) {
            if (std::isnan(fit.local_slope[k])) return std::numeric_limits<double>::infinity();
            mn = std::min(mn, fit.local_slope[k]);
            mx = std::max(mx, fit.local_slope[k]);
        }
        return mx - mn;
    };

    std::size_t first = 0, last = 0;
    bool have = false;
    if (opt.fit_range) {
        fit.automatic = false;
        const auto [ra, rb] = *opt.fit_range;
        std::size_t cnt = 0;
        for (std::size_t k = 0; k < n; ++k)
            // A relative margin so that grid radii printed in decimal (0.06 = 1e-4 + 599 * 1e-4
            // up to rounding) are inside the range the user typed.
            if (curve.r[k] >= ra * (1.0 - 1e-9) && curve.r[k] <= rb * (1.0 + 1e-9) && curve.pairs[k] > 0) {
                if (cnt++ == 0) first = k;
                last = k;
            }
        if (cnt < 3) {
            std::size_t k0 = 0;
            while (k0 < n && curve.pairs[k0] == 0) ++k0;
            std::string msg = "fit range ";
            msg += format_double(ra);
            msg += ':';
            msg += format_double(rb);
            msg += " holds ";
            msg += std::to_string(cnt);
            msg += " radii with C > 0 (need >= 3); radii with C > 0 span ";
            if (k0 < n) {
                msg += '[';
                msg += format_double(curve.r[k0]);
                msg += ", ";
                msg += format_double(curve.r[n - 1]);
                msg += ']';
            } else {
                msg += "nothing (no pair is that close)";
            }
            throw input_error(msg);
        }
        have = true;
        fit.found = true;
    } else if (fit.usable_count > 0) {
        const double need = std::log(opt.min_extent) * (1.0 - 1e-12);
        double best_extent = -1.0, best_spread = 0.0;
        for (std::size_t a = lo; a <= hi; ++a) {
            if (std::isnan(fit.local_slope[a])) continue;
            double mn = fit.local_slope[a], mx = mn;
            for (std::size_t b = a; b <= hi; ++b) {
                const double s = fit.local_slope[b];
                if (std::isnan(s)) break;
                mn = std::min(mn, s);
                mx = std::max(mx, s);
                if (mx - mn > 2.0 * opt.slope_tolerance) break;
                const double extent = x[b] - x[a];
                if (b > a && (extent > best_extent + 1e-12 || (std::abs(extent - best_extent) <= 1e-12 && mx - mn < best_spread))) {
                    best_extent = extent;
                    best_spread = mx - mn;
                    first = a;
                    last = b;
                }
            }
        }
        if (best_extent >= need) {
            have = true;
            fit.found = true;
        } else {
            // No range meets the tolerance: the range of the minimum extent whose local
            // slopes vary least, flagged as not found.
            double least = std::numeric_limits<double>::infinity();
            std::size_t b = lo;
            for (std::size_t a = lo; a <= hi; ++a) {
                b = std::max(b, a);
                while (b <= hi && x[b] - x[a] < need) ++b;
                if (b > hi) break;
                const double s = spread(a, b);
                if (s < least) {
                    least = s;
                    first = a;
                    last = b;
                    have = true;
                }
            }
            if (!have && hi >= lo + 2) {
                first = lo;
                last = hi;
                have = true;
            }
        }
    }
    if (have) {
        const auto lf = detail::least_squares(x, y, first, last);
        fit.first = first;
        fit.last = last;
        fit.fitted = last - first + 1;
        fit.dimension = lf.slope;
        fit.intercept = lf.intercept;
        fit.r2 = lf.r2;
        fit.slope_error = lf.slope_error;
        fit.r_min = curve.r[first];
        fit.r_max = curve.r[last];
        fit.slope_spread = spread(first, last);
    }
    return fit;
}

// ---- the whole estimate --------------------------------------------------------------------

// Radius below which about `pairs` of the eligible pairs lie, from the distances between an
// evenly spaced subsample (deterministic).
double pair_distance_quantile(const point_set& ps, double fraction)
{
    const std::size_t n = ps.size();
    const std::size_t m = std::min<std::size_t>(n, 2048);
    std::vector<double> d2;
    d2.reserve(m * (m - 1) / 2);
    for (std::size_t a = 0; a < m; ++a)
        for (std::size_t b = a + 1; b < m; ++b)
            d2.push_back(squared_distance(ps.point(a * n / m), ps.point(b * n / m), ps.dim()));
    if (d2.empty()) return std::numeric_limits<double>::infinity();
    const auto q = static_cast<std::size_t>(std::clamp(fraction, 0.0, 1.0) * static_cast<double>(d2.size() - 1));
    std::nth_element(d2.begin(), d2.begin() + static_cast<std::ptrdiff_t>(q), d2.end());
    return std::sqrt(d2[q]);
}

dimension_result correlation_dimension(const point_set& ps, const dimension_options& options)
{
    validate(options);
    dimension_options opt = options;
    opt.correlation.theiler_window = opt.theiler_window;
    opt.centre.theiler_window = opt.theiler_window;
    // Two points make one pair and one distance: no curve to fit a slope to.
    detail::validate_points(ps, 3, "the dimension");
    dimension_result res;
    res.estimator = opt.estimator;
    res.points = ps.size();
    res.embedding = ps.dim();
    if (opt.estimator == dimension_estimator::centres) {
        res.curve = centre_counts(ps, opt.centre, &res.centres);
    } else {
        correlation_sum_options co = opt.correlation;
        detail::validate_points(ps, 2, "the correlation sum");
        const std::uint64_t total = detail::eligible_pairs(ps.size(), co.theiler_window);
        if (!std::isfinite(co.r_max) && opt.max_pairs > 0 && total > opt.max_pairs) {
            const double q = pair_distance_quantile(ps, static_cast<double>(opt.max_pairs) / static_cast<double>(total));
            if (q > 0.0) co.r_max = q;
        }
        res.curve = correlation_sum(ps, co);
        res.r_cap = res.curve.r.empty() ? 0.0 : res.curve.r.back();
        res.all_pairs = !res.curve.pairs.empty() && res.curve.pairs.back() == res.curve.total_pairs;
    }
    res.fit = fit_scaling_region(res.curve, opt.scaling);
    return res;
}


void validate(const dimension_options& o)
{
    check_options(o);
    validate(o.scaling);
    (void)detail::mantissa_bits(o.correlation.bins_per_octave);
    if (!(o.correlation.range > 1.0) || !std::isfinite(o.correlation.range) || o.correlation.range > 0x1p200)
        throw input_error("bin range must be in (1, 2^200] (got " + format_double(o.correlation.range) + ")");
    if (o.estimator == dimension_estimator::centres) {
        if (o.centre.centres < 1)
            throw input_error("centres must be >= 1 (got " + std::to_string(o.centre.centres) + ")");
        (void)centre_radii(o.centre);
    }
}

}  // namespace vimpact
