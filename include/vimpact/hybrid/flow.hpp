#pragma once
// The hybrid flow: smooth flight integrated by an adaptive Runge-Kutta method, impacts on any
// number of surfaces located on the interpolant and mapped by each surface's reset, section
// crossings recorded as events, and chattering resolved into a contact phase where a surface
// declares one.
//
// Surfaces. Surface i is a gap g_i(x) that the motion keeps >= 0; an impact is a crossing of
// g_i from > 0 to <= 0 (terminal: the first in time among all surfaces; a tie goes to the
// lower index). Each crossing is found grazing-safely: a dip of g_i below zero between two
// positive step ends is found by splitting the step at the interior minimum
// (integrate/event_location.hpp). The reset R_i maps the state at the crossing.
//
// Resolution. The crossing search reads each event function from its values and slopes at a
// step's ends (integrate/event_location.hpp); a gap or section that is not affine in the state
// (model/spec.hpp) is also checked on every step at one interior point of the state's cubic
// interpolant, and a step on which it strays from its own cubic is taken back and tried
// again shorter (integrate/event_resolution.hpp), so that no crossing hides inside a step
// however long the integrator's error control would let it be. After a few such retries in a
// row the step is kept (a function with a kink never looks like a cubic near it).
// A step that ends beyond a present surface without a located crossing ends the run with the
// outcome `inadmissible`, rather than going on in the forbidden region.
//
// Resets. A reset whose image is not finite ends the run with `non_finite`; one that puts the
// state beyond a surface (a gap below minus its resolution), or leaves it on the impacting
// surface moving into it, with `inadmissible`. The chattering rule below applies only where
// the reset leaves the state on the surface: a reset that moves the state away from it (a
// drop to a height) starts a new flight.
//
// Events. Besides the surfaces the flow watches a list of scalar event functions, each with
// a direction: a model section s_k, or the rate of a gap g_i' = grad g_i . F (its upward
// zeros are the minima of the gap, its downward zeros the maxima: grazing). Crossings before
// the step's impact (or release) are reported in time order; the rest of the step is
// discarded with the trajectory it belonged to.
//
// Chattering (the rule, docs/model.md). After an impact on surface i the rebound is the gap
// rate u = g_i'(R_i(x)). Let a be the gap's acceleration at rest: the model's release
// function at the rest state for a surface with a contact phase, g_i'' of the free flow
// otherwise. The rebound is negligible when u < sticking_velocity, or when its hop height
// u^2 / (2 |a|) is below the resolution of g_i (sticking_height; default 256 ulps of
// max(1, sum_j |dg_i/dx_j x_j|), i.e. of max(1, |sigma|) for the paper's barrier). A
// negligible rebound while a <= 0 (the surface pushes back) ends a chatter sequence:
// - on a surface that declares a contact phase, the state is put at rest (the model's rest
//   map) and follows the constrained vector field until the release function crosses zero
//   upwards (located as an event);
// - on any other surface the run ends with the outcome `chattering`: the impacts accumulate
//   and the model says nothing about what happens after.
// With restitution r < 1 the rebound velocities shrink by r per impact, so the rule is
// reached after about log(u_stop / u_0) / log(r) impacts: a bounded number, never a hang. A
// step that leaves a surface and ends below it without the gap ever turning positive (a hop
// below the resolution of the gap) is treated the same way.
#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/core/outcome.hpp"
#include "vimpact/hybrid/flow_options.hpp"
#include "vimpact/hybrid/run_stats.hpp"
#include "vimpact/hybrid/stepper.hpp"
#include "vimpact/integrate/adaptive_integrator.hpp"
#include "vimpact/integrate/event_location.hpp"
#include "vimpact/integrate/event_resolution.hpp"
#include "vimpact/model/engine_model.hpp"

namespace vimpact {

// Default (no-op) observer; derive and shadow what you need.
struct flow_observer {
    [[nodiscard]] bool wants_segments() const { return false; }
    // `event` indexes flow_options::events; `direction` is the way this crossing went.
    template <class X>
    flow_control on_section(int /*event*/, crossing /*direction*/, double, const X&) { return flow_control::proceed; }
    template <class X>
    flow_control on_impact(int /*surface*/, double, const X& /*pre*/, const X& /*post*/) { return flow_control::proceed; }
    // A crossing of switching surface `k` (model/spec.hpp): the states before and after it
    // (the same unless the switch has a reset that applied).
    template <class X>
    flow_control on_switch(int /*k*/, double, const X& /*pre*/, const X& /*post*/) { return flow_control::proceed; }
    template <class X>
    void on_stick(int /*surface*/, double, const X&) {}
    template <class X>
    void on_release(int /*surface*/, double, const X&) {}
    template <class D>
    void on_segment(const D&, double, double, flow_mode) {}
    // With flow_options::gap_maxima: the largest value of gap `surface` on the step just
    // taken and when it was reached.
    void on_gap_maximum(int /*surface*/, double /*t*/, double /*gap*/) {}
    flow_control on_step_end(double) { return flow_control::proceed; }
};

template <engine_model Model, template <int> class Method = dop853>
class hybrid_flow {
public:
    static constexpr int N = Model::dim;
    using state = vec<N>;
    using integrator_type = adaptive_integrator<N, Method, typename flow_stepper<Model, Method>::type>;
    using dense_type = typename integrator_type::dense_type;

    hybrid_flow(const Model& model, const flow_options& opt)
        : m_model(model), m_opt(opt), m_integ(opt.integration), m_x(state::Zero(state_dim(model))), m_point(m_x),
          m_slope(m_x), m_pre(m_x), m_post(m_x), m_gradient(m_x)
    {
        m_stats.impacts_by_surface.assign(static_cast<std::size_t>(m_model.surface_count()), 0);
        for (auto* e : {&m_start, &m_end}) {
            e->gaps.resize(static_cast<std::size_t>(m_model.surface_count()));
            e->events.resize(m_opt.events.size());
            e->switches.resize(m_opt.switches ? static_cast<std::size_t>(switch_count(m_model)) : 0);
        }
        m_batch_gaps.resize(2 * static_cast<std::size_t>(m_model.surface_count()));
        m_batch_sections.resize(2 * static_cast<std::size_t>(m_model.section_count()));
        for (int i = 0; i < m_model.surface_count(); ++i) m_check_gap.push_back(!gap_is_affine(m_model, i));
        for (const flow_event& e : m_opt.events) m_check_event.push_back(!resolved_by_integrator(e));
        if constexpr (has_switches)
            if (m_opt.switches)
                for (int k = 0; k < m_model.switch_count(); ++k) m_check_switch.push_back(!m_model.switching_affine(k));
        const auto any = [](const std::vector<char>& v) { return std::any_of(v.begin(), v.end(), [](char c) { return c != 0; }); };
        m_check_any = any(m_check_event) || any(m_check_switch) || (m_opt.surfaces && any(m_check_gap));
    }

