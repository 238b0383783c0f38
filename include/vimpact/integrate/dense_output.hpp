#pragma once
// Dense output of one Runge-Kutta step on [t0, t0 + h] in the nested form used by the
// Dormand-Prince interpolants:
//   x(t0 + theta h) = x0 + p0(c0 + p1(c1 + p2(c2 + ...)))   with p_j = theta (j even), 1 - theta (j odd)
// The time derivative of the polynomial comes with it, so events can be located by Newton's
// method on the interpolant itself.
#include <array>

#include "vimpact/core/state.hpp"

namespace vimpact {

template <int N, int K>
struct dense_segment {
    double t0 = 0.0;
    double h = 0.0;
    vec<N> x0;
    std::array<vec<N>, K> c;

    [[nodiscard]] double t1() const { return t0 + h; }
    [[nodiscard]] double theta(double t) const { return (t - t0) / h; }

    [[nodiscard]] vec<N> value_at(double theta) const
    {
        vec<N> out = x0;
        value_at(theta, out);
        return out;
    }

    // The same into `out` (sized as x0), with no temporary: the runtime-sized flow calls it on
    // every step and allocates nothing. The Horner sum runs in `out` itself; each component sees
    // the same operations in the same order as in the expression form, so the bits are those.
    void value_at(double theta, vec<N>& out) const
    {
        out = c[K - 1];
        for (int j = K - 1; j >= 1; --j) {
            const double p = (j % 2 == 0) ? theta : 1.0 - theta;
            out = c[j - 1] + p * out;
        }
        out = x0 + theta * out;
    }

    // Value and d/dtheta at theta (divide the derivative by h for d/dt), into outputs sized as
    // x0; the outputs carry the sums, so nothing is allocated.
    void value_and_slope(double theta, vec<N>& value, vec<N>& slope) const
    {
        value = c[K - 1];  // the sum s
        slope.setZero(value.size());  // its derivative ds
        for (int j = K - 1; j >= 1; --j) {
            const bool even = (j % 2 == 0);
            const double p = even ? theta : 1.0 - theta;
            const double dp = even ? 1.0 : -1.0;
            slope = dp * value + p * slope;
            value = c[j - 1] + p * value;
        }
        slope = value + theta * slope;  // before value, which still holds s
        value = x0 + theta * value;
    }

    [[nodiscard]] vec<N> value(double t) const { return value_at(theta(t)); }
};

}  // namespace vimpact
