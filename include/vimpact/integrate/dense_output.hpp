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
        vec<N> s = c[K - 1];
        for (int j = K - 1; j >= 1; --j) {
            const double p = (j % 2 == 0) ? theta : 1.0 - theta;
            s = c[j - 1] + p * s;
        }
        return x0 + theta * s;
    }

    // Value and d/dtheta at theta (divide the derivative by h for d/dt).
    void value_and_slope(double theta, vec<N>& value, vec<N>& slope) const
    {
        vec<N> s = c[K - 1];
        vec<N> ds = vec<N>::Zero(s.size());
        for (int j = K - 1; j >= 1; --j) {
            const bool even = (j % 2 == 0);
            const double p = even ? theta : 1.0 - theta;
            const double dp = even ? 1.0 : -1.0;
            ds = dp * s + p * ds;
            s = c[j - 1] + p * s;
        }
        value = x0 + theta * s;
        slope = s + theta * ds;
    }

    [[nodiscard]] vec<N> value(double t) const { return value_at(theta(t)); }
};

}  // namespace vimpact