    // Starts at (t, x). Throws input_error if x is not admissible (beyond a surface). A state
    // on a contact surface at rest, pushed into it, starts in the contact phase.
    void start(double t, const state& x)
    {
        if (!x.allFinite()) throw input_error("initial state must be finite");
        m_t = t;
        m_x = x;
        m_mode = flow_mode::free;
        m_contact = -1;
        if (m_opt.surfaces) {
            int bad = -1;
            for (int i = 0; i < m_model.surface_count() && bad < 0; ++i) {
                const double g = m_model.gap(i, x);
                if (!absent(i) && (g < 0.0 || (g == 0.0 && gap_rate(m_model, i, x) < 0.0))) bad = i;
            }
            if (bad >= 0)
                throw input_error("initial state is not admissible: it lies beyond surface " + std::to_string(bad) +
                                  " (gap " + format_double(m_model.gap(bad, x)) + " < 0, or 0 and decreasing)");
            for (int i = 0; i < m_model.surface_count(); ++i)
                if (m_model.sticks(i) && m_model.gap(i, x) == 0.0 && gap_rate(m_model, i, x) == 0.0 &&
                    m_model.release(i, x) <= 0.0) {
                    m_mode = flow_mode::sticking;
                    m_contact = i;
                    break;
                }
        }
        if constexpr (has_switches) pin_sides_at(x);
        restart(0.0);
    }

    // Integrates until the observer asks to stop (outcome::ok), t_max, or another limit.
    template <class Observer>
    outcome run(Observer& obs)
    {
        begin_run();
        for (;;) {
            if (const auto o = limit_reached()) return *o;
            const step_status st = (m_mode == flow_mode::free) ? step_free(obs) : step_sticking(obs);
            if (const auto o = step_taken(st, obs)) return *o;
        }
    }

    // run() in pieces, for a driver that takes the free steps of several flows at once in SIMD
    // lanes (hybrid/flow_lanes.hpp): begin_run(), then per step limit_reached(), the step
    // (free_step_taken() after the integrator took it outside, or step() in any mode), and
    // step_taken(); a value from either ends the run with that outcome.
    void begin_run()
    {
        m_stop = false;
        m_finished.reset();
    }
    // always_inline: called out of line (the SIMD lanes' driver, hybrid/flow_lanes.hpp, is too
    // large for GCC to inline it), the optional came back through the stack, written as two
    // stores and read as one load that waited for both (a failed store forward), about 10 % of
    // the lanes' time in a profile of bench/lanes_bench.cpp.
    [[nodiscard, gnu::always_inline]] std::optional<outcome> limit_reached() const
    {
        if (m_integ.counters().steps >= m_opt.max_steps) return outcome::step_limit;
        if (m_t >= m_opt.t_max) return outcome::time_limit;
        if (m_stats.impacts >= m_opt.max_impacts) return outcome::impact_limit;
        if (m_opt.cancel && m_opt.cancel->load(std::memory_order_relaxed)) return outcome::interrupted;
        return std::nullopt;
    }
    template <class Observer>
    step_status step(Observer& obs)
    {
        return (m_mode == flow_mode::free) ? step_free(obs) : step_sticking(obs);
    }
    // The free step the integrator has just accepted (integrator().accept_external).
    template <class Observer>
    step_status free_step_taken(Observer& obs)
    {
        auto rhs = free_rhs();
        return after_free_step(obs, rhs);
    }
    // A free step the integrator has just accepted that the driver found quiet: no surface
    // and no watched event can have been crossed in it, decided from the same end samples and
    // by the same rule as after_free_step (hybrid/flow_lanes.hpp), which would only have moved
    // on. Its end samples are not kept (the next step samples its start again: the same numbers).
    // With gap maxima watched (flow_options::gap_maxima), the driver also found no gap's rate
    // turning from rising to falling in the step: each gap's largest value on it is its end
    // value, which report_gap_maxima would report, at the time it would report it (t0 + 1.0 h,
    // which differs from the step's end time in its last bit on a step cut short at t_max).
    template <class Observer>
    void quiet_free_step(Observer& obs)
    {
        m_retractions = 0;
        m_free_step_max = std::max(m_free_step_max, m_integ.last_step());
        m_t = m_integ.t();
        m_x = m_integ.x();
        m_ends_valid = false;
        if (m_opt.gap_maxima && m_opt.surfaces && !m_stop) {
            const double t_end = m_integ.t_prev() + 1.0 * m_integ.last_step();
            for (int i = 0; i < m_model.surface_count(); ++i) obs.on_gap_maximum(i, t_end, m_model.gap(i, m_x));
        }
    }
    // Several quiet free steps the driver kept in its lanes and the integrator has just taken
    // over (accept_external_steps), each of which quiet_free_step and step_taken would have
    // followed. The driver let them pass only where those calls could change nothing but the
    // gaps' largest values (Observer::step_end_acts_from, no time series, no limit reached), so
    // the observer hears of each gap once, with the largest of its end values, gap_max(i)
    // (>= as on_gap_maximum compares, the first one taken), at the last step's end time.
    template <class Observer, class GapMax>
    void quiet_free_steps(Observer& obs, double step_max, GapMax&& gap_max)
    {
        m_retractions = 0;
        m_free_step_max = std::max(m_free_step_max, step_max);
        m_t = m_integ.t();
        m_x = m_integ.x();
        m_ends_valid = false;
        if (m_opt.gap_maxima && m_opt.surfaces && !m_stop)
            for (int i = 0; i < m_model.surface_count(); ++i) obs.on_gap_maximum(i, m_t, gap_max(i));
    }
    template <class Observer>
    std::optional<outcome> step_taken(step_status st, Observer& obs)
    {
        if (st == step_status::step_underflow) return outcome::step_underflow;
        if (st == step_status::non_finite) return outcome::non_finite;
        if (st == step_status::retracted) return std::nullopt;  // no time passed: nothing to tell
        if (m_finished) return *m_finished;
        if (!m_stop && obs.on_step_end(m_t) == flow_control::stop) m_stop = true;
        if (m_stop) return outcome::ok;
        return std::nullopt;
    }
    [[nodiscard]] integrator_type& integrator() { return m_integ; }
    [[nodiscard]] const integrator_type& integrator() const { return m_integ; }

    [[nodiscard]] double t() const { return m_t; }
    [[nodiscard]] const state& x() const { return m_x; }
    [[nodiscard]] flow_mode mode() const { return m_mode; }
    [[nodiscard]] int contact_surface() const { return m_contact; }
    [[nodiscard]] const Model& model() const { return m_model; }
    [[nodiscard]] const flow_options& options() const { return m_opt; }
    // stats().sticking_phases without the copy of the statistics (a driver asks after every step).
    [[nodiscard]] long sticking_phases() const { return m_stats.sticking_phases; }
    [[nodiscard]] run_stats stats() const
    {
        run_stats s = m_stats;
        const auto& c = m_integ.counters();
        s.steps = c.steps;
        s.rejected = c.rejected;
        s.rhs_calls = c.rhs_calls;
        s.h_min = c.h_min;
        s.h_max = c.h_max;
        s.t_final = m_t;
        return s;
    }

