#pragma once
// How a deviation from a reference orbit crosses an impact on surface i (the paper's Eq. 8
// and Appendix A, corrected).
//
// Notation: x is the reference state on the surface just before the reset, F = F(x),
// J = DF(x), F+ = F(R(x)), J+ = DF(R(x)), R' = DR(x), n = grad g(x), v_g = n . F < 0.
// A deviation y- of the reference at the impact time t_i (continued with the pre-impact field
// if the perturbed orbit hits later or earlier) becomes the deviation y+ of the post-impact
// orbit at t_i (continued with the post-impact field). The perturbed orbit reaches the surface
// after the flight time d = d1 + d2 + O(|y|^3).
//
// First order (saltation matrix, Eq. 8):   S = R' + (F+ - R' F) n^T / v_g,   y+ = S y-.
// Second order (transverse discontinuity mapping):
//   d1 = -(n . y) / v_g
//   d2 = -(1/v_g) [ d1 n.J y + d1^2/2 n.J F + 1/2 (y + d1 F)^T D2g (y + d1 F) ]
//   y+ = R' y + (d1 + d2)(R' F - F+) + d1 (R' J y - J+ R' y)
//        + d1^2 (1/2 R' J F - J+ R' F + 1/2 J+ F+) + 1/2 R''[y + d1 F, y + d1 F]
// obtained by expanding the perturbed flight x + y -> (flow for d) -> reset -> (flow for -d)
// to second order in y; the vector field's own second derivative cancels at this order.
#include <array>
#include <Eigen/Core>

#include "vimpact/core/names.hpp"
#include "vimpact/core/state.hpp"
#include "vimpact/model/engine_model.hpp"

namespace vimpact {

// What the tangent dynamics applies at an impact. Only `saltation` (linear) and
// `second_order` (finite deviations) are correct; the other two exist to show what goes wrong
// without the saltation correction (the trivial Floquet multiplier leaves 1).
enum class impact_tangent { saltation, second_order, reset_jacobian, identity };

constexpr std::string_view to_string(impact_tangent m)
{
    switch (m) {
        case impact_tangent::saltation: return "saltation";
        case impact_tangent::second_order: return "second-order";
        case impact_tangent::reset_jacobian: return "reset-jacobian";
        case impact_tangent::identity: return "identity";
    }
    return "unknown";
}
// The jumps a Floquet analysis may apply to its monodromy (as a linear map the second-order
// mapping is the saltation matrix).
inline constexpr std::array<impact_tangent, 3> monodromy_jumps{impact_tangent::saltation, impact_tangent::reset_jacobian,
                                                               impact_tangent::identity};

// Eq. 8: S = R' + (F+ - R' F) n^T / (n^T F), from the reset's Jacobian R', the fields before
// (F) and after (F+) and the normal n of the surface crossed. An impact's and a switching
// surface's (tangent/variational.hpp) crossing alike.
template <int N>
mat<N> saltation(const mat<N>& Rp, const vec<N>& F, const vec<N>& Fp, const vec<N>& n)
{
    return Rp + (Fp - Rp * F) * n.transpose() / n.dot(F);
}

// Eq. 8 at the pre-impact state x on surface i (crossed transversally, v_g != 0).
template <engine_model Model>
mat<Model::dim> saltation_matrix(const Model& m, int i, const vec<Model::dim>& x)
{
    return saltation<Model::dim>(m.reset_jacobian(i, x), m.rhs(x), m.rhs(m.reset(i, x)), m.gap_gradient(i, x));
}

// The tangent jump chosen by `mode` for linear deviations (second_order: as a linear map it
// is the saltation matrix).
template <engine_model Model>
mat<Model::dim> impact_jump_matrix(const Model& m, int i, const vec<Model::dim>& x, impact_tangent mode)
{
    switch (mode) {
        case impact_tangent::reset_jacobian: return m.reset_jacobian(i, x);
        case impact_tangent::identity: return mat<Model::dim>::Identity(x.size(), x.size());
        default: return saltation_matrix(m, i, x);
    }
}

// Everything the second-order mapping needs at one impact, computed once and applied to
// many deviation vectors.
template <int N>
struct impact_derivatives {
    int surface = 0;
    vec<N> x, F, Fp, n, RpF, Fp_minus_RpF;
    mat<N> J, Jp, Rp, H;               // H: the gap's Hessian
    double vg = 0.0;
    double nJF = 0.0;                  // n . J F
    vec<N> quad_coefficient;           // 1/2 R' J F - J+ R' F + 1/2 J+ F+
};

template <engine_model Model>
impact_derivatives<Model::dim> prepare_impact(const Model& m, int i, const vec<Model::dim>& x)
{
    impact_derivatives<Model::dim> d;
    d.surface = i;
    d.x = x;
    d.F = m.rhs(x);
    const vec<Model::dim> post = m.reset(i, x);
    d.Fp = m.rhs(post);
    d.n = m.gap_gradient(i, x);
    d.H = m.gap_hessian(i, x);
    d.J = m.jacobian(x);
    d.Jp = m.jacobian(post);
    d.Rp = m.reset_jacobian(i, x);
    d.vg = d.n.dot(d.F);
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
    // The flight-time quadratic  n.y + d (v_g + n.J y + y^T D2g F) + d^2/2 (n.J F + F^T D2g F)
    // + 1/2 y^T D2g y = 0  has no real root: the perturbed orbit turns back before reaching the
    // surface (it misses it). The map is still the second-order Taylor polynomial.
    bool misses = false;
};

// The second-order mapping of one finite deviation y.
template <engine_model Model>
second_order_jump<Model::dim> second_order_map(const Model& m, const impact_derivatives<Model::dim>& d,
                                               const vec<Model::dim>& y)
{
    constexpr int N = Model::dim;
    second_order_jump<N> out;
    const vec<N> Jy = d.J * y;
    const double ny = d.n.dot(y);
    out.d1 = -ny / d.vg;
    const vec<N> u = y + out.d1 * d.F;
    const double hess_u = u.dot(d.H * u);
    out.d2 = -(out.d1 * d.n.dot(Jy) + 0.5 * out.d1 * out.d1 * d.nJF + 0.5 * hess_u) / d.vg;
    const double delta = out.d1 + out.d2;
    const vec<N> Rpy = d.Rp * y;
    out.y_plus = Rpy - delta * d.Fp_minus_RpF + out.d1 * (d.Rp * Jy - d.Jp * Rpy) +
                 (out.d1 * out.d1) * d.quad_coefficient + 0.5 * m.reset_second_derivative(d.surface, d.x, u, u);

    const double a2 = 0.5 * (d.nJF + d.F.dot(d.H * d.F));
    const double a1 = d.vg + d.n.dot(Jy) + y.dot(d.H * d.F);
    const double a0 = ny + 0.5 * y.dot(d.H * y);
    out.misses = a1 * a1 - 4.0 * a2 * a0 < 0.0;
    return out;
}

template <engine_model Model>
second_order_jump<Model::dim> second_order_map(const Model& m, int i, const vec<Model::dim>& x,
                                               const vec<Model::dim>& y)
{
    return second_order_map(m, prepare_impact(m, i, x), y);
}

}  // namespace vimpact
