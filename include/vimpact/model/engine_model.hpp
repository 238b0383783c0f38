#pragma once
// What the hybrid flow and the tangent machinery call: a model with every derivative filled
// in, the parameters bound. Two kinds satisfy it: native_model<D> (a C++ definition compiled
// into the caller, derivatives by automatic differentiation where not hand-written) and
// table_model<N> (a compiled model file or plugin, called through its function table).
//
// Conventions: surfaces i = 0 .. surface_count() - 1, each a gap g_i >= 0 and a reset R_i;
// sections k = 0 .. section_count() - 1, each the zero crossings of s_k in section_direction(k).
// Second derivatives are bilinear forms D2f(x)[u, w]; gap Hessians full matrices.
#include <concepts>

#include "vimpact/core/state.hpp"
#include "vimpact/core/switch_sides.hpp"
#include "vimpact/model/spec.hpp"

namespace vimpact {

template <class M>
concept engine_model = requires(const M& m, const vec<M::dim>& x, int i) {
    { M::dim } -> std::convertible_to<int>;
    { m.surface_count() } -> std::convertible_to<int>;
    { m.section_count() } -> std::convertible_to<int>;
    { m.rhs(x) } -> std::convertible_to<vec<M::dim>>;
    { m.jacobian(x) } -> std::convertible_to<mat<M::dim>>;
    { m.second_derivative(x, x, x) } -> std::convertible_to<vec<M::dim>>;
    { m.divergence(x) } -> std::convertible_to<double>;
    { m.gap(i, x) } -> std::convertible_to<double>;
    { m.gap_gradient(i, x) } -> std::convertible_to<vec<M::dim>>;
    { m.gap_hessian(i, x) } -> std::convertible_to<mat<M::dim>>;
    { m.reset(i, x) } -> std::convertible_to<vec<M::dim>>;
    { m.reset_jacobian(i, x) } -> std::convertible_to<mat<M::dim>>;
    { m.reset_second_derivative(i, x, x, x) } -> std::convertible_to<vec<M::dim>>;
    { m.section(i, x) } -> std::convertible_to<double>;
    { m.section_gradient(i, x) } -> std::convertible_to<vec<M::dim>>;
    { m.section_direction(i) } -> std::convertible_to<crossing>;
    { m.sticks(i) } -> std::convertible_to<bool>;
    { m.sticking_rhs(i, x) } -> std::convertible_to<vec<M::dim>>;
    { m.release(i, x) } -> std::convertible_to<double>;
    { m.release_gradient(i, x) } -> std::convertible_to<vec<M::dim>>;
    { m.rest(i, x) } -> std::convertible_to<vec<M::dim>>;
    { m.state_difference(x, x) } -> std::convertible_to<vec<M::dim>>;
};

// A model with switching surfaces (model/spec.hpp, switching_surface): switching function
// h_k, its gradient and derivative along a direction, the sides its field is evaluated on
// (core/switch_sides.hpp), pinned by the flow that holds them, and the crossing of switch k,
// which changes its side and maps the state by the switch's reset where one applies (true
// then). The saltation of a crossing is formed from these (tangent/variational.hpp).
template <class M>
concept switching_model = requires(M& mm, const M& m, const vec<M::dim>& x, vec<M::dim>& out, int k) {
    { m.switch_count() } -> std::convertible_to<int>;
    { m.switch_direction(k) } -> std::convertible_to<crossing>;
    { m.switching_affine(k) } -> std::convertible_to<bool>;
    { m.switching(k, x) } -> std::convertible_to<double>;
    { m.switching_gradient(k, x) } -> std::convertible_to<vec<M::dim>>;
    { m.switching_derivative(k, x, x) } -> std::convertible_to<double>;
    { m.sides_at(x) } -> std::convertible_to<switch_sides>;
    { m.switch_reset_jacobian(k, x) } -> std::convertible_to<mat<M::dim>>;
    mm.pin_sides(switch_sides{});
    { mm.cross(k, x, out) } -> std::convertible_to<bool>;
};

template <class M>
int switch_count(const M& m)
{
    if constexpr (switching_model<M>) return m.switch_count();
    else return (void)m, 0;
}

// The state dimension of an engine model: its compile-time dim, or, for a model whose states
// are sized at run time (dim == Eigen::Dynamic: table_model<Eigen::Dynamic>), its own count.
template <class M>
int state_dim(const M& m)
{
    if constexpr (M::dim != Eigen::Dynamic) return M::dim;
    else return m.runtime_dim();
}

// Directional derivatives dg_i/dx v and ds_k/dx v: what event location needs of a gap or a
// section (its rate along the flow, its slope along an interpolant). A model may provide them
// itself when they cost less than a gradient (automatic differentiation along one direction
// costs two evaluations; a whole gradient N + 1).
template <engine_model M>
double gap_derivative(const M& m, int i, const vec<M::dim>& x, const vec<M::dim>& v)
{
    if constexpr (requires { { m.gap_derivative(i, x, v) } -> std::convertible_to<double>; })
        return m.gap_derivative(i, x, v);
    else return m.gap_gradient(i, x).dot(v);
}

template <engine_model M>
double section_derivative(const M& m, int k, const vec<M::dim>& x, const vec<M::dim>& v)
{
    if constexpr (requires { { m.section_derivative(k, x, v) } -> std::convertible_to<double>; })
        return m.section_derivative(k, x, v);
    else return m.section_gradient(k, x).dot(v);
}

// The rate of gap i along the flow, g_i' = grad g_i . F, and its gradient H_i F + J^T grad g_i:
// its upward zeros are the minima of the gap (grazing), its downward zeros the maxima.
template <engine_model M>
double gap_rate(const M& m, int i, const vec<M::dim>& x)
{
    if constexpr (requires { { m.gap_rate(i, x) } -> std::convertible_to<double>; }) return m.gap_rate(i, x);
    else return gap_derivative(m, i, x, m.rhs(x));
}

// A gradient, a reset, the field or its Jacobian written into `out`: a model whose states are
// sized at run time writes there without a temporary (the flow and the tangent field keep
// `out` from one call to the next).
template <engine_model M>
void gap_gradient_into(const M& m, int i, const vec<M::dim>& x, vec<M::dim>& out)
{
    if constexpr (requires { m.gap_gradient_into(i, x, out); }) m.gap_gradient_into(i, x, out);
    else out = m.gap_gradient(i, x);
}
template <engine_model M>
void rhs_into(const M& m, const vec<M::dim>& x, vec<M::dim>& out)
{
    if constexpr (requires { m.rhs_into(x, out); }) m.rhs_into(x, out);
    else out = m.rhs(x);
}
template <engine_model M>
void jacobian_into(const M& m, const vec<M::dim>& x, mat<M::dim>& out)
{
    if constexpr (requires { m.jacobian_into(x, out); }) m.jacobian_into(x, out);
    else out = m.jacobian(x);
}
template <engine_model M>
void section_gradient_into(const M& m, int k, const vec<M::dim>& x, vec<M::dim>& out)
{
    if constexpr (requires { m.section_gradient_into(k, x, out); }) m.section_gradient_into(k, x, out);
    else out = m.section_gradient(k, x);
}
template <engine_model M>
void reset_into(const M& m, int i, const vec<M::dim>& x, vec<M::dim>& out)
{
    if constexpr (requires { m.reset_into(i, x, out); }) m.reset_into(i, x, out);
    else out = m.reset(i, x);
}

// A model may provide these itself when it knows a cheaper form (the tangent flow does: its
// gaps read the reference state only).
template <engine_model M>
vec<M::dim> gap_rate_gradient(const M& m, int i, const vec<M::dim>& x)
{
    if constexpr (requires { { m.gap_rate_gradient(i, x) } -> std::convertible_to<vec<M::dim>>; })
        return m.gap_rate_gradient(i, x);
    else return m.gap_hessian(i, x) * m.rhs(x) + m.jacobian(x).transpose() * m.gap_gradient(i, x);
}

// The gradient of F_j, the rate of state variable j (its zeros are the extrema of x_j).
template <engine_model M>
vec<M::dim> state_rate_gradient(const M& m, int j, const vec<M::dim>& x)
{
    if constexpr (requires { { m.state_rate_gradient(j, x) } -> std::convertible_to<vec<M::dim>>; })
        return m.state_rate_gradient(j, x);
    else return m.jacobian(x).row(j).transpose();
}

// Whether gap i (section k) is an affine function of the state, as the model declares
// (model/spec.hpp, impact_surface::affine); a model that says nothing declares none.
template <engine_model M>
bool gap_is_affine(const M& m, int i)
{
    if constexpr (requires { { m.gap_affine(i) } -> std::convertible_to<bool>; }) return m.gap_affine(i);
    else return false;
}
template <engine_model M>
bool section_is_affine(const M& m, int k)
{
    if constexpr (requires { { m.section_affine(k) } -> std::convertible_to<bool>; }) return m.section_affine(k);
    else return false;
}

// A state is admissible when every gap is positive, or zero and not decreasing.
template <engine_model M>
bool admissible(const M& m, const vec<M::dim>& x)
{
    for (int i = 0; i < m.surface_count(); ++i) {
        const double g = m.gap(i, x);
        if (g < 0.0 || (g == 0.0 && gap_rate(m, i, x) < 0.0)) return false;
    }
    return true;
}

// The first surface the state lies beyond (or on, moving in), -1 if none.
template <engine_model M>
int violated_surface(const M& m, const vec<M::dim>& x)
{
    for (int i = 0; i < m.surface_count(); ++i) {
        const double g = m.gap(i, x);
        if (g < 0.0 || (g == 0.0 && gap_rate(m, i, x) < 0.0)) return i;
    }
    return -1;
}

}  // namespace vimpact