    // The resolution of gap i near zero at x (see the header).
    [[nodiscard]] double hop_resolution(int i, const state& x) const
    {
        if (m_opt.sticking_height >= 0.0) return m_opt.sticking_height;
        gap_gradient_into(m_model, i, x, m_gradient);
        return resolution(m_gradient, x);
    }
    // 256 ulps of max(1, sum_j |dg/dx_j x_j|): the resolution near zero of a function g of the
    // state with this gradient at x.
    [[nodiscard]] static double resolution(const state& gradient, const state& x)
    {
        return 256.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, gradient.cwiseProduct(x).cwiseAbs().sum());
    }

private:
    // The value and rate (gradient . F) of an event function at a step end; the slope on the
    // step's interpolant is the rate times the step.
    struct end_sample {
        double value = 0.0, rate = 0.0;
        [[nodiscard]] scalar_sample at(double h) const { return {value, rate * h}; }
    };
    struct end_samples {
        std::vector<end_sample> gaps, events, switches;  // switches: side * h_k, held sides
    };
    static constexpr bool has_switches = switching_model<Model>;

    // The sides of the switches at a start x: the sign of h_k, and where h_k = 0 the side the
    // motion moves into.
    void pin_sides_at(const state& x)
        requires has_switches
    {
        switch_sides sides;
        for (int k = 0; k < m_model.switch_count(); ++k) {
            const double h = m_model.switching(k, x);
            sides.set(k, h > 0.0 || (h == 0.0 && m_model.switching_derivative(k, x, m_model.rhs(x)) >= 0.0));
        }
        m_model.pin_sides(sides);
    }
    // Switch k's value as an event function: side * h_k, positive until its crossing.
    [[nodiscard]] double switch_value(int k, const state& x) const
    {
        if constexpr (has_switches) return m_model.sides_at(x).side(k) * m_model.switching(k, x);
        else return (void)k, (void)x, 0.0;
    }
    [[nodiscard]] double switch_derivative(int k, const state& x, const state& v) const
    {
        if constexpr (has_switches) return m_model.sides_at(x).side(k) * m_model.switching_derivative(k, x, v);
        else return (void)k, (void)x, (void)v, 0.0;
    }

    [[nodiscard]] bool absent(int i) const
    {
        return i < 64 && ((m_opt.absent_surfaces >> i) & 1U) != 0 && m_t >= m_opt.absent_from &&
               m_t <= m_opt.absent_until;
    }

    free_field<Model> free_rhs() const { return {&m_model}; }
    auto contact_rhs() const
    {
        return [this](const state& x) { return m_model.sticking_rhs(m_contact, x); };
    }

    void restart(double h_hint)
    {
        m_ends_valid = false;
        if (m_mode == flow_mode::free) m_integ.start(free_rhs(), m_t, m_x, h_hint);
        else m_integ.start(contact_rhs(), m_t, m_x, h_hint);
    }

    // A scalar function of the state and its derivative along a direction (x, v) -> dg/dx v,
    // as seen along the interpolant.
    template <class Rhs, class Value, class Derivative>
    auto on_dense(Rhs& rhs, Value&& value, Derivative&& derivative)
    {
        return [this, &rhs, value, derivative](double theta) {
            m_integ.dense(rhs).value_and_slope(theta, m_point, m_slope);
            return scalar_sample{value(m_point), derivative(m_point, m_slope)};
        };
    }

    // Puts a located crossing exactly on its surface when the event function is a coordinate
    // (up to a constant: its gradient a unit vector e_j, e.g. a velocity section or the
    // paper's gap y - sigma): one Newton step in x_j, kept only if the function is then exactly
    // zero. Anything else (sin(phi) near phi = 2 pi k has a gradient that rounds to a unit
    // vector too) keeps the root finder's point, which lies on the far side of the crossing.
    template <class Value>
    static void polish(Value&& value_at, const state& gradient, state& p, state& q)
    {
        int j = -1;
        for (int k = 0; k < gradient.size(); ++k) {
            if (gradient[k] == 0.0) continue;
            if (j >= 0 || std::abs(gradient[k]) != 1.0) return;
            j = k;
        }
        if (j < 0) return;
        q = p;
        q[j] -= value_at(p) / gradient[j];
        if (value_at(q) == 0.0) p = q;
    }

    // The event functions' values and rates at the ends of the step just taken: the start's
    // are the previous step's end when the trajectory went on from there, so each state is
    // sampled once. A model that evaluates every gap and section in one call (a table model's
    // `samples`) is asked once per state.
    void sample_step_ends(bool gaps)
    {
        // The end's samples copied into the start's, not the containers swapped: the copy
        // of a few numbers is cheaper on this path than moving the containers' pointers.
        if (m_ends_valid) {
            std::copy(m_end.gaps.begin(), m_end.gaps.end(), m_start.gaps.begin());
            std::copy(m_end.events.begin(), m_end.events.end(), m_start.events.begin());
            if constexpr (has_switches) std::copy(m_end.switches.begin(), m_end.switches.end(), m_start.switches.begin());
        } else {
            sample_at(m_integ.x_prev(), m_integ.f_prev(), gaps, m_start);
        }
        sample_at(m_integ.x(), m_integ.f(), gaps, m_end);
        m_ends_valid = false;  // set again when the step ends without a reset
    }

    void sample_at(const state& x, const state& f, bool gaps, end_samples& out)
    {
        const int S = gaps ? m_model.surface_count() : 0;
        bool batched = false;
        if constexpr (requires { m_model.samples(x, f, m_batch_gaps.data(), m_batch_sections.data()); }) {
            batched = m_model.samples(x, f, m_batch_gaps.data(), m_batch_sections.data());
        }
        for (int i = 0; i < S; ++i) {
            const auto k = static_cast<std::size_t>(i);
            out.gaps[k] = batched ? end_sample{m_batch_gaps[2 * k], m_batch_gaps[2 * k + 1]}
                                  : end_sample{m_model.gap(i, x), gap_derivative(m_model, i, x, f)};
        }
        if constexpr (has_switches)
            for (std::size_t k = 0; k < out.switches.size(); ++k)
                out.switches[k] = {switch_value(static_cast<int>(k), x), switch_derivative(static_cast<int>(k), x, f)};
        for (std::size_t e = 0; e < m_opt.events.size(); ++e) {
            const flow_event& ev = m_opt.events[e];
            if (batched && ev.kind == flow_event::source::section) {
                const auto k = static_cast<std::size_t>(ev.index);
                out.events[e] = {m_batch_sections[2 * k], m_batch_sections[2 * k + 1]};
            } else {
                out.events[e] = {event_value(ev, x), event_derivative(ev, x, f)};
            }
        }
    }

