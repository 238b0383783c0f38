#pragma once
// What a model declares about itself, in a form a C++ model states at compile time
// (constexpr arrays of these) and a model file or plugin states at run time: state
// variables, parameters with their meaning, default, unit and valid range, impact surfaces,
// and sections.
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <string_view>

#include "vimpact/core/format.hpp"

namespace vimpact {

inline constexpr double unbounded = std::numeric_limits<double>::infinity();

// An interval of admissible values; every bound optional, open or closed.
struct value_range {
    double lower = -unbounded;
    double upper = unbounded;
    bool lower_inclusive = false;
    bool upper_inclusive = false;

    [[nodiscard]] bool admits(double v) const
    {
        if (!std::isfinite(v)) return false;
        if (lower_inclusive ? v < lower : v <= lower) return false;
        if (upper_inclusive ? v > upper : v >= upper) return false;
        return true;
    }

    [[nodiscard]] std::string text() const
    {
        const bool has_lo = std::isfinite(lower);
        const bool has_hi = std::isfinite(upper);
        if (has_lo && has_hi)
            return std::string(lower_inclusive ? "[" : "(") + format_double(lower) + ", " + format_double(upper) +
                   (upper_inclusive ? "]" : ")");
        if (has_lo) return std::string(lower_inclusive ? ">= " : "> ") + format_double(lower);
        if (has_hi) return std::string(upper_inclusive ? "<= " : "< ") + format_double(upper);
        return "any finite number";
    }
};

constexpr value_range any_value() { return {}; }
constexpr value_range above(double a) { return {a, unbounded, false, false}; }
constexpr value_range at_least(double a) { return {a, unbounded, true, false}; }
constexpr value_range below(double b) { return {-unbounded, b, false, false}; }
constexpr value_range at_most(double b) { return {-unbounded, b, false, true}; }
constexpr value_range between(double a, double b) { return {a, b, true, true}; }  // closed

// A state variable. `period` > 0 marks a variable on a circle (a phase): states that differ
// by a multiple of it are the same point, for period detection, attractor identity and the
// closure of periodic orbits.
struct state_variable {
    std::string_view name;
    std::string_view meaning = "";
    std::string_view unit = "";
    double period = 0.0;
};

struct parameter {
    std::string_view name;
    double default_value = 0.0;
    std::string_view meaning = "";
    value_range range = {};
    std::string_view unit = "";
};

// An impact surface: the motion keeps gap >= 0; an impact happens when the gap decreases
// through 0 and the surface's reset maps the state. A surface that `sticks` also declares a
// contact phase (see docs/own-model.md): when a chatter sequence accumulates, the state rests on
// it and follows a constrained vector field until a release function turns positive.
// `affine`: the gap is an affine function of the state (a wall at a coordinate, a tilted
// plane). The hybrid flow then trusts the integrator's error control to resolve it on every
// step; any other gap is checked on each step and a step too long for it is taken again
// shorter (integrate/event_resolution.hpp). Declaring a gap affine that is not can miss impacts.
struct impact_surface {
    std::string_view name;
    std::string_view meaning = "";
    bool sticks = false;
    bool affine = false;
};

// Which crossings of a section function count: from positive to non-positive (down), the
// reverse (up), or both.
enum class crossing { down, up, both };

constexpr std::string_view to_string(crossing c)
{
    switch (c) {
        case crossing::down: return "down";
        case crossing::up: return "up";
        case crossing::both: return "both";
    }
    return "unknown";
}

// A Poincare section: the zero crossings of a scalar function of the state in a direction.
// `affine` as for impact_surface: a section function affine in the state is not checked for
// resolution on each step.
struct poincare_section {
    std::string_view name;
    crossing direction = crossing::down;
    std::string_view meaning = "";
    bool affine = false;
};

// A named set of parameter values (those not listed keep their defaults).
struct preset_value {
    std::string_view parameter;
    double value;
};

template <std::size_t K>
struct preset {
    std::string_view name;
    std::string_view meaning;
    std::array<preset_value, K> values;
};

}  // namespace vimpact
