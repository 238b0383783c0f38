#pragma once
// The paper's wake-induced vibro-impacting oscillator: a damped linear structure y coupled by
// acceleration coupling to a Van der Pol wake oscillator x (Facchinetti et al. 2004), with a
// rigid barrier at y = sigma and Newton's restitution law.
//
//   y' = ydot,  ydot' = a(X) = -delta^2 y - alpha ydot + M x
//   x' = xdot,  xdot' = -x - eps (x^2 - 1) xdot + A a(X)
//   delta = 1/(St Ur),  alpha = 2 xi delta + gamma/mu,  M = CL0 / (16 pi^2 St^2 mu)
//   surface "barrier": gap y - sigma; reset (y, ydot, x, xdot) -> (sigma, -r ydot, x, xdot)
//   contact (chattering ended): y = sigma, ydot = 0, the wake runs with a = 0; released
//   when a(X) > 0
//
// Every derivative is written by hand (the tests compare them with automatic
// differentiation); they are cheaper than the automatic ones in the tangent runs.
#include <array>
#include <numbers>
#include <span>
#include <string_view>

#include "vimpact/core/lane_ops.hpp"
#include "vimpact/core/state.hpp"
#include "vimpact/model/spec.hpp"

namespace vimpact {

// P: the type of the parameters, double; lanes (core/lanes.hpp) for the vector field of several
// jobs at once, each lane with its own parameters.
template <class P>
class basic_wake_impact {
public:
    static constexpr std::string_view name = "wake_impact";
    static constexpr std::string_view description =
        "the paper's wake-induced vibro-impacting oscillator: a damped cylinder y coupled by acceleration "
        "coupling to a Van der Pol wake oscillator x, with a rigid barrier at y = sigma";
    static constexpr std::array<state_variable, 4> state{{
        {"y", "cross-flow displacement of the cylinder", "D"},
        {"ydot", "its velocity dy/dt", "D"},
        {"x", "wake variable (reduced lift coefficient 2 CL/CL0)"},
        {"xdot", "its rate dx/dt"},
    }};
    // The paper does not state CL0; its numbers are reproduced with M = 0.05/mu, i.e.
    // CL0 = 0.05 * 16 pi^2 * 0.2^2 (docs/model.md).
    static constexpr double paper_CL0 = 0.05 * 16.0 * std::numbers::pi * std::numbers::pi * 0.04;
    static constexpr std::array<parameter, 10> parameters{{
        {"Ur", 16.0, "reduced velocity U/(f_n D)", above(0.0)},
        {"sigma", -0.150298, "barrier position", any_value(), "D"},
        {"r", 0.8, "coefficient of restitution", between(0.0, 1.0)},
        {"A", 12.0, "wake coupling coefficient", any_value()},
        {"eps", 0.3, "Van der Pol coefficient", at_least(0.0)},
        {"St", 0.2, "Strouhal number", above(0.0)},
        {"xi", 0.0052, "structural damping ratio", at_least(0.0)},
        {"gamma", 0.8, "stall parameter (fluid damping)", at_least(0.0)},
        {"mu", 1.19381, "mass ratio (m* + C_m) pi/4", above(0.0)},
        {"CL0", paper_CL0, "lift coefficient of the fixed cylinder", at_least(0.0)},
    }};
    static constexpr std::array<impact_surface, 1> surfaces{{{"barrier", "rigid barrier at y = sigma", true, true}}};
    static constexpr std::array<poincare_section, 2> sections{{
        {"maxima", crossing::down, "maxima of y: ydot = 0, ydot decreasing (the paper's Sigma)", true},
        {"minima", crossing::up, "minima of y: ydot = 0, ydot increasing", true},
    }};
    static constexpr std::array<double, 4> initial_state{0.0, 0.0, 0.0, 0.1};
    // Named parameter sets: the defaults are the "paper" preset.
    static constexpr std::array<preset<1>, 2> presets{{
        {"paper", "M = 0.05/mu at St = 0.2: the paper's grazing values and labels", {{{"CL0", paper_CL0}}}},
        {"facchinetti", "Facchinetti et al.'s CL0 = 0.3 (amplitudes about 8 % smaller)", {{{"CL0", 0.3}}}},
    }};

    // The vector field in SIMD lanes (hybrid/flow_lanes.hpp).
    using lanes_definition = basic_wake_impact<lanes>;

    explicit basic_wake_impact(std::span<const P> p)
        : m_sigma(p[1]), m_r(p[2]), m_A(p[3]), m_eps(p[4]),
          m_delta(1.0 / (p[5] * p[0])), m_delta2(m_delta * m_delta),
          m_alpha(2.0 * p[6] * m_delta + p[7] / p[8]),
          m_M(p[9] / (16.0 * std::numbers::pi * std::numbers::pi * p[5] * p[5] * p[8]))
    {
    }