    [[nodiscard]] double event_value(const flow_event& e, const state& x) const
    {
        switch (e.kind) {
            case flow_event::source::section: return m_model.section(e.index, x);
            case flow_event::source::gap_rate: return gap_rate(m_model, e.index, x);
            case flow_event::source::state_rate: break;
            case flow_event::source::switch_rate: return switch_derivative(e.index, x, m_model.rhs(x));
        }
        return m_model.rhs(x)[e.index];
    }
    [[nodiscard]] double event_derivative(const flow_event& e, const state& x, const state& v) const
    {
        if (e.kind == flow_event::source::section) return section_derivative(m_model, e.index, x, v);
        if (e.kind == flow_event::source::switch_rate) return switch_rate_derivative(e.index, x, v);
        return event_gradient(e, x).dot(v);
    }
    // The derivative along v of r = side * grad h_k . F, by a central difference of r along v:
    // the model gives no second derivatives of a switching function (nor, for the tangent
    // flow's model, a Jacobian). It only shapes the cubic through the step's ends that
    // brackets an extremum; the extremum itself is located on the values of r.
    [[nodiscard]] double switch_rate_derivative(int k, const state& x, const state& v) const
    {
        if constexpr (has_switches) {
            const double scale = v.template lpNorm<Eigen::Infinity>();
            if (!(scale > 0.0)) return 0.0;
            const double eps = 1e-6 * (1.0 + x.template lpNorm<Eigen::Infinity>()) / scale;
            const state a = x + eps * v, b = x - eps * v;
            return (switch_derivative(k, a, m_model.rhs(a)) - switch_derivative(k, b, m_model.rhs(b))) / (2.0 * eps);
        } else {
            return (void)k, (void)x, (void)v, 0.0;
        }
    }
    [[nodiscard]] state event_gradient(const flow_event& e, const state& x) const
    {
        switch (e.kind) {
            case flow_event::source::section: return m_model.section_gradient(e.index, x);
            case flow_event::source::gap_rate: return gap_rate_gradient(m_model, e.index, x);
            case flow_event::source::state_rate: break;
            case flow_event::source::switch_rate: return state::Zero(x.size());  // polish() passes it by
        }
        return state_rate_gradient(m_model, e.index, x);
    }
    // The same into `out`: a section's without allocating (the runtime-sized flow locates
    // its crossings on every step that holds one).
    void event_gradient_into(const flow_event& e, const state& x, state& out) const
    {
        if (e.kind == flow_event::source::section) section_gradient_into(m_model, e.index, x, out);
        else out = event_gradient(e, x);
    }

    // The watched events' crossings in (0, theta_end], in time order, reported to the
    // observer (the step-end samples are taken: sample_step_ends).
    template <class Observer, class Rhs>
    void report_events(Observer& obs, Rhs& rhs, double theta_end)
    {
        if (m_opt.events.empty()) return;
        const double h = m_integ.last_step();
        const double t0 = m_integ.t_prev();
        struct found_event {
            double theta;
            int event;
            crossing direction;
        };
        std::array<found_event, 16> found;  // only the first nfound are read
        int nfound = 0;
        for (int e = 0; e < static_cast<int>(m_opt.events.size()); ++e) {
            const flow_event& ev = m_opt.events[static_cast<std::size_t>(e)];
            auto g = on_dense(
                rhs, [this, &ev](const state& x) { return event_value(ev, x); },
                [this, &ev](const state& x, const state& v) { return event_derivative(ev, x, v); });
            const scalar_sample s0 = m_start.events[static_cast<std::size_t>(e)].at(h);
            const scalar_sample s1 = m_end.events[static_cast<std::size_t>(e)].at(h);
            auto collect = [&](crossing dir) {
                return [&, dir](double th) {
                    if (th > theta_end || nfound >= static_cast<int>(found.size())) return false;
                    found[static_cast<std::size_t>(nfound++)] = {th, e, dir};
                    return true;
                };
            };
            if (ev.direction != crossing::up)
                find_crossings(crossing_direction::down, g, s0, s1, collect(crossing::down), m_opt.event_subdivisions);
            if (ev.direction != crossing::down)
                find_crossings(crossing_direction::up, g, s0, s1, collect(crossing::up), m_opt.event_subdivisions);
        }
        // Insertion sort: a handful of crossings (std::sort trips a false -Warray-bounds in
        // GCC 12 here).
        for (int i = 1; i < nfound; ++i)
            for (int j = i; j > 0 && found[static_cast<std::size_t>(j)].theta < found[static_cast<std::size_t>(j - 1)].theta; --j)
                std::swap(found[static_cast<std::size_t>(j)], found[static_cast<std::size_t>(j - 1)]);
        for (int i = 0; i < nfound; ++i) {
            ++m_stats.sections;
            if (m_stop) continue;
            const auto& fe = found[static_cast<std::size_t>(i)];
            const flow_event& ev = m_opt.events[static_cast<std::size_t>(fe.event)];
            state& p = m_pre;
            m_integ.dense(rhs).value_at(fe.theta, p);
            event_gradient_into(ev, p, m_gradient);
            polish([&](const state& y) { return event_value(ev, y); }, m_gradient, p, m_slope);
            if (obs.on_section(fe.event, fe.direction, t0 + fe.theta * h, p) == flow_control::stop) {
                m_stop = true;
                m_stop_theta = fe.theta;
            }
        }
    }

    template <class Observer>
    step_status step_free(Observer& obs)
    {
        auto rhs = free_rhs();
        const step_status st = m_integ.advance(rhs, m_opt.t_max);
        if (st != step_status::ok) return st;
        return after_free_step(obs, rhs);
    }

    template <class Observer, class Rhs>
    step_status after_free_step(Observer& obs, Rhs& rhs)
    {
        const double h = m_integ.last_step();
        sample_step_ends(m_opt.surfaces);
        if (m_check_any && m_retractions < max_retractions) {
            const auto d = worst_deviation(h);
            if (d.error > d.allowed) {
                ++m_retractions;
                m_integ.retract(h * event_resolution::step_factor(d));
                m_ends_valid = false;
                return step_status::retracted;
            }
        }
        m_retractions = 0;
        m_free_step_max = std::max(m_free_step_max, h);
        const double t0 = m_integ.t_prev();
        const state& x0 = m_integ.x_prev();
        const state& x1 = m_integ.x();
        if (quiet_step(h)) {
            // What the general path below does when it finds nothing.
            m_stop_theta = 2.0;
            if (m_opt.gap_maxima && m_opt.surfaces && !m_stop)
                for (int i = 0; i < m_model.surface_count(); ++i)
                    obs.on_gap_maximum(i, t0 + 1.0 * h, m_end.gaps[static_cast<std::size_t>(i)].value);
            if (!m_stop && obs.wants_segments()) obs.on_segment(m_integ.dense(rhs), t0, m_integ.t(), flow_mode::free);
            m_t = m_integ.t();
            m_x = x1;
            m_ends_valid = true;
            return step_status::ok;
        }

        // Terminal event: the first crossing of any surface inside (t0, t1].
        double theta_impact = 2.0;
        int surface = -1;
        if (m_opt.surfaces) {
            for (int i = 0; i < m_model.surface_count(); ++i) {
                if (absent(i)) continue;
                const scalar_sample s0 = m_start.gaps[static_cast<std::size_t>(i)].at(h);
                const scalar_sample s1 = m_end.gaps[static_cast<std::size_t>(i)].at(h);
                const double theta = gap_crossing(rhs, i, s0, s1);
                if (theta < theta_impact) {
                    theta_impact = theta;
                    surface = i;
                }
                // A rebound too small for doubles: the step left the surface (g <= 0) and
                // ended below it moving in, without the gap ever turning positive. The hop
                // was below the resolution of the gap.
                if (theta > 1.0 && s0.value <= 0.0 && s1.value < 0.0 && s1.slope <= 0.0 && unresolved_hop(obs, i, t0, x0))
                    return step_status::ok;
            }
        }

        // No crossing found, yet a present gap ends beyond its surface.
        if (theta_impact > 1.0 &&
            ended_beyond_unseen(-1, [this](int i) { return m_end.gaps[static_cast<std::size_t>(i)].value; }))
            return step_status::ok;

        // The first crossing of a switching surface; before the step's impact, it ends the step.
        const auto [theta_switch, sw] = first_switch_crossing(rhs, h);
        if (sw < 0 && ended_on_other_side()) return step_status::ok;
        const bool switch_first = theta_switch < theta_impact;
        const double theta_first = std::min(theta_impact, theta_switch);

        const bool stopped_before = m_stop;
        m_stop_theta = 2.0;
        report_events(obs, rhs, theta_first);
        // The gaps up to the impact, or up to the crossing at which the observer stopped.
        if (m_opt.gap_maxima && m_opt.surfaces && !stopped_before)
            report_gap_maxima(obs, rhs, std::min(theta_first, m_stop_theta),
                              m_stop_theta < theta_first || switch_first ? -1 : surface);

        if (switch_first) {
            const auto& d = m_integ.dense(rhs);
            const double t_switch = (theta_switch >= 1.0) ? m_integ.t() : t0 + theta_switch * h;
            if (!m_stop && obs.wants_segments()) obs.on_segment(d, t0, t_switch, flow_mode::free);
            take_switch(obs, d, sw, theta_switch, t_switch);
            return step_status::ok;
        }

        if (theta_impact > 1.0) {
            if (!m_stop && obs.wants_segments()) obs.on_segment(m_integ.dense(rhs), t0, m_integ.t(), flow_mode::free);
            m_t = m_integ.t();
            m_x = x1;
            m_ends_valid = true;
            return step_status::ok;
        }

        const auto& d = m_integ.dense(rhs);
        const double t_impact = (theta_impact >= 1.0) ? m_integ.t() : t0 + theta_impact * h;
        if (!m_stop && obs.wants_segments()) obs.on_segment(d, t0, t_impact, flow_mode::free);
        if (take_impact(obs, d, surface, theta_impact, t_impact)) after_impact(obs, surface);
        return step_status::ok;
    }

