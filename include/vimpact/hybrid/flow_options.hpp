#pragma once
// What a caller of the hybrid flow (hybrid/flow.hpp) chooses: the integration, which surfaces
// act, which events are watched, the limits and the chattering rule. Apart from the flow so
// that the analyses' option types carry it without including the engine.
#include <atomic>
#include <cstdint>
#include <limits>
#include <vector>

#include "vimpact/integrate/integrator_options.hpp"
#include "vimpact/model/spec.hpp"

namespace vimpact {

enum class flow_mode { free, sticking };
enum class flow_control { proceed, stop };

// A scalar event the flow watches: a model section, the rate of a gap, the rate of a state
// variable (F_j: its zeros are the extrema of x_j), or the rate of side * h_k, a switching
// function on the side the flow holds.
struct flow_event {
    enum class source { section, gap_rate, state_rate, switch_rate };
    source kind = source::section;
    int index = 0;                     // section k, surface i, state variable j or switch k
    crossing direction = crossing::down;

    static flow_event section(int k, crossing d) { return {source::section, k, d}; }
    // Minima (up), maxima (down) or both extrema of gap i.
    static flow_event gap_extrema(int i, crossing d) { return {source::gap_rate, i, d}; }
    // Minima (up), maxima (down) or both extrema of state variable j.
    static flow_event state_extrema(int j, crossing d) { return {source::state_rate, j, d}; }
    // Minima (up), maxima (down) or both extrema of side * h_k, the distance to switch k
    // measured on the held side (with switches off: the switch-free system's grazing).
    static flow_event switch_extrema(int k, crossing d) { return {source::switch_rate, k, d}; }
};

struct flow_options {
    integrator_options integration{};
    bool surfaces = true;          // false: the surface-free system (grazing, response)
    // false: the switch-free system: the sides of the switches stay those of the start (as
    // pinned there), crossings are not sought (grazing of switches).
    bool switches = true;
    // Bit i set: surface i is absent (the flow passes through it) while the others act, in
    // the steps that start within [absent_from, absent_until]. A continuation follows an orbit
    // that grazes a surface onto the side where the orbit crosses it, so that the depth of the
    // crossing stays a smooth function; the window spares the orbit's other impacts there.
    std::uint64_t absent_surfaces = 0;
    double absent_from = -std::numeric_limits<double>::infinity();
    double absent_until = std::numeric_limits<double>::infinity();
    std::vector<flow_event> events{};
    double sticking_velocity = 1e-8;
    double sticking_height = -1.0;  // < 0: 256 ulps of the gap's scale (see the header)
    double t_max = std::numeric_limits<double>::infinity();
    long max_steps = 200'000'000;
    long max_impacts = std::numeric_limits<long>::max();
    int event_subdivisions = 8;    // interpolant samples per step when an event may be inside
    // Polled after every step; when set, the run ends with outcome::interrupted. Lets a
    // caller (a Python session's Ctrl-C, a job loop being stopped) cut a long run short.
    const std::atomic<bool>* cancel = nullptr;
    // Report each surface's largest gap on every step to the observer (on_gap_maximum): the
    // interior maximum where the gap's rate turns from positive to non-positive inside the
    // step (located on the interpolant), else the gap at the step's end. The protocol keeps
    // the largest over its record (the excursion of the impact statistics).
    bool gap_maxima = false;
};

}  // namespace vimpact