    [[nodiscard]] P delta() const { return m_delta; }
    [[nodiscard]] P alpha() const { return m_alpha; }
    [[nodiscard]] P coupling_M() const { return m_M; }

    // The structural acceleration a(X): the force per unit mass on the cylinder.
    template <class T>
    [[nodiscard]] T free_acceleration(const vec_t<T, 4>& X) const
    {
        return -m_delta2 * X[0] - m_alpha * X[1] + m_M * X[2];
    }

    template <class T>
    [[nodiscard]] vec_t<T, 4> derivatives(const vec_t<T, 4>& X) const
    {
        const T a = free_acceleration(X);
        return {X[1], a, X[3], -X[2] - m_eps * (X[2] * X[2] - 1.0) * X[3] + m_A * a};
    }
    template <class T>
    [[nodiscard]] T gap(int, const vec_t<T, 4>& X) const { return X[0] - m_sigma; }
    template <class T>
    [[nodiscard]] vec_t<T, 4> reset(int, const vec_t<T, 4>& X) const
    {
        return {T(m_sigma), -m_r * X[1], X[2], X[3]};
    }
    template <class T>
    [[nodiscard]] T section(int k, const vec_t<T, 4>& X) const { return (void)k, X[1]; }

    template <class T>
    [[nodiscard]] vec_t<T, 4> sticking_derivatives(int, const vec_t<T, 4>& X) const
    {
        return {T(0.0), T(0.0), X[3], -X[2] - m_eps * (X[2] * X[2] - 1.0) * X[3]};
    }
    template <class T>
    [[nodiscard]] T release(int, const vec_t<T, 4>& X) const { return free_acceleration(X); }
    [[nodiscard]] vec<4> rest(int, const vec<4>& X) const { return {m_sigma, 0.0, X[2], X[3]}; }

    // ---- hand-written derivatives
    [[nodiscard]] mat<4> jacobian(const vec<4>& X) const
    {
        const double x = X[2], w = X[3];
        mat<4> J;
        J << 0.0, 1.0, 0.0, 0.0,                                               //
            -m_delta2, -m_alpha, m_M, 0.0,                                     //
            0.0, 0.0, 0.0, 1.0,                                                //
            -m_A * m_delta2, -m_A * m_alpha, m_A * m_M - 1.0 - 2.0 * m_eps * x * w,  //
            -m_eps * (x * x - 1.0);
        return J;
    }
    [[nodiscard]] vec<4> second_derivative(const vec<4>& X, const vec<4>& u, const vec<4>& v) const
    {
        const double x = X[2], w = X[3];
        return {0.0, 0.0, 0.0, -2.0 * m_eps * (w * u[2] * v[2] + x * (u[2] * v[3] + u[3] * v[2]))};
    }
    [[nodiscard]] double divergence(const vec<4>& X) const { return -m_alpha - m_eps * (X[2] * X[2] - 1.0); }
    // Templates, so that SIMD lanes screen their steps for events too (hybrid/flow_lanes.hpp).
    template <class T>
    [[nodiscard]] vec_t<T, 4> gap_gradient(int, const vec_t<T, 4>&) const
    {
        return {T(1.0), T(0.0), T(0.0), T(0.0)};
    }
    [[nodiscard]] mat<4> gap_hessian(int, const vec<4>&) const { return mat<4>::Zero(); }
    [[nodiscard]] mat<4> reset_jacobian(int, const vec<4>&) const
    {
        mat<4> R = mat<4>::Zero();
        R(1, 1) = -m_r;
        R(2, 2) = 1.0;
        R(3, 3) = 1.0;
        return R;
    }
    [[nodiscard]] vec<4> reset_second_derivative(int, const vec<4>&, const vec<4>&, const vec<4>&) const
    {
        return vec<4>::Zero();
    }
    template <class T>
    [[nodiscard]] vec_t<T, 4> section_gradient(int, const vec_t<T, 4>&) const
    {
        return {T(0.0), T(1.0), T(0.0), T(0.0)};
    }
    [[nodiscard]] vec<4> release_gradient(int, const vec<4>&) const { return {-m_delta2, -m_alpha, m_M, 0.0}; }

private:
    P m_sigma, m_r, m_A, m_eps;
    P m_delta, m_delta2, m_alpha, m_M;
};

using wake_impact = basic_wake_impact<double>;

}  // namespace vimpact