    // The impact on `surface` at theta (time t_impact) of the step just taken, whose
    // interpolant is d: the state put on the surface and reset, counted and reported, then
    // the other surfaces reached at that instant. False when the run ends there: a state not
    // finite, or a reset that is not admissible.
    template <class Observer, class Dense>
    bool take_impact(Observer& obs, const Dense& d, int surface, double theta, double t_impact)
    {
        state& pre = m_pre;
        if (theta >= 1.0) pre = m_integ.x();
        else d.value_at(theta, pre);
        gap_gradient_into(m_model, surface, pre, m_gradient);
        polish([&](const state& y) { return m_model.gap(surface, y); }, m_gradient, pre, m_slope);
        reset_into(m_model, surface, pre, m_post);
        const state& post = m_post;
        if (const auto fault = !pre.allFinite() ? std::optional<outcome>(outcome::non_finite) : reset_fault(surface, post)) {
            // The run ends at the last finite state: the impact's, else the step's start (the
            // interpolant of a step near overflow can overflow where its ends did not).
            const bool at_impact = pre.allFinite();
            m_t = at_impact ? t_impact : m_integ.t_prev();
            m_x = at_impact ? pre : m_integ.x_prev();
            m_finished = *fault;
            return false;
        }
        ++m_stats.impacts;
        ++m_stats.impacts_by_surface[static_cast<std::size_t>(surface)];
        if (!m_stop && obs.on_impact(surface, t_impact, pre, post) == flow_control::stop) m_stop = true;
        m_t = t_impact;
        m_x = post;
        simultaneous_impacts(obs, surface);
        return !m_finished;
    }

    // The other surfaces the state reaches at the same instant as surface `first` (identical
    // copies of a system hit their stops together; a symmetric pair hits both neighbours):
    // each one whose gap is zero to within its resolution and closing takes its impact now,
    // after `first`'s, in the order of the surfaces (a tie goes to the lower index). Without
    // this the next step would start beyond that surface and the run would end inadmissible.
    template <class Observer>
    void simultaneous_impacts(Observer& obs, int first)
    {
        for (int j = 0; j < m_model.surface_count(); ++j) {
            if (j == first || j == m_contact || absent(j)) continue;
            if (!(m_model.gap(j, m_x) <= hop_resolution(j, m_x)) || !(gap_rate(m_model, j, m_x) < 0.0)) continue;
            m_pre = m_x;
            reset_into(m_model, j, m_pre, m_post);
            if (const auto fault = reset_fault(j, m_post)) {
                m_finished = *fault;
                return;
            }
            ++m_stats.impacts;
            ++m_stats.impacts_by_surface[static_cast<std::size_t>(j)];
            if (!m_stop && obs.on_impact(j, m_t, m_pre, m_post) == flow_control::stop) m_stop = true;
            m_x = m_post;
        }
    }

    // The first crossing of a switching surface in the step just taken (end samples taken):
    // (theta, switch), or (2, -1) where there is none.
    template <class Rhs>
    std::pair<double, int> first_switch_crossing(Rhs& rhs, double h)
    {
        double theta_first = 2.0;
        int first = -1;
        for (int k = 0; k < static_cast<int>(m_start.switches.size()); ++k) {
            auto g = on_dense(
                rhs, [this, k](const state& x) { return switch_value(k, x); },
                [this, k](const state& x, const state& v) { return switch_derivative(k, x, v); });
            double theta = 2.0;
            find_crossings(crossing_direction::down, g, m_start.switches[static_cast<std::size_t>(k)].at(h),
                           m_end.switches[static_cast<std::size_t>(k)].at(h), [&](double th) { theta = th; return false; },
                           m_opt.event_subdivisions);
            if (theta < theta_first) {
                theta_first = theta;
                first = k;
            }
        }
        return {theta_first, first};
    }

    // No crossing of a switch located, yet the step ended on the other side of one: it started
    // on the surface (a crossing just taken) and the field of the new side turned it back. The
    // fields on both sides point into the surface, where the motion would slide (Filippov),
    // which a switch does not model: the run ends with `sliding` at the step's start.
    bool ended_on_other_side()
    {
        for (const end_sample& e : m_end.switches)
            if (e.value < 0.0) return end_at_step_start(outcome::sliding);
        return false;
    }

    // Ends the run with `o` at the start of the step just taken (its last state known to be
    // good). True.
    bool end_at_step_start(outcome o)
    {
        m_t = m_integ.t_prev();
        m_x = m_integ.x_prev();
        m_finished = o;
        return true;
    }

