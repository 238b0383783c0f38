#pragma once
// Whether an event function g (a gap or a section) is resolved on a step: whether it lies
// close to the cubic Hermite interpolant through its values and slopes at the step's ends,
// which is what the crossing search's screening reads (integrate/event_location.hpp). The
// integrator's error control keeps the state's interpolant accurate, so a function affine in
// the state follows it; a function that is not (the table of a ball on a vibrating table,
// z - G sin(phi), or a strobe section sin(phi) of a system whose phase never limits the step)
// can turn many times inside a step the integrator finds smooth, and hide crossings there.
//
// The check: g at the state's own cubic Hermite interpolant (through the end states and their
// derivatives, known without any further evaluation of the vector field) at two interior
// points, theta_c and 1 - theta_c, against the cubic through g's end samples there. The
// error of a cubic is of order h^4 against a scale of order h (the change of g over the
// step), so a step that fails is taken again shorter by the factor step_factor gives.
// theta_c = sqrt(2) - 1: at irrational points, a step that is a whole number of periods of an
// oscillation of g cannot look like a cubic at both ends and there. Measured on sin over a
// step of h radians, over 2000 phases: every step of 1 radian passes, half of those of 1.9,
// 5 % of those of 3, none of 4 or more (two extrema at most, which the screening sees).
#include <algorithm>
#include <cmath>
#include <limits>

namespace vimpact::event_resolution {

inline constexpr double theta_c = 0.41421356237309503;
// The cubic's error tolerated at each point, relative to the change of g over the step: 1 %.
inline constexpr double tolerance = 0.01;

// Cubic Hermite basis at theta_c: value = h00 v0 + h01 v1 + h10 s0 + h11 s1 (s: slopes per
// unit of theta); at 1 - theta_c the same with the ends exchanged: h01 v0 + h00 v1 - h11 s0 -
// h10 s1.
inline constexpr double c2 = theta_c * theta_c, c3 = c2 * theta_c;
inline constexpr double h00 = 2.0 * c3 - 3.0 * c2 + 1.0, h01 = 3.0 * c2 - 2.0 * c3;
inline constexpr double h10 = c3 - 2.0 * c2 + theta_c, h11 = c3 - c2;

// The state's cubic Hermite interpolant of the step (x0, f0) -> (x1, f1) of size h at theta_c
// (point 0) or 1 - theta_c (point 1), component by component in one order, so that a double
// and SIMD lanes (hybrid/flow_lanes.hpp) give the same bits.
template <int N, class V, class S>
void hermite_state(int point, const V& x0, const V& f0, const V& x1, const V& f1, const S& h, V& out)
{
    if (point == 0)
        for (Eigen::Index i = 0; i < x0.size(); ++i) out[i] = (h00 * x0[i] + h01 * x1[i]) + h * (h10 * f0[i] + h11 * f1[i]);
    else
        for (Eigen::Index i = 0; i < x0.size(); ++i) out[i] = (h01 * x0[i] + h00 * x1[i]) - h * (h11 * f0[i] + h10 * f1[i]);
}

// How far g there (vc) lies from the cubic through the end samples (v, s per unit of theta),
// and what is tolerated: the change of g over the step, plus rounding of its values.
template <class T>
struct deviation {
    T error, allowed;
};
template <class T>
deviation<T> deviation_at(int point, const T& v0, const T& s0, const T& v1, const T& s1, const T& vc)
{
    using std::abs;
    const T predicted = point == 0 ? (h00 * v0 + h01 * v1) + (h10 * s0 + h11 * s1)
                                   : (h01 * v0 + h00 * v1) - (h11 * s0 + h10 * s1);
    const T scale = abs(v1 - v0) + 0.5 * (abs(s0) + abs(s1));
    const T rounding = 64.0 * std::numeric_limits<double>::epsilon() * (abs(v0) + abs(v1) + abs(vc));
    return {abs(vc - predicted), tolerance * scale + rounding};
}

// The factor of the step to take instead of one whose deviation is `d` (d.error > d.allowed):
// the cubic's error falls as h^4 against a scale in h, so as h^3 relative to it; kept in
// [0.1, 0.5] so that a step always shrinks and never collapses.
inline double step_factor(const deviation<double>& d)
{
    const double f = 0.9 * std::cbrt(d.allowed / d.error);
    return std::clamp(std::isfinite(f) ? f : 0.1, 0.1, 0.5);
}

}  // namespace vimpact::event_resolution
