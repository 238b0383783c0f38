#pragma once
// A harmonically forced linear oscillator between two rigid stops at x = -d and x = d:
//
//   x' = v,  v' = -2 zeta v - x + a cos(phi),  phi' = w
//   surface "right": gap d - x;  surface "left": gap x + d;  both reset v -> -r v
//   section "strobe": sin(phi) = 0 going up (once per forcing period)
//
// The same system as the model file examples/models/two_sided_impact_oscillator.toml. No
// surface declares a contact phase: an accumulation of impacts on a stop ends the run with
// the outcome `chattering`. Every derivative comes from automatic differentiation.
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
class basic_two_sided_impact_oscillator {
public:
    static constexpr std::string_view name = "two_sided_impact_oscillator";
    static constexpr std::string_view description =
        "a harmonically forced linear oscillator x'' + 2 zeta x' + x = a cos(phi), phi' = w, between rigid "
        "stops at x = -d and x = d";
    static constexpr std::array<state_variable, 3> state{{
        {"x", "displacement"},
        {"v", "velocity"},
        {"phi", "forcing phase", "rad", 2.0 * std::numbers::pi},
    }};
    static constexpr std::array<parameter, 5> parameters{{
        {"zeta", 0.05, "damping ratio", at_least(0.0)},
        {"a", 1.0, "forcing amplitude", any_value()},
        {"w", 1.2, "forcing frequency / natural frequency", above(0.0)},
        {"d", 1.0, "half the clearance between the stops", above(0.0)},
        {"r", 0.8, "coefficient of restitution", between(0.0, 1.0)},
    }};
    static constexpr std::array<impact_surface, 2> surfaces{{
        {"right", "stop at x = d", false, true},
        {"left", "stop at x = -d", false, true},
    }};
    static constexpr std::array<poincare_section, 1> sections{{
        {"strobe", crossing::up, "once per forcing period: sin(phi) = 0, increasing (phi = 0 mod 2 pi)"},
    }};
    static constexpr std::array<double, 3> initial_state{0.0, 0.0, 0.0};

    // The vector field in SIMD lanes (hybrid/flow_lanes.hpp).
    using lanes_definition = basic_two_sided_impact_oscillator<lanes>;

    explicit basic_two_sided_impact_oscillator(std::span<const P> p)
        : m_zeta(p[0]), m_a(p[1]), m_w(p[2]), m_d(p[3]), m_r(p[4])
    {
    }

    template <class T>
    [[nodiscard]] vec_t<T, 3> derivatives(const vec_t<T, 3>& X) const
    {
        using std::cos;
        return {X[1], -2.0 * m_zeta * X[1] - X[0] + m_a * cos(X[2]), T(m_w)};
    }
    template <class T>
    [[nodiscard]] T gap(int i, const vec_t<T, 3>& X) const
    {
        return i == 0 ? T(m_d - X[0]) : T(X[0] + m_d);
    }
    template <class T>
    [[nodiscard]] vec_t<T, 3> reset(int, const vec_t<T, 3>& X) const { return {X[0], -m_r * X[1], X[2]}; }
    template <class T>
    [[nodiscard]] T section(int, const vec_t<T, 3>& X) const
    {
        using std::sin;
        return sin(X[2]);
    }

private:
    P m_zeta, m_a, m_w, m_d, m_r;
};

using two_sided_impact_oscillator = basic_two_sided_impact_oscillator<double>;

}  // namespace vimpact
