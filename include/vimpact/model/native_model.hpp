#pragma once
// native_model<D>: a C++ model definition (model/definition.hpp) with its parameters bound,
// completed into an engine model (model/engine_model.hpp). A derivative the definition writes
// by hand is used as written; every other one is computed by forward-mode automatic
// differentiation of the templated functions (model/autodiff.hpp).
#include <cmath>
#include <span>
#include <type_traits>

#include "vimpact/model/autodiff.hpp"
#include "vimpact/model/definition.hpp"
#include "vimpact/model/engine_model.hpp"

namespace vimpact {

template <model_definition D>
class native_model {
public:
    using definition_type = D;
    static constexpr int dim = definition_dim<D>;
    static constexpr int surfaces = static_cast<int>(D::surfaces.size());
    static constexpr int sections = static_cast<int>(D::sections.size());
    using state = vec<dim>;
    using matrix = mat<dim>;

    explicit native_model(std::span<const double> parameters) : m_def(parameters) {}
    explicit native_model(const D& definition) : m_def(definition) {}

    [[nodiscard]] const D& definition() const { return m_def; }
    [[nodiscard]] static constexpr int surface_count() { return surfaces; }
    [[nodiscard]] static constexpr int section_count() { return sections; }
    [[nodiscard]] static constexpr crossing section_direction(int k) { return D::sections[k].direction; }
    [[nodiscard]] static constexpr bool sticks(int i) { return D::surfaces[i].sticks; }
    [[nodiscard]] static constexpr bool gap_affine(int i) { return D::surfaces[i].affine; }
    [[nodiscard]] static constexpr bool section_affine(int k) { return D::sections[k].affine; }

    [[nodiscard]] state rhs(const state& x) const { return m_def.derivatives(x); }

    [[nodiscard]] matrix jacobian(const state& x) const
    {
        if constexpr (requires { { m_def.jacobian(x) } -> std::convertible_to<matrix>; }) return m_def.jacobian(x);
        else return ad::jacobian<dim>(field(), x);
    }

    [[nodiscard]] state second_derivative(const state& x, const state& u, const state& w) const
    {
        if constexpr (requires { { m_def.second_derivative(x, u, w) } -> std::convertible_to<state>; })
            return m_def.second_derivative(x, u, w);
        else return ad::second_directional<dim>(field(), x, u, w);
    }

    [[nodiscard]] double divergence(const state& x) const
    {
        if constexpr (requires { { m_def.divergence(x) } -> std::convertible_to<double>; }) return m_def.divergence(x);
        else return jacobian(x).trace();
    }

    [[nodiscard]] double gap(int i, const state& x) const { return m_def.gap(i, x); }

    [[nodiscard]] state gap_gradient(int i, const state& x) const
    {
        if constexpr (requires { { m_def.gap_gradient(i, x) } -> std::convertible_to<state>; })
            return m_def.gap_gradient(i, x);
        else return ad::gradient<dim>(gap_function(i), x);
    }

    [[nodiscard]] double gap_derivative(int i, const state& x, const state& v) const
    {
        if constexpr (requires { { m_def.gap_gradient(i, x) } -> std::convertible_to<state>; })
            return m_def.gap_gradient(i, x).dot(v);
        else return ad::directional<dim>(gap_function(i), x, v);
    }

    [[nodiscard]] matrix gap_hessian(int i, const state& x) const
    {
        if constexpr (requires { { m_def.gap_hessian(i, x) } -> std::convertible_to<matrix>; })
            return m_def.gap_hessian(i, x);
        else return ad::hessian<dim>(gap_function(i), x);
    }

    [[nodiscard]] state reset(int i, const state& x) const { return m_def.reset(i, x); }

    [[nodiscard]] matrix reset_jacobian(int i, const state& x) const
    {
        if constexpr (requires { { m_def.reset_jacobian(i, x) } -> std::convertible_to<matrix>; })
            return m_def.reset_jacobian(i, x);
        else return ad::jacobian<dim>(reset_function(i), x);
    }

    [[nodiscard]] state reset_second_derivative(int i, const state& x, const state& u, const state& w) const
    {
        if constexpr (requires { { m_def.reset_second_derivative(i, x, u, w) } -> std::convertible_to<state>; })
            return m_def.reset_second_derivative(i, x, u, w);
        else return ad::second_directional<dim>(reset_function(i), x, u, w);
    }

    [[nodiscard]] double section(int k, const state& x) const { return m_def.section(k, x); }

    [[nodiscard]] state section_gradient(int k, const state& x) const
    {
        if constexpr (requires { { m_def.section_gradient(k, x) } -> std::convertible_to<state>; })
            return m_def.section_gradient(k, x);
        else return ad::gradient<dim>([this, k](const auto& y) { return call_section(k, y); }, x);
    }

    [[nodiscard]] double section_derivative(int k, const state& x, const state& v) const
    {
        if constexpr (requires { { m_def.section_gradient(k, x) } -> std::convertible_to<state>; })
            return m_def.section_gradient(k, x).dot(v);
        else return ad::directional<dim>([this, k](const auto& y) { return call_section(k, y); }, x, v);
    }

    // Contact phases exist only on surfaces that declare them (sticks(i)); on the others the
    // flow never calls these.
    [[nodiscard]] state sticking_rhs(int i, const state& x) const
    {
        if constexpr (sticking_definition<D>) return m_def.sticking_derivatives(i, x);
        else return (void)i, x * 0.0;
    }
    [[nodiscard]] double release(int i, const state& x) const
    {
        if constexpr (sticking_definition<D>) return m_def.release(i, x);
        else return (void)i, (void)x, 1.0;
    }
    [[nodiscard]] state release_gradient(int i, const state& x) const
    {
        if constexpr (requires { { m_def.release_gradient(i, x) } -> std::convertible_to<state>; })
            return m_def.release_gradient(i, x);
        else if constexpr (sticking_definition<D>)
            return ad::gradient<dim>([this, i](const auto& y) { return m_def.release(i, y); }, x);
        else return (void)i, x * 0.0;
    }
    [[nodiscard]] state rest(int i, const state& x) const
    {
        if constexpr (sticking_definition<D>) return m_def.rest(i, x);
        else return (void)i, x;
    }

    // b - a, with every phase variable's difference taken into (-period/2, period/2].
    [[nodiscard]] static state state_difference(const state& b, const state& a)
    {
        state d = b - a;
        for (int j = 0; j < dim; ++j) {
            const double p = D::state[static_cast<std::size_t>(j)].period;
            if (p > 0.0) d[j] -= p * std::round(d[j] / p);
        }
        return d;
    }

private:
    static_assert(!any_surface_sticks<D>() || sticking_definition<D>,
                  "a surface declares sticking: the definition needs sticking_derivatives, release and rest");

    auto field() const
    {
        return [this](const auto& y) {
            using T = typename std::decay_t<decltype(y)>::Scalar;
            return vec_t<T, dim>(m_def.derivatives(y));
        };
    }
    auto gap_function(int i) const
    {
        return [this, i](const auto& y) { return m_def.gap(i, y); };
    }
    auto reset_function(int i) const
    {
        return [this, i](const auto& y) {
            using T = typename std::decay_t<decltype(y)>::Scalar;
            return vec_t<T, dim>(m_def.reset(i, y));
        };
    }
    template <class Y>
    auto call_section(int k, const Y& y) const
    {
        return m_def.section(k, y);
    }

    D m_def;
};

}  // namespace vimpact
