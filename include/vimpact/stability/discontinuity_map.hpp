#pragma once
// How a deviation from a reference orbit crosses an impact (SPEC §4, the paper's Eq. 8 and
// Appendix A, corrected).
//
// Notation: x is the reference state at the barrier just before the reset, F = F(x),
// J = DF(x), F+ = F(R(x)), J+ = DF(R(x)), R' = DR(x), n = grad H(x), v_H = n . F < 0.
// A deviation y- of the reference at the impact time t_i (continued with the pre-impact field
// if the perturbed orbit hits later or earlier) becomes the deviation y+ of the post-impact
// orbit at t_i (continued with the post-impact field). The perturbed orbit reaches the guard
// after the flight time d = d1 + d2 + O(|y|^3).
//
// First order (saltation matrix, Eq. 8):   S = R' + (F+ - R' F) n^T / v_H,   y+ = S y-.
// Second order (transverse discontinuity mapping):
//   d1 = -(n . y) / v_H
//   d2 = -(1/v_H) [ d1 n.J y + d1^2/2 n.J F + 1/2 (y + d1 F)^T D2H (y + d1 F) ]
//   y+ = R' y + (d1 + d2)(R' F - F+) + d1 (R' J y - J+ R' y)
//        + d1^2 (1/2 R' J F - J+ R' F + 1/2 J+ F+) + 1/2 R''[y + d1 F, y + d1 F]
// obtained by expanding the perturbed flight x + y -> (flow for d) -> reset -> (flow for -d)
// to second order in y; the vector field's own second derivative cancels at this order.
#include <cmath>

#include <Eigen/Core>

#include "vimpact/core/state.hpp"
#include "vimpact/model/concepts.hpp"

namespace vimpact {

// What the tangent dynamics applies at an impact. Only `saltation` (linear) and
// `second_order` (finite deviations) are correct; the other two exist to show what goes wrong
// without the saltation correction (the trivial Floquet multiplier leaves 1).
enum class impact_tangent { saltation, second_order, reset_jacobian, identity };

constexpr const char* to_string(impact_tangent m)
{
    switch (m) {
        case impact_tangent::saltation: return "saltation";
        case impact_tangent::second_order: return "second-order";
        case impact_tangent::reset_jacobian: return "reset-jacobian";
        case impact_tangent::identity: return "identity";
    }
    return "unknown";
}

template <class M>
concept saltation_model = hybrid_model<M> && has_reset_jacobian<M>;

template <class M>
concept second_order_model = saltation_model<M> && has_jacobian<M> && has_guard_hessian<M> &&
                             has_reset_second_derivative<M>;

// Eq. 8 at the pre-impact state x (the guard must be crossed transversally, v_H != 0).
template <saltation_model Model>
mat<Model::dim> saltation_matrix(const Model& m, const vec<Model::dim>& x)
{
    const vec<Model::dim> F = m.rhs(x);
    const vec<Model::dim> Fp = m.rhs(m.reset(x));
    const mat<Model::dim> Rp = m.reset_jacobian(x);
    const vec<Model::dim> n = m.guard_gradient(x);
    return Rp + (Fp - Rp * F) * n.transpose() / n.dot(F);
}

// The tangent jump chosen by `mode` for linear deviations (second_order falls back to
// saltation here: as a linear map it is the saltation matrix).
template <saltation_model Model>
mat<Model::dim> impact_jump_matrix(const Model& m, const vec<Model::dim>& x, impact_tangent mode)
{
    switch (mode) {
        case impact_tangent::reset_jacobian: return m.reset_jacobian(x);
        case impact_tangent::identity: return mat<Model::dim>::Identity();
        default: return saltation_matrix(m, x);
    }
}

// Everything the second-order mapping needs at one impact, computed once and applied to
// many deviation vectors.
template <int N>
struct impact_derivatives {
    vec<N> x, F, Fp, n, RpF, Fp_minus_RpF;
    mat<N> J, Jp, Rp;
    double vH = 0.0;
    double nJF = 0.0;                  // n . J F
    vec<N> quad_coefficient;           // 1/2 R' J F - J+ R' F + 1/2 J+ F+
};

template <second_order_model Model>
impact_derivatives<Model::dim> prepare_impact(const Model& m, const vec<Model::dim>& x)
{
    impact_derivatives<Model::dim> d;
    d.x = x;
    d.F = m.rhs(x);
    const vec<Model::dim> post = m.reset(x);
    d.Fp = m.rhs(post);
    d.n = m.guard_gradient(x);
    d.J = m.jacobian(x);
    d.Jp = m.jacobian(post);
    d.Rp = m.reset_jacobian(x);
    d.vH = d.n.dot(d.F);
    d.nJF = d.n.dot(d.J * d.F);
    d.RpF = d.Rp * d.F;
    d.Fp_minus_RpF = d.Fp - d.RpF;
    d.quad_coefficient = 0.5 * (d.Rp * (d.J * d.F)) - d.Jp * d.RpF + 0.5 * (d.Jp * d.Fp);
    return d;
}

template <int N>
struct second_order_jump {
    vec<N> y_plus;
    double d1 = 0.0;        // first-order flight time
    double d2 = 0.0;        // its second-order correction
    // The flight-time quadratic  n.y + d (v_H + n.J y + y^T D2H F) + d^2/2 (n.J F + F^T D2H F)
    // + 1/2 y^T D2H y = 0  has no real root: the perturbed orbit turns back before reaching the
    // guard (it misses the barrier). The map is still the second-order Taylor polynomial.
    bool misses = false;
};

// The second-order mapping of one finite deviation y.
template <second_order_model Model>
second_order_jump<Model::dim> second_order_map(const Model& m, const impact_derivatives<Model::dim>& d,
                                               const vec<Model::dim>& y)
{
    constexpr int N = Model::dim;
    second_order_jump<N> out;
    const vec<N> Jy = d.J * y;
    const double ny = d.n.dot(y);
    out.d1 = -ny / d.vH;
    const vec<N> u = y + out.d1 * d.F;
    const double hess_u = m.guard_hessian(d.x, u, u);
    out.d2 = -(out.d1 * d.n.dot(Jy) + 0.5 * out.d1 * out.d1 * d.nJF + 0.5 * hess_u) / d.vH;
    const double delta = out.d1 + out.d2;
    const vec<N> Rpy = d.Rp * y;
    out.y_plus = Rpy - delta * d.Fp_minus_RpF + out.d1 * (d.Rp * Jy - d.Jp * Rpy) +
                 (out.d1 * out.d1) * d.quad_coefficient +
                 0.5 * m.reset_second_derivative(d.x, u, u);

    const double a2 = 0.5 * (d.nJF + m.guard_hessian(d.x, d.F, d.F));
    const double a1 = d.vH + d.n.dot(Jy) + m.guard_hessian(d.x, y, d.F);
    const double a0 = ny + 0.5 * m.guard_hessian(d.x, y, y);
    out.misses = a1 * a1 - 4.0 * a2 * a0 < 0.0;
    return out;
}

template <second_order_model Model>
second_order_jump<Model::dim> second_order_map(const Model& m, const vec<Model::dim>& x,
                                               const vec<Model::dim>& y)
{
    return second_order_map(m, prepare_impact(m, x), y);
}

}  // namespace vimpact