    // The crossing of switch k at theta (time t) of the step just taken, whose interpolant is
    // d: the state put on the surface, the side changed, the switch's reset applied where it
    // does, counted and reported; the integration starts again with the field of the new side.
    template <class Observer, class Dense>
    void take_switch(Observer& obs, const Dense& d, int k, double theta, double t)
    {
        if constexpr (has_switches) {
            state& pre = m_pre;
            if (theta >= 1.0) pre = m_integ.x();
            else d.value_at(theta, pre);
            m_gradient = m_model.sides_at(pre).side(k) * m_model.switching_gradient(k, pre);
            polish([&](const state& y) { return switch_value(k, y); }, m_gradient, pre, m_slope);
            if (!pre.allFinite()) {
                end_at_step_start(outcome::non_finite);
                return;
            }
            m_model.cross(k, pre, m_post);
            const state& post = m_post;
            m_t = t;
            if (!post.allFinite()) {
                m_x = pre;
                m_finished = outcome::non_finite;
                return;
            }
            ++m_stats.switchings;
            if (!m_stop && obs.on_switch(k, t, pre, post) == flow_control::stop) m_stop = true;
            m_x = post;
            if (m_opt.surfaces)
                for (int j = 0; j < m_model.surface_count(); ++j)
                    if (!absent(j) && m_model.gap(j, post) < -hop_resolution(j, post)) {
                        m_finished = outcome::inadmissible;
                        return;
                    }
            if (slides_after(k, post)) {
                m_finished = outcome::sliding;
                return;
            }
            restart(m_integ.step_size());
        } else {
            (void)obs, (void)d, (void)k, (void)theta, (void)t;
        }
    }
    // Whether the motion stays on switch k after its crossing at `post` (sides changed): the
    // new side's field points back into the surface (Filippov sliding), or it leaves the
    // surface too slowly to get away from it. The second is the switch's chattering rule: a
    // rate of side * h below sticking_velocity that the new side's field turns back (its
    // derivative along the field, by a difference over a short time, negative), as the
    // crossings of a rocking block coming to rest accumulate, each slower by its restitution.
    // Without it their number would be bounded only by the time resolution.
    [[nodiscard]] bool slides_after(int k, const state& post) const
    {
        if (!(std::abs(m_model.switching(k, post)) <= hop_resolution_of_switch(k, post))) return false;
        const auto field = [&](const state& x) {
            return m_mode == flow_mode::free ? state(m_model.rhs(x)) : state(m_model.sticking_rhs(m_contact, x));
        };
        const state f = field(post);
        const double u = switch_derivative(k, post, f);
        if (u < 0.0) return true;
        if (!(u < m_opt.sticking_velocity)) return false;
        const double tau = 1e-6 * std::max(1.0, m_integ.step_size());
        const state y = post + tau * f;
        return (switch_derivative(k, y, field(y)) - u) / tau < 0.0;
    }

    // The resolution of switching function k near zero at x, as hop_resolution's of a gap.
    [[nodiscard]] double hop_resolution_of_switch(int k, const state& x) const
    {
        if constexpr (has_switches) {
            return resolution(m_model.switching_gradient(k, x), x);
        } else {
            return (void)k, (void)x, 0.0;
        }
    }

    // Event functions the integrator's error control resolves: affine functions of the state
    // and the rates of state variables (the derivatives of such functions along the flow).
    [[nodiscard]] bool resolved_by_integrator(const flow_event& e) const
    {
        switch (e.kind) {
            case flow_event::source::section: return section_is_affine(m_model, e.index);
            case flow_event::source::gap_rate: return gap_is_affine(m_model, e.index);
            case flow_event::source::state_rate: break;
            case flow_event::source::switch_rate:
                if constexpr (has_switches) return m_model.switching_affine(e.index);
                else return true;
        }
        return true;
    }

    // The largest deviation from its cubic, relative to what is tolerated, of the event
    // functions checked on the step just taken (end samples taken): error <= allowed when all
    // are resolved.
    [[nodiscard]] event_resolution::deviation<double> worst_deviation(double h) const
    {
        event_resolution::deviation<double> worst{0.0, 1.0};
        for (int point = 0; point < 2; ++point) {
            state& xc = m_point;
            event_resolution::hermite_state<N>(point, m_integ.x_prev(), m_integ.f_prev(), m_integ.x(), m_integ.f(), h, xc);
            const auto consider = [&](const end_sample& a, const end_sample& b, double vc) {
                const scalar_sample s0 = a.at(h), s1 = b.at(h);
                const auto d = event_resolution::deviation_at(point, s0.value, s0.slope, s1.value, s1.slope, vc);
                // Compared as error / allowed without dividing (allowed may be 0).
                if (d.error * worst.allowed > worst.error * d.allowed) worst = d;
            };
            if (m_opt.surfaces)
                for (int i = 0; i < m_model.surface_count(); ++i)
                    if (m_check_gap[static_cast<std::size_t>(i)] && !absent(i))
                        consider(m_start.gaps[static_cast<std::size_t>(i)], m_end.gaps[static_cast<std::size_t>(i)],
                                 m_model.gap(i, xc));
            for (std::size_t e = 0; e < m_opt.events.size(); ++e)
                if (m_check_event[e]) consider(m_start.events[e], m_end.events[e], event_value(m_opt.events[e], xc));
            for (std::size_t k = 0; k < m_check_switch.size(); ++k)
                if (m_check_switch[k])
                    consider(m_start.switches[k], m_end.switches[k], switch_value(static_cast<int>(k), xc));
        }
        return worst;
    }

    // What is wrong with the state a reset of surface i gave, if anything (see the header).
    [[nodiscard]] std::optional<outcome> reset_fault(int i, const state& post) const
    {
        if (!post.allFinite()) return outcome::non_finite;
        for (int j = 0; j < m_model.surface_count(); ++j)
            if (!absent(j) && m_model.gap(j, post) < -hop_resolution(j, post)) return outcome::inadmissible;
        if (m_model.gap(i, post) <= hop_resolution(i, post) && gap_rate(m_model, i, post) < -m_opt.sticking_velocity)
            return outcome::inadmissible;
        return std::nullopt;
    }

    // Whether the free step just taken (end samples taken) is quiet: find_crossings' screening
    // finds no possible crossing of any surface (each gap positive at one end at least) or watched
    // event, and no gap's rate turns from rising to falling (report_gap_maxima's test for a
    // maximum inside the step). The general path of after_free_step would then find nothing;
    // deciding it from the samples alone skips that path's setup on most steps (about a tenth
    // of a step's time: docs/performance.md).
    [[nodiscard]] bool quiet_step(double h) const
    {
        if (m_opt.surfaces)
            for (int i = 0; i < m_model.surface_count(); ++i) {
                const scalar_sample s0 = m_start.gaps[static_cast<std::size_t>(i)].at(h);
                const scalar_sample s1 = m_end.gaps[static_cast<std::size_t>(i)].at(h);
                // A step from a gap <= 0 to a positive one (the step after an impact starts on
                // the surface) is only screened: the general path's crossing search and its
                // unresolved-hop rule (which needs a negative end) then find nothing either.
                if (!absent(i) && ((!(s0.value > 0.0) && !(s1.value > 0.0)) ||
                                   down_crossing_possible(s0.value, s1.value, s0.slope, s1.slope, 1.0)))
                    return false;
                if (m_opt.gap_maxima && s0.slope > 0.0 && s1.slope <= 0.0) return false;
            }
        if constexpr (has_switches)
            for (std::size_t k = 0; k < m_start.switches.size(); ++k) {
                const scalar_sample s0 = m_start.switches[k].at(h), s1 = m_end.switches[k].at(h);
                if ((!(s0.value > 0.0) && !(s1.value > 0.0)) || s1.value < 0.0 ||
                    down_crossing_possible(s0.value, s1.value, s0.slope, s1.slope, 1.0))
                    return false;
            }
        for (std::size_t e = 0; e < m_opt.events.size(); ++e) {
            const scalar_sample s0 = m_start.events[e].at(h), s1 = m_end.events[e].at(h);
            const crossing dir = m_opt.events[e].direction;
            if (dir != crossing::up && down_crossing_possible(s0.value, s1.value, s0.slope, s1.slope, 1.0)) return false;
            if (dir != crossing::down && down_crossing_possible(-s0.value, -s1.value, -s0.slope, -s1.slope, 1.0))
                return false;
        }
        return true;
    }

