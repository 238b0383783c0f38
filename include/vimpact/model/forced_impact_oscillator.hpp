#pragma once
// The classic harmonically forced linear impact oscillator, in autonomous form with a phase:
//
//   y' = v,  v' = -y - 2 zeta v + F cos(theta),  theta' = omega
//   impact when y decreases through sigma; reset (y, v, theta) -> (sigma, -r v, theta)
//
// Between impacts the flow is known in closed form, so event times, impacting periodic orbits
// and their stability can be checked against exact values.
#include <array>
#include <cmath>
#include <numbers>
#include <string_view>

#include "vimpact/core/state.hpp"
#include "vimpact/model/parameter.hpp"

namespace vimpact {

struct forced_impact_parameters {
    double zeta = 0.05;   // damping ratio
    double omega = 0.8;   // forcing frequency / natural frequency
    double F = 1.0;       // forcing amplitude
    double sigma = -1.0;  // barrier position
    double r = 0.8;       // coefficient of restitution
};

inline const std::array<parameter_info<forced_impact_parameters>, 5>&
forced_impact_parameter_table()
{
    using P = forced_impact_parameters;
    static const std::array<parameter_info<P>, 5> table{{
        {"zeta", "damping ratio", &P::zeta, 0.0, true, 1.0, false},
        {"omega", "forcing frequency", &P::omega, 0.0, false, unbounded, false},
        {"F", "forcing amplitude", &P::F, -unbounded, false, unbounded, false},
        {"sigma", "barrier position", &P::sigma, -unbounded, false, unbounded, false},
        {"r", "coefficient of restitution", &P::r, 0.0, true, 1.0, true},
    }};
    return table;
}

class forced_impact_oscillator {
public:
    static constexpr int dim = 3;
    static constexpr int position = 0;
    static constexpr int velocity = 1;
    using state = vec<3>;
    using parameters = forced_impact_parameters;

    explicit forced_impact_oscillator(const forced_impact_parameters& p = {}) : m_p(p)
    {
        validate_parameters(m_p, forced_impact_parameter_table());
    }

    [[nodiscard]] const forced_impact_parameters& params() const { return m_p; }
    [[nodiscard]] double barrier() const { return m_p.sigma; }
    [[nodiscard]] double restitution() const { return m_p.r; }

    [[nodiscard]] double free_acceleration(const state& X) const
    {
        return -X[0] - 2.0 * m_p.zeta * X[1] + m_p.F * std::cos(X[2]);
    }
    [[nodiscard]] state free_acceleration_gradient(const state& X) const
    {
        return {-1.0, -2.0 * m_p.zeta, -m_p.F * std::sin(X[2])};
    }

    [[nodiscard]] state rhs(const state& X) const
    {
        return {X[1], free_acceleration(X), m_p.omega};
    }

    [[nodiscard]] mat<3> jacobian(const state& X) const
    {
        mat<3> J;
        J << 0.0, 1.0, 0.0,                                        //
            -1.0, -2.0 * m_p.zeta, -m_p.F * std::sin(X[2]),        //
            0.0, 0.0, 0.0;
        return J;
    }

    [[nodiscard]] state second_derivative(const state& X, const state& u, const state& v) const
    {
        return {0.0, -m_p.F * std::cos(X[2]) * u[2] * v[2], 0.0};
    }

    [[nodiscard]] double divergence(const state&) const { return -2.0 * m_p.zeta; }

    [[nodiscard]] double guard(const state& X) const { return X[0] - m_p.sigma; }
    [[nodiscard]] state guard_gradient(const state&) const { return {1.0, 0.0, 0.0}; }
    [[nodiscard]] state reset(const state& X) const { return {m_p.sigma, -m_p.r * X[1], X[2]}; }
    [[nodiscard]] mat<3> reset_jacobian(const state&) const
    {
        mat<3> R = mat<3>::Zero();
        R(1, 1) = -m_p.r;
        R(2, 2) = 1.0;
        return R;
    }
    // The guard and the reset are affine, so their second derivatives vanish.
    [[nodiscard]] double guard_hessian(const state&, const state&, const state&) const { return 0.0; }
    [[nodiscard]] state reset_second_derivative(const state&, const state&, const state&) const
    {
        return state::Zero();
    }

    // b - a with the phase difference taken modulo 2 pi into (-pi, pi]: states one forcing
    // period apart are the same point of the cylinder.
    [[nodiscard]] state state_difference(const state& b, const state& a) const
    {
        state d = b - a;
        constexpr double two_pi = 2.0 * std::numbers::pi;
        d[2] -= two_pi * std::round(d[2] / two_pi);
        return d;
    }

    [[nodiscard]] state sticking_rhs(const state&) const { return {0.0, 0.0, m_p.omega}; }

    // The phase enters through (cos, sin) so that points one forcing period apart coincide.
    [[nodiscard]] vec<3> section_coordinates(const state& X) const
    {
        return {X[0], std::cos(X[2]), std::sin(X[2])};
    }

    static constexpr std::array<std::string_view, 3> state_names{"y", "v", "theta"};

private:
    forced_impact_parameters m_p;
};

}  // namespace vimpact
