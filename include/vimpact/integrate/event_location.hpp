#pragma once
// Locating the crossings of a scalar event function g(theta) on one step's interpolant,
// theta in [0, 1].
//
// A *downward* crossing is a passage from g > 0 to g <= 0; the crossing time is the left-open
// interval (0, 1], so a root exactly at a step boundary belongs to the step that ends there
// and is not seen again by the next step (which starts with g = 0, not g > 0). Upward
// crossings are downward crossings of -g.
//
// Grazing safety: g may dip below zero and come back between two samples that are both
// positive. Every interior extremum is therefore located (as a root of g', which the
// interpolant gives exactly) and the dip is split there, so such a crossing is found.
// The screening uses the exact values and slopes at the step ends: an interior extremum
// shows as a sign change of the slope. An event function whose slope changes sign twice
// within one step (two extrema in one step) can escape the screening; the steps of a
// tolerance-controlled integrator are far shorter than the oscillation periods where this
// could happen.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace vimpact {

enum class crossing_direction { down, up };

struct scalar_sample {
    double value;  // g
    double slope;  // dg/dtheta
};

namespace detail {

// First point for the root search on [a, b], g(a) > 0 > g(b): the inverse cubic Hermite
// interpolant, theta as a function of g through the end samples (their values and inverse
// slopes), at g = 0. On the short monotone pieces the locator searches (an eighth of a step,
// split at extrema) it lies within about (b - a)^4 of the root, so Newton on g then needs one
// or two evaluations where a midpoint start needs four. Where the piece is not seen to fall
// at both ends, the secant point; where rounding puts either outside the piece, its midpoint.
inline double inverse_hermite_root(double a, scalar_sample ga, double b, scalar_sample gb)
{
    const double d = gb.value - ga.value, s = ga.value / -d;
    double x = a + s * (b - a);
    if (ga.slope < 0.0 && gb.slope < 0.0) {
        const double s2 = s * s, s3 = s2 * s;
        x = a + (b - a) * (3.0 * s2 - 2.0 * s3) + d / ga.slope * (s3 - 2.0 * s2 + s) + d / gb.slope * (s3 - s2);
    }
    return (x > a && x < b) ? x : 0.5 * (a + b);
}

// Root of g on [a, b] with g(a) > 0 >= g(b): safeguarded Newton from inverse_hermite_root,
// returns a point with g <= 0 (the side the crossing leads to), as close to the root as
// doubles allow. Once its steps shrink below a unit in the last place it tries the
// neighbouring double on the root's side, which closes the bracket.
template <class G>
double newton_bracketed(G&& g, double a, scalar_sample ga, double b, scalar_sample gb)
{
    if (gb.value == 0.0) return b;
    double x = inverse_hermite_root(a, ga, b, gb);
    for (int it = 0; it < 100; ++it) {
        const scalar_sample s = g(x);
        if (s.value > 0.0) a = x;
        else b = x;
        if (s.value == 0.0) return x;
        const double width = b - a;
        if (width <= 2.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(b)))
            break;
        double next = (s.slope != 0.0) ? x - s.value / s.slope : 0.5 * (a + b);
        if (!(next > a && next < b)) {
            next = std::abs(next - x) <= std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(x))
                       ? std::nextafter(x, x == a ? b : a)
                       : 0.5 * (a + b);
            if (!(next > a && next < b)) break;
        }
        // Newton steps that stall (much smaller than the bracket) fall back to bisection
        // every few iterations to keep the bracket shrinking.
        if (it % 8 == 7) next = 0.5 * (a + b);
        x = next;
    }
    return b;
}