    // Each gap's largest value on (0, theta_end] of the step just taken (theta_end < 1: an
    // impact on surface `impacting` there, where its gap is 0). A maximum is bracketed by the
    // gap's rate, known at the step's ends, and located on its slope along the interpolant by
    // the event locator's extremum search (a few interpolant evaluations); a step with two
    // interior extrema (longer than half an oscillation of the gap) reports its end value only.
    template <class Observer, class Rhs>
    void report_gap_maxima(Observer& obs, Rhs& rhs, double theta_end, int impacting)
    {
        theta_end = std::min(theta_end, 1.0);
        const double h = m_integ.last_step();
        const double t0 = m_integ.t_prev();
        for (int i = 0; i < m_model.surface_count(); ++i) {
            const double slope_start = m_start.gaps[static_cast<std::size_t>(i)].rate * h;  // per unit theta
            double value = m_end.gaps[static_cast<std::size_t>(i)].value;
            double slope_end = m_end.gaps[static_cast<std::size_t>(i)].rate * h;
            if (theta_end < 1.0) {
                m_integ.dense(rhs).value_and_slope(theta_end, m_point, m_slope);
                value = i == impacting ? 0.0 : m_model.gap(i, m_point);
                slope_end = gap_derivative(m_model, i, m_point, m_slope);
            }
            double best = value, theta_best = theta_end;
            if (slope_start > 0.0 && slope_end < 0.0) {
                auto g = on_dense(
                    rhs, [this, i](const state& x) { return m_model.gap(i, x); },
                    [this, i](const state& x, const state& v) { return gap_derivative(m_model, i, x, v); });
                const double c =
                    detail::extremum_bracketed(g, 0.0, m_start.gaps[static_cast<std::size_t>(i)].at(h), theta_end, {value, slope_end});
                m_integ.dense(rhs).value_at(c, m_point);
                const double gc = m_model.gap(i, m_point);
                if (gc > best) {
                    best = gc;
                    theta_best = c;
                }
            }
            obs.on_gap_maximum(i, t0 + theta_best * h, best);
        }
    }

    // The rebound rule at (m_t, m_x), just after an impact on surface i.
    template <class Observer>
    void after_impact(Observer& obs, int i)
    {
        // A reset that moved the state off the surface: a new flight, whatever its speed.
        if (m_model.gap(i, m_x) > hop_resolution(i, m_x)) {
            restart(m_integ.step_size());
            return;
        }
        const double u = gap_rate(m_model, i, m_x);
        if (m_model.sticks(i)) {
            const state rest = m_model.rest(i, m_x);
            const double a = m_model.release(i, rest);
            if (negligible_rebound(i, rest, u, a) && a <= 0.0) {
                enter_sticking(obs, i, m_t, rest);
                return;
            }
        } else {
            const double a = gap_rate_gradient(m_model, i, m_x).dot(m_model.rhs(m_x));
            if (negligible_rebound(i, m_x, u, a) && a <= 0.0) {
                m_finished = outcome::chattering;
                return;
            }
        }
        restart(m_integ.step_size());
    }

    [[nodiscard]] bool negligible_rebound(int i, const state& at, double u, double a) const
    {
        const double hop = hop_resolution(i, at);
        return u < m_opt.sticking_velocity || (a < 0.0 && u * u < 2.0 * hop * -a);
    }

    // Ends the step at its start in a contact phase or with the outcome chattering; false when
    // the surface pushes the state away (the step then goes on as usual).
    template <class Observer>
    bool unresolved_hop(Observer& obs, int i, double t0, const state& x0)
    {
        if (m_model.sticks(i)) {
            const state rest = m_model.rest(i, x0);
            if (m_model.release(i, rest) > 0.0) return false;
            enter_sticking(obs, i, t0, rest);
            return true;
        }
        if (gap_rate_gradient(m_model, i, x0).dot(m_model.rhs(x0)) > 0.0) return false;
        m_t = t0;
        m_x = x0;
        m_finished = outcome::chattering;
        return true;
    }

    template <class Observer>
    void enter_sticking(Observer& obs, int i, double t, const state& rest)
    {
        m_t = t;
        m_x = rest;
        m_mode = flow_mode::sticking;
        m_contact = i;
        ++m_stats.sticking_phases;
        if (!m_stop) obs.on_stick(i, m_t, m_x);
        restart(m_integ.step_size());
    }

