#pragma once
// A model written in C++: a small struct that states its dimension, parameters, vector field,
// impact surfaces with their resets, and sections once, as templates over the scalar type.
// Every derivative the analyses need (Jacobian, second derivatives, gap gradients and
// Hessians, reset Jacobians and second derivatives, section gradients) then comes from
// forward-mode automatic differentiation (model/autodiff.hpp); a model may still write any of
// them by hand, and the hand-written one is used (docs/own-model.md has a complete example).
//
// Required members of a definition D with N state variables:
//   static constexpr std::string_view name, description;
//   static constexpr std::array<state_variable, N> state;        (model/spec.hpp)
//   static constexpr std::array<parameter, P> parameters;         name, default, meaning, range
//   static constexpr std::array<impact_surface, S> surfaces;
//   static constexpr std::array<poincare_section, K> sections;
//   explicit D(std::span<const double> p);   p: the parameters in declared order (already
//                                             range-checked; throw input_error for more)
//   template <class T> vec_t<T, N> derivatives(const vec_t<T, N>& x) const;
//   template <class T> T gap(int i, const vec_t<T, N>& x) const;          >= 0 is admissible
//   template <class T> vec_t<T, N> reset(int i, const vec_t<T, N>& x) const;
//   template <class T> T section(int k, const vec_t<T, N>& x) const;
// (gap and reset only with surfaces, section only with sections)
// and, when a surface sticks,
//   template <class T> vec_t<T, N> sticking_derivatives(int i, const vec_t<T, N>& x) const;
//   template <class T> T release(int i, const vec_t<T, N>& x) const;    contact ends when > 0
//   vec<N> rest(int i, const vec<N>& x) const;                           the state put at rest
// Switching surfaces (optional: a piecewise-smooth field, model/spec.hpp):
//   static constexpr std::array<switching_surface, W> switches;
//   template <class T> T switching(int k, const vec_t<T, N>& x) const;   h_k: its sign is the side
//   template <class T> vec_t<T, N> derivatives(const vec_t<T, N>& x, const switch_sides& s) const;
// the field on the sides s (s.side(k) = +1 or -1, s.on(k) = 1 or 0) instead of the one-argument
// derivatives, and, for a jump of the state at a crossing,
//   template <class T> vec_t<T, N> switch_reset(int k, const vec_t<T, N>& x, const switch_sides& s) const;
// with s the sides after the crossing.
// Optional: static constexpr std::array<double, N> initial_state; and the hand-written
// derivatives jacobian(x), second_derivative(x, u, w), divergence(x), gap_gradient(i, x),
// gap_hessian(i, x), reset_jacobian(i, x), reset_second_derivative(i, x, u, w),
// section_gradient(k, x), release_gradient(i, x).
#include <algorithm>
#include <array>
#include <concepts>
#include <span>
#include <string_view>

#include "vimpact/core/state.hpp"
#include "vimpact/core/switch_sides.hpp"
#include "vimpact/model/spec.hpp"

namespace vimpact {

template <class D>
constexpr int definition_dim = static_cast<int>(std::tuple_size_v<std::decay_t<decltype(D::state)>>);

// A definition with switching surfaces (their number is switch_count_of<D>).
template <class D>
concept switching_definition = requires(const D& d, const vec<definition_dim<D>>& x, int k) {
    { D::switches.size() } -> std::convertible_to<std::size_t>;
    { D::switches[0] } -> std::convertible_to<switching_surface>;
    { d.switching(k, x) } -> std::convertible_to<double>;
    { d.derivatives(x, switch_sides{}) } -> std::convertible_to<vec<definition_dim<D>>>;
};

template <class D>
constexpr int switch_count_of()
{
    if constexpr (requires { D::switches.size(); }) return static_cast<int>(D::switches.size());
    else return 0;
}

// The field of a definition: on sides s where it has switches, else its only one.
template <class D>
constexpr bool fields_by_side = requires(const D& d, const vec<definition_dim<D>>& x) {
    { d.derivatives(x, switch_sides{}) } -> std::convertible_to<vec<definition_dim<D>>>;
};

template <class D>
concept model_definition = requires(const D& d, const vec<definition_dim<D>>& x, std::span<const double> p, int i) {
    { D::name } -> std::convertible_to<std::string_view>;
    { D::description } -> std::convertible_to<std::string_view>;
    { D::state[0] } -> std::convertible_to<state_variable>;
    { D::parameters.size() } -> std::convertible_to<std::size_t>;
    { D::surfaces.size() } -> std::convertible_to<std::size_t>;
    { D::sections.size() } -> std::convertible_to<std::size_t>;
    D(p);
    requires fields_by_side<D> || requires { { d.derivatives(x) } -> std::convertible_to<vec<definition_dim<D>>>; };
    requires D::surfaces.size() == 0 || requires {
        { d.gap(i, x) } -> std::convertible_to<double>;
        { d.reset(i, x) } -> std::convertible_to<vec<definition_dim<D>>>;
    };
    requires D::sections.size() == 0 || requires { { d.section(i, x) } -> std::convertible_to<double>; };
};

template <class D>
constexpr bool any_surface_sticks()
{
    return std::any_of(D::surfaces.begin(), D::surfaces.end(), [](const impact_surface& s) { return s.sticks; });
}

template <class D>
concept sticking_definition = requires(const D& d, const vec<definition_dim<D>>& x, int i) {
    { d.sticking_derivatives(i, x) } -> std::convertible_to<vec<definition_dim<D>>>;
    { d.release(i, x) } -> std::convertible_to<double>;
    { d.rest(i, x) } -> std::convertible_to<vec<definition_dim<D>>>;
};

}  // namespace vimpact
