#pragma once
// The paper's wake-induced vibro-impacting oscillator: a damped linear structure y coupled by
// acceleration coupling to a Van der Pol wake oscillator x (Facchinetti et al. 2004), with a
// rigid barrier at y = sigma and Newton's restitution law.
//
//   y' = v,  v' = a(X) = -delta^2 y - alpha v + M x
//   x' = w,  w' = -x - eps (x^2 - 1) w + A a(X)
//   delta = 1/(St Ur),  alpha = 2 xi delta + gamma/mu,  M = CL0 / (16 pi^2 St^2 mu)
//   impact when y decreases through sigma; reset (y, v, x, w) -> (sigma, -r v, x, w)
#include <array>
#include <numbers>
#include <string>
#include <string_view>

#include "vimpact/core/state.hpp"
#include "vimpact/model/parameter.hpp"

namespace vimpact {

struct wake_impact_parameters {
    double Ur = 16.0;         // reduced flow velocity
    double sigma = -0.150298; // barrier position (the paper's grazing value at Ur = 25)
    double r = 0.8;           // coefficient of restitution
    double A = 12.0;          // wake coupling coefficient
    double eps = 0.3;         // Van der Pol coefficient
    double St = 0.2;          // Strouhal number
    double xi = 0.0052;       // structural damping ratio
    double gamma = 0.8;       // stall parameter (fluid damping)
    double mu = 1.19381;      // mass ratio (m* + C_m) pi / 4
    // Lift coefficient of the fixed cylinder. The paper does not state it; its numbers are
    // reproduced with M = 0.05/mu, i.e. CL0 = 0.05 * 16 pi^2 * 0.2^2 (see docs/model.md).
    double CL0 = 0.05 * 16.0 * std::numbers::pi * std::numbers::pi * 0.04;
};

// Named presets: "paper" (default, M = 0.05/mu at St = 0.2) and "facchinetti" (CL0 = 0.3).
wake_impact_parameters wake_impact_preset(std::string_view name);
std::string wake_impact_preset_names();

inline const std::array<parameter_info<wake_impact_parameters>, 10>& wake_impact_parameter_table()
{
    using P = wake_impact_parameters;
    static const std::array<parameter_info<P>, 10> table{{
        {"Ur", "reduced velocity", &P::Ur, 0.0, false, unbounded, false},
        {"sigma", "barrier position", &P::sigma, -unbounded, false, unbounded, false},
        {"r", "coefficient of restitution", &P::r, 0.0, true, 1.0, true},
        {"A", "wake coupling coefficient", &P::A, -unbounded, false, unbounded, false},
        {"eps", "Van der Pol coefficient", &P::eps, 0.0, true, unbounded, false},
        {"St", "Strouhal number", &P::St, 0.0, false, unbounded, false},
        {"xi", "structural damping ratio", &P::xi, 0.0, true, unbounded, false},
        {"gamma", "stall parameter", &P::gamma, 0.0, true, unbounded, false},
        {"mu", "mass ratio", &P::mu, 0.0, false, unbounded, false},
        {"CL0", "lift coefficient of the fixed cylinder", &P::CL0, 0.0, true, unbounded, false},
    }};
    return table;
}

class wake_impact {
public:
    static constexpr int dim = 4;
    static constexpr int position = 0;
    static constexpr int velocity = 1;
    using state = vec<4>;
    using parameters = wake_impact_parameters;

    // Throws input_error when a parameter is outside its valid range.
    explicit wake_impact(const wake_impact_parameters& p = {});

    [[nodiscard]] const wake_impact_parameters& params() const { return m_p; }
    [[nodiscard]] wake_impact with(std::string_view name, double value) const;

    [[nodiscard]] double delta() const { return m_delta; }
    [[nodiscard]] double alpha() const { return m_alpha; }
    [[nodiscard]] double coupling_M() const { return m_M; }
    [[nodiscard]] double barrier() const { return m_p.sigma; }
    [[nodiscard]] double restitution() const { return m_p.r; }

    // Structural acceleration a(X): the force per unit mass on the cylinder.
    [[nodiscard]] double free_acceleration(const state& X) const
    {
        return -m_delta2 * X[0] - m_alpha * X[1] + m_M * X[2];
    }
    [[nodiscard]] state free_acceleration_gradient(const state&) const
    {
        return {-m_delta2, -m_alpha, m_M, 0.0};
    }

    [[nodiscard]] state rhs(const state& X) const
    {
        const double a = free_acceleration(X);
        const double x = X[2], w = X[3];
        return {X[1], a, w, -x - m_p.eps * (x * x - 1.0) * w + m_p.A * a};
    }

    [[nodiscard]] mat<4> jacobian(const state& X) const
    {
        const double x = X[2], w = X[3], A = m_p.A, eps = m_p.eps;
        mat<4> J;
        J << 0.0, 1.0, 0.0, 0.0,                                                 //
            -m_delta2, -m_alpha, m_M, 0.0,                                       //
            0.0, 0.0, 0.0, 1.0,                                                  //
            -A * m_delta2, -A * m_alpha, A * m_M - 1.0 - 2.0 * eps * x * w,      //
            -eps * (x * x - 1.0);
        return J;
    }

    // Second derivative of the vector field as the bilinear form D2F(X)[u, v].
    [[nodiscard]] state second_derivative(const state& X, const state& u, const state& v) const
    {
        const double x = X[2], w = X[3], eps = m_p.eps;
        const double d4 = -2.0 * eps * (w * u[2] * v[2] + x * (u[2] * v[3] + u[3] * v[2]));
        return {0.0, 0.0, 0.0, d4};
    }

    [[nodiscard]] double divergence(const state& X) const
    {
        return -m_alpha - m_p.eps * (X[2] * X[2] - 1.0);
    }

    [[nodiscard]] double guard(const state& X) const { return X[0] - m_p.sigma; }
    [[nodiscard]] state guard_gradient(const state&) const { return {1.0, 0.0, 0.0, 0.0}; }

    [[nodiscard]] state reset(const state& X) const
    {
        return {m_p.sigma, -m_p.r * X[1], X[2], X[3]};
    }
    [[nodiscard]] mat<4> reset_jacobian(const state&) const
    {
        mat<4> R = mat<4>::Zero();
        R(1, 1) = -m_p.r;
        R(2, 2) = 1.0;
        R(3, 3) = 1.0;
        return R;
    }
    // The guard and the reset are affine, so their second derivatives vanish.
    [[nodiscard]] double guard_hessian(const state&, const state&, const state&) const { return 0.0; }
    [[nodiscard]] state reset_second_derivative(const state&, const state&, const state&) const
    {
        return state::Zero();
    }

    // Sticking phase: the structure rests on the barrier (y = sigma, v = 0) while the wake
    // evolves with a = 0 in its equation.
    [[nodiscard]] state sticking_rhs(const state& X) const
    {
        const double x = X[2], w = X[3];
        return {0.0, 0.0, w, -x - m_p.eps * (x * x - 1.0) * w};
    }

    // Coordinates that identify a point on the section v = 0 (used for period detection).
    [[nodiscard]] vec<3> section_coordinates(const state& X) const { return {X[0], X[2], X[3]}; }

    static constexpr std::array<std::string_view, 4> state_names{"y", "v", "x", "w"};

private:
    wake_impact_parameters m_p;
    double m_delta = 0, m_delta2 = 0, m_alpha = 0, m_M = 0;
};

}  // namespace vimpact