    template <class Observer>
    step_status step_sticking(Observer& obs)
    {
        auto rhs = contact_rhs();
        // A constrained field the error control does not limit (the forced oscillator at rest
        // on its barrier: only the phase moves) would let the step grow over several periods
        // of the release function, whose crossings the step's samples then miss: contact steps
        // are kept no longer than the longest free-flight step, the motion's own time scale.
        const double t_stop = m_free_step_max > 0.0 ? std::min(m_opt.t_max, m_t + m_free_step_max) : m_opt.t_max;
        const step_status st = m_integ.advance(rhs, t_stop);
        if (st != step_status::ok) return st;
        const double h = m_integ.last_step();
        const double t0 = m_integ.t_prev();
        const state& x0 = m_integ.x_prev();
        const state& x1 = m_integ.x();
        const int i = m_contact;

        double theta_release = 2.0;
        auto ga = on_dense(
            rhs, [this, i](const state& x) { return m_model.release(i, x); },
            [this, i](const state& x, const state& v) { return m_model.release_gradient(i, x).dot(v); });
        const scalar_sample s0{m_model.release(i, x0), m_model.release_gradient(i, x0).dot(m_integ.f_prev()) * h};
        const scalar_sample s1{m_model.release(i, x1), m_model.release_gradient(i, x1).dot(m_integ.f()) * h};
        find_crossings(crossing_direction::up, ga, s0, s1, [&](double th) { theta_release = th; return false; },
                       m_opt.event_subdivisions);
        // The other surfaces, which the motion in contact can reach (a ball sliding on the floor
        // into a wall): the first crossing in time, as in free flight.
        double theta_impact = 2.0;
        int surface = -1;
        if (m_opt.surfaces)
            for (int j = 0; j < m_model.surface_count(); ++j) {
                if (j == i || absent(j)) continue;
                const scalar_sample g0{m_model.gap(j, x0), gap_derivative(m_model, j, x0, m_integ.f_prev()) * h};
                const scalar_sample g1{m_model.gap(j, x1), gap_derivative(m_model, j, x1, m_integ.f()) * h};
                const double theta = gap_crossing(rhs, j, g0, g1);
                if (theta < theta_impact) {
                    theta_impact = theta;
                    surface = j;
                }
            }
        if (theta_impact >= theta_release) surface = -1;  // released first (or neither)
        // No crossing found, yet another surface ends beyond: crossed unseen, as in flight.
        if (surface < 0 && theta_release > 1.0 &&
            ended_beyond_unseen(i, [this, &x1](int j) { return m_model.gap(j, x1); }))
            return step_status::ok;
        sample_step_ends(false);
        // A switching surface crossed in contact (a compliant support the resting body slides
        // onto) before the release and any impact.
        const auto [theta_switch, sw] = first_switch_crossing(rhs, h);
        if (sw < 0 && theta_release > 1.0 && surface < 0 && ended_on_other_side()) return step_status::ok;
        const bool switch_first = theta_switch < std::min(theta_release, theta_impact);
        if (switch_first) surface = -1;
        const double theta_stop = std::min({theta_release, theta_impact, theta_switch});

        report_events(obs, rhs, theta_stop);
        if (m_opt.gap_maxima && !m_stop) {
            // In contact the contact surface's gap is 0; the others' at the step's end.
            const double theta_end = std::min(theta_stop, 1.0);
            const state x_end = theta_end >= 1.0 ? x1 : m_integ.dense(rhs).value_at(theta_end);
            for (int s = 0; s < m_model.surface_count(); ++s)
                obs.on_gap_maximum(s, t0 + theta_end * h, s == i ? 0.0 : m_model.gap(s, x_end));
        }

        if (surface >= 0) return impact_in_contact(obs, rhs, surface, theta_impact);
        if (switch_first) {
            const auto& d = m_integ.dense(rhs);
            const double t_switch = theta_switch >= 1.0 ? m_integ.t() : t0 + theta_switch * h;
            if (!m_stop && obs.wants_segments()) obs.on_segment(d, t0, t_switch, flow_mode::sticking);
            m_stats.sticking_time += t_switch - m_t;
            take_switch(obs, d, sw, theta_switch, t_switch);
            return step_status::ok;
        }
        if (theta_release > 1.0) {
            if (!m_stop && obs.wants_segments()) obs.on_segment(m_integ.dense(rhs), t0, m_integ.t(), flow_mode::sticking);
            m_stats.sticking_time += m_integ.t() - m_t;
            m_t = m_integ.t();
            m_x = x1;
            m_ends_valid = true;
            return step_status::ok;
        }
        const auto& d = m_integ.dense(rhs);
        const double t_release = (theta_release >= 1.0) ? m_integ.t() : t0 + theta_release * h;
        if (!m_stop && obs.wants_segments()) obs.on_segment(d, t0, t_release, flow_mode::sticking);
        const state x = m_model.rest(i, (theta_release >= 1.0) ? x1 : d.value_at(theta_release));
        m_stats.sticking_time += t_release - m_t;
        m_t = t_release;
        m_x = x;
        m_mode = flow_mode::free;
        m_contact = -1;
        if (!m_stop) obs.on_release(i, m_t, m_x);
        restart(m_integ.step_size());
        return step_status::ok;
    }

    // The first downward crossing of gap j on the interpolant of the step just taken, from its
    // samples at the step's ends (2 when there is none).
    template <class Rhs>
    double gap_crossing(Rhs& rhs, int j, const scalar_sample& s0, const scalar_sample& s1)
    {
        auto g = on_dense(
            rhs, [this, j](const state& x) { return m_model.gap(j, x); },
            [this, j](const state& x, const state& v) { return gap_derivative(m_model, j, x, v); });
        double theta = 2.0;
        find_crossings(crossing_direction::down, g, s0, s1, [&](double th) { theta = th; return false; },
                       m_opt.event_subdivisions);
        return theta;
    }

    // No crossing located, yet a present surface (but `skip`) ends the step beyond itself, its
    // gap there `gap_end(j)`: the motion crossed it unseen (or a hop below resolution pushed
    // away from it). Going on would continue in the forbidden region; the run ends at the
    // step's start instead. True when it ends.
    template <class GapEnd>
    bool ended_beyond_unseen(int skip, GapEnd&& gap_end)
    {
        if (!m_opt.surfaces) return false;
        const state& x1 = m_integ.x();
        for (int j = 0; j < m_model.surface_count(); ++j)
            if (j != skip && !absent(j) && gap_end(j) < -hop_resolution(j, x1)) return end_at_step_start(outcome::inadmissible);
        return false;
    }

    // An impact on surface j at theta of the contact step just taken, in contact with surface
    // m_contact. The contact goes on where the impact leaves the state at rest on that surface
    // (a wall's reset of the horizontal velocity); otherwise it ends there.
    template <class Observer, class Rhs>
    step_status impact_in_contact(Observer& obs, Rhs& rhs, int j, double theta)
    {
        const int i = m_contact;
        const double h = m_integ.last_step();
        const double t0 = m_integ.t_prev();
        const auto& d = m_integ.dense(rhs);
        const double t_impact = theta >= 1.0 ? m_integ.t() : t0 + theta * h;
        if (!m_stop && obs.wants_segments()) obs.on_segment(d, t0, t_impact, flow_mode::sticking);
        m_stats.sticking_time += t_impact - m_t;
        if (!take_impact(obs, d, j, theta, t_impact)) return step_status::ok;
        const bool resting = m_model.gap(i, m_x) <= hop_resolution(i, m_x) &&
                             std::abs(gap_rate(m_model, i, m_x)) < m_opt.sticking_velocity && m_model.release(i, m_x) <= 0.0;
        if (!resting) {
            m_mode = flow_mode::free;
            m_contact = -1;
            if (!m_stop) obs.on_release(i, m_t, m_x);
        }
        restart(m_integ.step_size());
        return step_status::ok;
    }

    Model m_model;
    flow_options m_opt;
    end_samples m_start, m_end;  // at the start and end of the last step
    std::vector<double> m_batch_gaps, m_batch_sections;
    // The last step ended where the trajectory goes on (no impact, no change of mode): its end
    // samples are the next step's start samples.
    bool m_ends_valid = false;
    integrator_type m_integ;
    run_stats m_stats;
    flow_mode m_mode = flow_mode::free;
    int m_contact = -1;
    double m_t = 0.0;
    state m_x;
    // Points on the interpolant where event functions are evaluated, sized once: the
    // runtime-sized flow allocates nothing per step.
    mutable state m_point, m_slope;
    // The same for impacts and section crossings: the state on the surface, its image, a gradient.
    state m_pre, m_post;
    mutable state m_gradient;
    bool m_stop = false;
    double m_stop_theta = 2.0;  // where in the current step the observer stopped the run
    double m_free_step_max = 0.0;  // the longest free-flight step so far
    std::optional<outcome> m_finished;
    // Which gaps and watched events are checked for resolution on each step (not affine in the
    // state), and how many steps in a row were taken back for it.
    static constexpr int max_retractions = 8;
    std::vector<char> m_check_gap, m_check_event, m_check_switch;
    bool m_check_any = false;
    int m_retractions = 0;
};

}  // namespace vimpact
