#pragma once
// The classic harmonically forced linear impact oscillator, in autonomous form with a phase:
//
//   y' = ydot,  ydot' = -y - 2 zeta ydot + F cos(theta),  theta' = omega
//   surface "barrier": gap y - sigma; reset (y, ydot, theta) -> (sigma, -r ydot, theta)
//   contact: y = sigma, ydot = 0, theta runs on; released when the free acceleration > 0
//
// Between impacts the flow is known in closed form, so event times, impacting periodic orbits
// and their stability can be checked against exact values. The Jacobian and the divergence
// are written by hand; the other derivatives come from automatic differentiation.
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
class basic_forced_impact_oscillator {
public:
    static constexpr std::string_view name = "forced_impact_oscillator";
    static constexpr std::string_view description =
        "the harmonically forced linear oscillator y'' + 2 zeta y' + y = F cos(theta), theta' = omega, "
        "with a rigid barrier at y = sigma";
    static constexpr std::array<state_variable, 3> state{{
        {"y", "displacement"},
        {"ydot", "velocity"},
        {"theta", "forcing phase", "rad", 2.0 * std::numbers::pi},
    }};
    static constexpr std::array<parameter, 5> parameters{{
        {"zeta", 0.05, "damping ratio", {0.0, 1.0, true, false}},
        {"omega", 0.8, "forcing frequency / natural frequency", above(0.0)},
        {"F", 1.0, "forcing amplitude", any_value()},
        {"sigma", -1.0, "barrier position", any_value()},
        {"r", 0.8, "coefficient of restitution", between(0.0, 1.0)},
    }};
    static constexpr std::array<impact_surface, 1> surfaces{{{"barrier", "rigid barrier at y = sigma", true, true}}};
    static constexpr std::array<poincare_section, 3> sections{{
        {"maxima", crossing::down, "maxima of y: ydot = 0, ydot decreasing", true},
        {"minima", crossing::up, "minima of y: ydot = 0, ydot increasing", true},
        {"strobe", crossing::up, "once per forcing period: sin(theta) = 0, increasing (theta = 0 mod 2 pi)"},
    }};
    static constexpr std::array<double, 3> initial_state{0.0, 0.0, 0.0};

    // The vector field in SIMD lanes (hybrid/flow_lanes.hpp).
    using lanes_definition = basic_forced_impact_oscillator<lanes>;

    explicit basic_forced_impact_oscillator(std::span<const P> p)
        : m_zeta(p[0]), m_omega(p[1]), m_F(p[2]), m_sigma(p[3]), m_r(p[4])
    {
    }

    template <class T>
    [[nodiscard]] T free_acceleration(const vec_t<T, 3>& X) const
    {
        using std::cos;
        return -X[0] - 2.0 * m_zeta * X[1] + m_F * cos(X[2]);
    }
    template <class T>
    [[nodiscard]] vec_t<T, 3> derivatives(const vec_t<T, 3>& X) const
    {
        return {X[1], free_acceleration(X), T(m_omega)};
    }
    template <class T>
    [[nodiscard]] T gap(int, const vec_t<T, 3>& X) const { return X[0] - m_sigma; }
    template <class T>
    [[nodiscard]] vec_t<T, 3> reset(int, const vec_t<T, 3>& X) const { return {T(m_sigma), -m_r * X[1], X[2]}; }
    template <class T>
    [[nodiscard]] T section(int k, const vec_t<T, 3>& X) const
    {
        using std::sin;
        return k == 2 ? T(sin(X[2])) : X[1];
    }
    template <class T>
    [[nodiscard]] vec_t<T, 3> sticking_derivatives(int, const vec_t<T, 3>&) const
    {
        return {T(0.0), T(0.0), T(m_omega)};
    }
    template <class T>
    [[nodiscard]] T release(int, const vec_t<T, 3>& X) const { return free_acceleration(X); }
    [[nodiscard]] vec<3> rest(int, const vec<3>& X) const { return {m_sigma, 0.0, X[2]}; }

    [[nodiscard]] mat<3> jacobian(const vec<3>& X) const
    {
        mat<3> J;
        J << 0.0, 1.0, 0.0,                                    //
            -1.0, -2.0 * m_zeta, -m_F * std::sin(X[2]),        //
            0.0, 0.0, 0.0;
        return J;
    }
    [[nodiscard]] double divergence(const vec<3>&) const { return -2.0 * m_zeta; }

private:
    P m_zeta, m_omega, m_F, m_sigma, m_r;
};

using forced_impact_oscillator = basic_forced_impact_oscillator<double>;

}  // namespace vimpact
