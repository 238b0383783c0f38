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
// The screening uses the exact values and slopes at the step ends: one interior extremum
// shows as a sign change of the slope; two (a maximum and a minimum, the slope of one sign at
// both ends) show as the two turns of the slope of the cubic Hermite interpolant through the
// end samples. The same test splits each sampled piece of a step. What it relies on is that g
// is resolved on the step: close to that cubic. The hybrid flow makes sure of it for every
// event function that is not an affine function of the state (those are resolved by the
// integrator's own error control), by a check on each step (integrate/event_resolution.hpp)
// that takes back a step too long for the function.
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

// Whether the cubic Hermite interpolant through end samples (values v, slopes r per unit of
// the piece, r0 and r1 of one sign) has two interior extrema: its slope
// p'(u) = r0 + 2 b u + 3 c u^2, with b = 3 (v1 - v0) - 2 r0 - r1 and c = r0 + r1 - 2 (v1 - v0),
// turns at u* = -b / (3 c) inside (0, 1) to the other sign there, p'(u*) = r0 - b^2 / (3 c).
// No division by zero reaches a comparison as true: c = 0 gives an infinite or NaN u*.
template <class T>
auto two_interior_extrema(const T& v0, const T& v1, const T& r0, const T& r1)
{
    const T zero(0.0), d = v1 - v0;
    const T b = 3.0 * d - 2.0 * r0 - r1, c = r0 + r1 - 2.0 * d;
    const T u = -b / (3.0 * c), turn = r0 - b * b / (3.0 * c);
    return ((r0 > zero && r1 > zero && turn < zero) || (r0 < zero && r1 < zero && turn > zero)) && u > zero &&
           u < T(1.0);
}

// find_down_crossings' screening from the end samples alone (values v, slopes or rates r of
// the same signs): false when no downward crossing can lie on the step. No crossing without a
// sign change to <= 0, and no dip without an interior minimum (slope from negative to
// positive), a maximum (from the g <= 0 side), or, in the second form, two interior extrema.
// T: double, or lanes (hybrid/flow_lanes.hpp), whose comparisons give masks. The first form's
// tests read only signs, so r may be rates per unit of time; the second's cubic needs slopes
// per unit of the step: r h (h = 1 for slopes per unit of theta).
template <class T>
auto down_crossing_possible(const T& v0, const T& v1, const T& r0, const T& r1)
{
    const T zero(0.0);
    const auto ends_down = v0 > zero && v1 <= zero;
    const auto interior_min = r0 < zero && r1 > zero;
    const auto interior_max = r0 > zero && r1 < zero;
    return ends_down || (interior_min && v1 > zero) || (interior_max && v1 <= zero && v0 <= zero);
}
template <class T>
auto down_crossing_possible(const T& v0, const T& v1, const T& r0, const T& r1, const T& h)
{
    return down_crossing_possible(v0, v1, r0, r1) || two_interior_extrema(v0, v1, r0 * h, r1 * h);
}

// Finds the downward crossings of g on (0, 1] in increasing order and calls on_root(theta)
// for each; on_root returns false to stop the search (a terminal event). `g(theta)` returns
// value and slope; the end samples are passed in because they are known exactly.
// Returns the number of crossings reported.
template <class G, class OnRoot>
int find_down_crossings(G&& g, scalar_sample s0, scalar_sample s1, OnRoot&& on_root,
                        int subdivisions = 8)
{
    if (!down_crossing_possible(s0.value, s1.value, s0.slope, s1.slope, 1.0)) return 0;

    // Sample the interpolant; split at every extremum so each piece is monotone. A piece whose
    // end slopes have one sign but whose cubic turns twice is split first where the cubic's
    // slope is extreme, so that each half shows its extremum as a change of sign.
    constexpr int max_points = 4 * 32 + 2;
    subdivisions = std::clamp(subdivisions, 1, 32);
    // Not value-initialised: every entry read was written first, and zeroing 1.5 kB on each
    // call was about 1 % of a map's time.
    std::array<double, max_points> th;
    std::array<scalar_sample, max_points> gs;
    int n = 0;
    th[n] = 0.0;
    gs[n++] = s0;
    // Appends the piece (a, ga] .. (b, gb]: its interior extremum, if the slope changes sign,
    // then b.
    const auto monotone_piece = [&](double a, scalar_sample ga, double b, scalar_sample gb) {
        if ((ga.slope < 0.0 && gb.slope > 0.0) || (ga.slope > 0.0 && gb.slope < 0.0)) {
            const double te = detail::extremum_bracketed(g, a, ga, b, gb);
            if (te > a && te < b) {
                th[n] = te;
                gs[n++] = g(te);
            }
        }
        th[n] = b;
        gs[n++] = gb;
    };
    double prev_t = 0.0;
    scalar_sample prev = s0;
    for (int k = 1; k <= subdivisions; ++k) {
        const double t = static_cast<double>(k) / subdivisions;
        const scalar_sample cur = (k == subdivisions) ? s1 : g(t);
        const double w = t - prev_t;
        if (two_interior_extrema(prev.value, cur.value, prev.slope * w, cur.slope * w)) {
            const double d = cur.value - prev.value, r0 = prev.slope * w, r1 = cur.slope * w;
            const double u = -(3.0 * d - 2.0 * r0 - r1) / (3.0 * (r0 + r1 - 2.0 * d));
            const double tm = prev_t + u * w;
            if (tm > prev_t && tm < t) {
                const scalar_sample mid = g(tm);
                monotone_piece(prev_t, prev, tm, mid);
                monotone_piece(tm, mid, t, cur);
            } else {
                monotone_piece(prev_t, prev, t, cur);
            }
        } else {
            monotone_piece(prev_t, prev, t, cur);
        }
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
