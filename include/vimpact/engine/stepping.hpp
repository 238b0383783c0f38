#pragma once
// The hybrid flow driven one step at a time from outside: what the steppable systems
// (system/hybrid_system.hpp, section_system.hpp, tangent_system.hpp) are made of. The flow
// (hybrid/flow.hpp) does all the integration, event location, impacts and contact phases;
// this decides only where a step may end (a time to land on exactly) and keeps what the flow
// reported on the way (impacts, section crossings), for the caller to take.
#include <deque>
#include <limits>
#include <vector>

#include "vimpact/hybrid/flow.hpp"

namespace vimpact::engine {

// What the flow reported in its steps, kept until the caller takes it. Never stops the flow:
// a step runs to its end, and a crossing that is not the step's last waits in `points`.
template <class X>
struct step_record : flow_observer {
    struct impact {
        double t;
        int surface;
        X pre, post;
    };
    struct point {
        double t;
        X x;
    };
    // >= 0: the post-impact states on that surface are points too; -1: on every surface;
    // -2: none (the points are the watched events' crossings only).
    int impact_points = -2;
    std::deque<impact> impacts;
    std::deque<point> points;
    // The crossings of switching surfaces (`surface`: the switch), kept only when asked
    // (a tangent flow's caller reads their jumps).
    bool keep_switchings = false;
    std::deque<impact> switchings;

    flow_control on_switch(int k, double t, const X& pre, const X& post)
    {
        if (keep_switchings) switchings.push_back({t, k, pre, post});
        return flow_control::proceed;
    }

    flow_control on_section(int, crossing, double t, const X& x)
    {
        points.push_back({t, x});
        return flow_control::proceed;
    }
    flow_control on_impact(int surface, double t, const X& pre, const X& post)
    {
        impacts.push_back({t, surface, pre, post});
        if (impact_points == -1 || impact_points == surface) points.push_back({t, post});
        return flow_control::proceed;
    }
};

template <engine_model Model, template <int> class Method>
class stepping_flow {
public:
    using flow_type = hybrid_flow<Model, Method>;
    using state = typename flow_type::state;
    static constexpr double forever = std::numeric_limits<double>::infinity();

    // Started at (t, x): throws input_error where the flow does (x beyond a surface).
    stepping_flow(const Model& m, const flow_options& fo, double t, const state& x) : m_flow(m, fo)
    {
        m_flow.start(t, x);
        m_flow.begin_run();
    }

    [[nodiscard]] const flow_type& flow() const { return m_flow; }
    // The flow's counters, less the contact time of steps cut back by advance_to (the flow
    // counted them to their ends, and counts that stretch again after the landing).
    [[nodiscard]] run_stats stats() const
    {
        run_stats s = m_flow.stats();
        s.sticking_time -= m_cut_contact;
        return s;
    }
    [[nodiscard]] double t() const { return m_flow.t(); }
    [[nodiscard]] const state& x() const { return m_flow.x(); }
    // ok while the flow can go on; else why it ended (then nothing moves any more).
    [[nodiscard]] outcome status() const { return m_status; }
    [[nodiscard]] step_record<state>& record() { return m_record; }
    [[nodiscard]] const step_record<state>& record() const { return m_record; }

    // One accepted step (the integrator's), through any impact in it; in free flight it ends
    // no later than t_stop. A step the flow takes back (an event function it did not resolve)
    // is no step: the next one is taken.
    outcome step(double t_stop = forever)
    {
        if (m_status != outcome::ok) return m_status;
        t_stop = std::min(t_stop, m_flow.options().t_max);
        for (;;) {
            if (const auto o = m_flow.limit_reached()) return m_status = *o;
            step_status st;
            if (m_flow.mode() == flow_mode::free && t_stop < forever) {
                // What the flow's own free step does, with the integrator's step ending at t_stop
                // (the same entry the SIMD lanes' driver uses).
                st = m_flow.integrator().advance(free_field<Model>{&m_flow.model()}, t_stop);
                if (st == step_status::ok) st = m_flow.free_step_taken(m_record);
            } else {
                st = m_flow.step(m_record);
            }
            if (const auto o = m_flow.step_taken(st, m_record)) return m_status = *o;
            if (st != step_status::retracted) return outcome::ok;
        }
    }

    // Steps until the time is exactly t (>= t()), or the flow ends.
    outcome advance_to(double t)
    {
        while (m_status == outcome::ok && m_flow.t() < t) {
            if (m_flow.mode() == flow_mode::free) {
                step(t);
                continue;
            }
            const double t0 = m_flow.t();
            const state x0 = m_flow.x();
            const int surface = m_flow.contact_surface();
            if (step() == outcome::ok && m_flow.t() > t) land_in_contact(t, t0, x0, surface);
        }
        return m_status;
    }

private:
    // A contact step ends where its error control says, not at a requested time, and it went
    // past t (before any release: a release ends the step). The state at t is that of the
    // constrained motion from the step's start, integrated alone (no event can happen on it
    // before t), put at rest on the surface, and the flow starts again there (at rest on a
    // contact surface it starts in contact). What the step reported after t is dropped.
    void land_in_contact(double t, double t0, const state& x0, int surface)
    {
        const Model& m = m_flow.model();
        auto rhs = [&](const state& y) { return m.sticking_rhs(surface, y); };
        typename flow_type::integrator_type integ(m_flow.options().integration);
        integ.start(rhs, t0, x0);
        while (integ.t() < t)
            if (integ.advance(rhs, t) != step_status::ok) {
                m_status = outcome::non_finite;
                return;
            }
        while (!m_record.points.empty() && m_record.points.back().t > t) m_record.points.pop_back();
        m_cut_contact += m_flow.t() - t;
        m_flow.start(t, m.rest(surface, integ.x()));
    }

    flow_type m_flow;
    step_record<state> m_record;
    outcome m_status = outcome::ok;
    double m_cut_contact = 0.0;
};

}  // namespace vimpact::engine
