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

#include "vimpact/core/value_range.hpp"

namespace vimpact {

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

// A switching surface: the zero set of a switching function h(x) where the vector field
// changes (a compliant contact, a bilinear spring, the pivot of a rocking block) while the
// state goes on continuously. The field is evaluated on one side, held between located
// crossings (core/switch_sides.hpp). A crossing in `direction` (down: h from positive to
// negative; up; both) applies the switch's reset, if the model has one; any crossing changes
// the side. `affine` as for impact_surface.
struct switching_surface {
    std::string_view name;
    std::string_view meaning = "";
    crossing direction = crossing::both;
    bool affine = false;
};

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
