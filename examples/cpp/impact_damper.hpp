#pragma once
// An impact damper: a harmonically forced primary oscillator with a free ball of mass ratio mu
// in a cavity of clearance 2 d. Between impacts (time in units of 1 / natural frequency)
//
//   x1'' + 2 zeta x1' + x1 = a cos(phi),   phi' = w      (the primary)
//   x2'' = 0                                               (the ball, free flight)
//
// and the ball hits the cavity's walls when |x2 - x1| = d: surfaces "right" (gap d - (x2 - x1))
// and "left" (gap (x2 - x1) + d). An impact keeps the momentum v1 + mu v2 and reverses the
// relative velocity u = v2 - v1 with restitution r:
//
//   v1+ = v1 + mu (1 + r) u / (1 + mu),   v2+ = v2 - (1 + r) u / (1 + mu).
//
// Everything vimpact needs besides these lines (Jacobians, second derivatives, gap gradients
// and Hessians, reset Jacobians and second derivatives) comes from automatic differentiation
// of the templates below.
#include <array>
#include <cmath>
#include <numbers>
#include <span>
#include <string_view>

#include <vimpact/model/definition.hpp>

struct impact_damper {
    static constexpr std::string_view name = "impact_damper";
    static constexpr std::string_view description =
        "a forced primary oscillator with a free ball in a cavity of clearance 2 d (momentum exchange at impacts)";
    static constexpr std::array<vimpact::state_variable, 5> state{{
        {"x1", "primary displacement"},
        {"v1", "primary velocity"},
        {"x2", "ball displacement"},
        {"v2", "ball velocity"},
        {"phi", "forcing phase", "rad", 2.0 * std::numbers::pi},
    }};
    static constexpr std::array<vimpact::parameter, 6> parameters{{
        {"zeta", 0.05, "damping ratio of the primary", vimpact::at_least(0.0)},
        {"a", 1.0, "forcing amplitude", vimpact::any_value()},
        {"w", 1.2, "forcing frequency / natural frequency", vimpact::above(0.0)},
        {"mu", 0.1, "ball mass / primary mass", vimpact::above(0.0)},
        {"d", 2.0, "half the clearance of the cavity", vimpact::above(0.0)},
        {"r", 0.6, "coefficient of restitution", vimpact::between(0.0, 1.0)},
    }};
    static constexpr std::array<vimpact::impact_surface, 2> surfaces{{
        // affine: each gap is linear in the state, so the integrator resolves it on every step
        {"right", "the ball hits the cavity's right wall", false, true},
        {"left", "the ball hits the cavity's left wall", false, true},
    }};
    static constexpr std::array<vimpact::poincare_section, 1> sections{{
        {"strobe", vimpact::crossing::up, "once per forcing period (phi = 0 mod 2 pi)"},
    }};
    static constexpr std::array<double, 5> initial_state{0.0, 0.0, 0.0, 0.0, 0.0};

    double zeta, a, w, mu, d, r;
    explicit impact_damper(std::span<const double> p) : zeta(p[0]), a(p[1]), w(p[2]), mu(p[3]), d(p[4]), r(p[5]) {}

    template <class T>
    vimpact::vec_t<T, 5> derivatives(const vimpact::vec_t<T, 5>& x) const
    {
        using std::cos;
        return {x[1], -2.0 * zeta * x[1] - x[0] + a * cos(x[4]), x[3], T(0.0), T(w)};
    }
    template <class T>
    T gap(int i, const vimpact::vec_t<T, 5>& x) const
    {
        const T relative = x[2] - x[0];
        return i == 0 ? T(d - relative) : T(relative + d);
    }
    template <class T>
    vimpact::vec_t<T, 5> reset(int, const vimpact::vec_t<T, 5>& x) const
    {
        const T u = x[3] - x[1];
        vimpact::vec_t<T, 5> y = x;
        y[1] = x[1] + mu * (1.0 + r) * u / (1.0 + mu);
        y[3] = x[3] - (1.0 + r) * u / (1.0 + mu);
        return y;
    }
    template <class T>
    T section(int, const vimpact::vec_t<T, 5>& x) const
    {
        using std::sin;
        return sin(x[4]);
    }
};
