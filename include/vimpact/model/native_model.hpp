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

    [[nodiscard]] state rhs(const state& x) const { return call_field(x, sides_at(x)); }

    // Switching surfaces (a definition that declares them: model/definition.hpp). The sides
    // the field is evaluated on are pinned by a flow that holds them between crossings;
    // unpinned, they are taken from the state (h_k >= 0: +1).
    static constexpr int switches = switch_count_of<D>();
    [[nodiscard]] static constexpr int switch_count()
        requires(switches > 0)
    {
        return switches;
    }
    [[nodiscard]] static constexpr crossing switch_direction(int k)
        requires(switches > 0)
    {
        return D::switches[static_cast<std::size_t>(k)].direction;
    }
    [[nodiscard]] static constexpr bool switching_affine(int k)
        requires(switches > 0)
    {
        return D::switches[static_cast<std::size_t>(k)].affine;
    }
    [[nodiscard]] double switching(int k, const state& x) const
        requires(switches > 0)
    {
        return m_def.switching(k, x);
    }
    [[nodiscard]] state switching_gradient(int k, const state& x) const
        requires(switches > 0)
    {
        return ad::gradient<dim>([this, k](const auto& y) { return m_def.switching(k, y); }, x);
    }
    [[nodiscard]] double switching_derivative(int k, const state& x, const state& v) const
        requires(switches > 0)
    {
        return ad::directional<dim>([this, k](const auto& y) { return m_def.switching(k, y); }, x, v);
    }
    [[nodiscard]] switch_sides sides_at(const state& x) const
    {
        if constexpr (switches == 0) return (void)x, switch_sides{};
        else {
            if (m_pinned) return m_sides;
            switch_sides s;
            for (int k = 0; k < switches; ++k) s.set(k, m_def.switching(k, x) >= 0.0);
            return s;
        }
    }
    // Holds the sides until unpin(): the flow's copy of the model, between crossings.
    void pin_sides(const switch_sides& s)
        requires(switches > 0)
    {
        m_sides = s;
        m_pinned = true;
    }
    // Crossing switch k at x (pinned): the side changes; out is the state after it, the
    // switch's reset where the crossing goes in the switch's direction, x otherwise. True
    // when the reset applied.
    bool cross(int k, const state& x, state& out)
        requires(switches > 0)
    {
        const bool down = !m_sides.negative(k);
        m_sides.flip(k);
        const crossing d = switch_direction(k);
        const bool applies = d == crossing::both || (d == crossing::down) == down;
        if constexpr (has_switch_reset) {
            out = applies ? state(m_def.switch_reset(k, x, m_sides)) : x;
            return applies;
        } else {
            out = x;
            return false;
        }
    }
    // The Jacobian of the reset of switch k at x, on the sides after the crossing (cross).
    [[nodiscard]] matrix switch_reset_jacobian(int k, const state& x) const
        requires(switches > 0)
    {
        if constexpr (has_switch_reset)
            return ad::jacobian<dim>(
                [this, k](const auto& y) {
                    using T = typename std::decay_t<decltype(y)>::Scalar;
                    return vec_t<T, dim>(m_def.switch_reset(k, y, m_sides));
                },
                x);
        else return (void)k, matrix::Identity(x.size(), x.size());
    }

    [[nodiscard]] matrix jacobian(const state& x) const
    {
        if constexpr (switches == 0 && requires { { m_def.jacobian(x) } -> std::convertible_to<matrix>; }) return m_def.jacobian(x);
        else return ad::jacobian<dim>(field(sides_at(x)), x);
    }

    [[nodiscard]] state second_derivative(const state& x, const state& u, const state& w) const
    {
        if constexpr (switches == 0 && requires { { m_def.second_derivative(x, u, w) } -> std::convertible_to<state>; })
            return m_def.second_derivative(x, u, w);
        else return ad::second_directional<dim>(field(sides_at(x)), x, u, w);
    }

    [[nodiscard]] double divergence(const state& x) const
    {
        if constexpr (switches == 0 && requires { { m_def.divergence(x) } -> std::convertible_to<double>; }) return m_def.divergence(x);
        else return jacobian(x).trace();
    }

    [[nodiscard]] double gap(int i, const state& x) const { return call_gap(i, x); }

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

    [[nodiscard]] state reset(int i, const state& x) const { return call_reset(i, x); }

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

    [[nodiscard]] double section(int k, const state& x) const { return call_section(k, x); }

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

    static constexpr bool has_switch_reset = requires(const D& d, const state& x) {
        { d.switch_reset(0, x, switch_sides{}) } -> std::convertible_to<state>;
    };

    template <class Y>
    auto call_field(const Y& y, const switch_sides& s) const
    {
        using T = typename Y::Scalar;
        if constexpr (fields_by_side<D>) return vec_t<T, dim>(m_def.derivatives(y, s));
        else return (void)s, vec_t<T, dim>(m_def.derivatives(y));
    }
    // The field on sides s, as a function to differentiate.
    auto field(const switch_sides& s) const
    {
        return [this, s](const auto& y) { return call_field(y, s); };
    }
    auto gap_function(int i) const
    {
        return [this, i](const auto& y) { return call_gap(i, y); };
    }
    auto reset_function(int i) const
    {
        return [this, i](const auto& y) { return call_reset(i, y); };
    }
    // A definition without surfaces (sections) need not write gaps and resets (sections): the
    // flow never asks for those of a surface (section) that does not exist.
    template <class Y>
    auto call_gap(int i, const Y& y) const
    {
        using T = typename Y::Scalar;
        if constexpr (surfaces > 0) return T(m_def.gap(i, y));
        else return (void)i, T(0.0);
    }
    template <class Y>
    auto call_reset(int i, const Y& y) const
    {
        using T = typename Y::Scalar;
        if constexpr (surfaces > 0) return vec_t<T, dim>(m_def.reset(i, y));
        else return (void)i, vec_t<T, dim>(y);
    }
    template <class Y>
    auto call_section(int k, const Y& y) const
    {
        using T = typename Y::Scalar;
        if constexpr (sections > 0) return T(m_def.section(k, y));
        else return (void)k, T(0.0);
    }

    D m_def;
    switch_sides m_sides;
    bool m_pinned = false;
};

}  // namespace vimpact