// Root of the slope on [a, b] where it changes sign (an extremum of g): the secant method on
// the slope alone, from the secant point of the end slopes, its first step taken with the
// curvature of the cubic Hermite interpolant through the end samples there, each step kept
// inside the bracket (else, and every eighth step, a bisection). It stops at a bracket of
// 4 eps, or at a step below 1e-10, whose end it returns. The secant converges superlinearly,
// so that end is far closer to the extremum than the step (about 1e-14 on the paper's
// protocol); and what the callers take from the point is g there, whose error is quadratic
// in the point's: below 1e-20 g'' even at 1e-10.
template <class G>
double extremum_bracketed(G&& g, double a, scalar_sample ga, double b, scalar_sample gb)
{
    constexpr double tol = 2.0 * std::numeric_limits<double>::epsilon();
    double sa = ga.slope;
    const double sb = gb.slope, w = b - a;
    double x = (a * sb - b * sa) / (sb - sa);
    if (!(x > a && x < b)) x = 0.5 * (a + b);
    // d(slope)/dtheta of the cubic at x: 2 c2 + 6 c3 u, over w^2.
    const double d0 = sa * w, d1 = sb * w, dg = gb.value - ga.value, u = (x - a) / w;
    double x_old = x, s_old = 0.0, rate = (6.0 * dg - 4.0 * d0 - 2.0 * d1 + 6.0 * u * (d0 + d1 - 2.0 * dg)) / (w * w);
    for (int it = 0; it < 80; ++it) {
        if (b - a <= 2.0 * tol) break;
        const double sx = g(x).slope;
        if (sx == 0.0) return x;
        if ((sx > 0.0) == (sa > 0.0)) {
            a = x;
            sa = sx;
        } else {
            b = x;
        }
        if (it > 0 && sx != s_old) rate = (sx - s_old) / (x - x_old);
        double next = rate != 0.0 ? x - sx / rate : 0.5 * (a + b);
        x_old = x;
        s_old = sx;
        const bool inside = next > a && next < b;
        if (inside && std::abs(next - x) < 1e-10) return next;
        if (!inside || it % 8 == 7) next = 0.5 * (a + b);
        x = next;
    }
    return 0.5 * (a + b);
}

}  // namespace detail

// find_down_crossings' screening from the end samples alone (values v, slopes or rates r of
// the same signs): false when no downward crossing can lie on the step. No crossing without a
// sign change to <= 0, and no dip without an interior minimum (slope from negative to
// positive) or maximum (from the g <= 0 side). T: double, or lanes (hybrid/flow_lanes.hpp),
// whose comparisons give masks.
template <class T>
auto down_crossing_possible(const T& v0, const T& v1, const T& r0, const T& r1)
{
    const T zero(0.0);
    const auto ends_down = v0 > zero && v1 <= zero;
    const auto interior_min = r0 < zero && r1 > zero;
    const auto interior_max = r0 > zero && r1 < zero;
    return ends_down || (interior_min && v1 > zero) || (interior_max && v1 <= zero && v0 <= zero);
}

// Finds the downward crossings of g on (0, 1] in increasing order and calls on_root(theta)
// for each; on_root returns false to stop the search (a terminal event). `g(theta)` returns
// value and slope; the end samples are passed in because they are known exactly.
// Returns the number of crossings reported.
template <class G, class OnRoot>
int find_down_crossings(G&& g, scalar_sample s0, scalar_sample s1, OnRoot&& on_root,
                        int subdivisions = 8)
{
    if (!down_crossing_possible(s0.value, s1.value, s0.slope, s1.slope)) return 0;

    // Sample the interpolant; split at every extremum so each piece is monotone.
    constexpr int max_points = 2 * 32 + 2;
    subdivisions = std::clamp(subdivisions, 1, 32);
    // Not value-initialised: every entry read was written first, and zeroing 1.5 kB on each
    // call was about 1 % of a map's time.
    std::array<double, max_points> th;
    std::array<scalar_sample, max_points> gs;
    int n = 0;
    double prev_t = 0.0;
    scalar_sample prev = s0;
    th[n] = 0.0;
    gs[n++] = s0;
    for (int k = 1; k <= subdivisions; ++k) {
        const double t = static_cast<double>(k) / subdivisions;
        const scalar_sample cur = (k == subdivisions) ? s1 : g(t);
        if ((prev.slope < 0.0 && cur.slope > 0.0) || (prev.slope > 0.0 && cur.slope < 0.0)) {
            const double te = detail::extremum_bracketed(g, prev_t, prev, t, cur);
            if (te > prev_t && te < t) {
                th[n] = te;
                gs[n++] = g(te);
            }
        }
        th[n] = t;
        gs[n++] = cur;
        prev_t = t;
        prev = cur;
    }

    int found = 0;
    for (int i = 0; i + 1 < n; ++i) {
        if (gs[i].value > 0.0 && gs[i + 1].value <= 0.0) {
            const double root = detail::newton_bracketed(g, th[i], gs[i], th[i + 1], gs[i + 1]);
            ++found;
            if (!on_root(root)) return found;
        }
    }
    return found;
}

template <class G, class OnRoot>
int find_crossings(crossing_direction dir, G&& g, scalar_sample s0, scalar_sample s1,
                   OnRoot&& on_root, int subdivisions = 8)
{
    if (dir == crossing_direction::down)
        return find_down_crossings(g, s0, s1, on_root, subdivisions);
    auto neg = [&](double t) {
        const scalar_sample s = g(t);
        return scalar_sample{-s.value, -s.slope};
    };
    return find_down_crossings(neg, scalar_sample{-s0.value, -s0.slope},
                               scalar_sample{-s1.value, -s1.slope}, on_root, subdivisions);
}

}  // namespace vimpact
