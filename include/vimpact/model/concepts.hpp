#pragma once
// What the hybrid flow needs from a model, and the optional parts it can use.
//
// Required: a fixed dimension, the vector field, the guard h (an impact happens when h
// decreases through zero), its gradient and the reset map. The position/velocity indices
// name the impacting coordinate and its rate, which define the sections (maxima and minima
// of the position) and the sticking phase.
#include <concepts>

#include "vimpact/core/state.hpp"

namespace vimpact {

template <class M>
concept hybrid_model = requires(const M& m, const vec<M::dim>& x) {
    { M::dim } -> std::convertible_to<int>;
    { M::position } -> std::convertible_to<int>;
    { M::velocity } -> std::convertible_to<int>;
    { m.rhs(x) } -> std::convertible_to<vec<M::dim>>;
    { m.guard(x) } -> std::convertible_to<double>;
    { m.guard_gradient(x) } -> std::convertible_to<vec<M::dim>>;
    { m.reset(x) } -> std::convertible_to<vec<M::dim>>;
    { m.section_coordinates(x) };
};

// A model that can stick to the barrier after chattering: the constrained vector field,
// and the free acceleration of the impacting coordinate whose sign decides release.
template <class M>
concept sticking_model = hybrid_model<M> && requires(const M& m, const vec<M::dim>& x) {
    { m.sticking_rhs(x) } -> std::convertible_to<vec<M::dim>>;
    { m.free_acceleration(x) } -> std::convertible_to<double>;
    { m.free_acceleration_gradient(x) } -> std::convertible_to<vec<M::dim>>;
    { m.restitution() } -> std::convertible_to<double>;
};

template <class M>
concept has_jacobian = requires(const M& m, const vec<M::dim>& x) {
    { m.jacobian(x) } -> std::convertible_to<mat<M::dim>>;
};

template <class M>
concept has_reset_jacobian = requires(const M& m, const vec<M::dim>& x) {
    { m.reset_jacobian(x) } -> std::convertible_to<mat<M::dim>>;
};

// Optional second derivatives, as bilinear forms D2(x)[u, w]; the second-order discontinuity
// mapping (stability/discontinuity_map.hpp) needs the guard's and the reset's.
template <class M>
concept has_second_derivative = requires(const M& m, const vec<M::dim>& x) {
    { m.second_derivative(x, x, x) } -> std::convertible_to<vec<M::dim>>;
};

template <class M>
concept has_guard_hessian = requires(const M& m, const vec<M::dim>& x) {
    { m.guard_hessian(x, x, x) } -> std::convertible_to<double>;
};

template <class M>
concept has_reset_second_derivative = requires(const M& m, const vec<M::dim>& x) {
    { m.reset_second_derivative(x, x, x) } -> std::convertible_to<vec<M::dim>>;
};

// div F = trace of the Jacobian, when the model knows it in closed form.
template <class M>
concept has_divergence = requires(const M& m, const vec<M::dim>& x) {
    { m.divergence(x) } -> std::convertible_to<double>;
};

// b - a for states that live on a cylinder (a forcing phase): the difference modulo the
// symmetry, so that points one forcing period apart coincide. Without it: b - a.
template <class M>
concept has_state_difference = requires(const M& m, const vec<M::dim>& x) {
    { m.state_difference(x, x) } -> std::convertible_to<vec<M::dim>>;
};

template <class M>
vec<M::dim> state_difference(const M& m, const vec<M::dim>& b, const vec<M::dim>& a)
{
    if constexpr (has_state_difference<M>) return m.state_difference(b, a);
    else return b - a;
}

}  // namespace vimpact
