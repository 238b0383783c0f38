#pragma once
// The protocol (analysis/protocol.hpp) on an engine model: the template every front end's
// simulate() call ends in, instantiated by the library for each model kind.
#include "vimpact/analysis/protocol.hpp"
#include <algorithm>
#include <limits>

#include "vimpact/core/first_beyond.hpp"
#include "vimpact/hybrid/flow.hpp"

namespace vimpact::engine {

template <int N>
class protocol_observer : public flow_observer {
public:
    protocol_observer(const protocol_options& opt, simulation& res) : m_opt(opt), m_res(res)
    {
        m_recording = opt.transient_impacts == 0;
    }

    [[nodiscard]] bool wants_segments() const { return m_recording && m_opt.sample_dt > 0.0; }

    // After every accepted step: the quiet-time rule.
    flow_control on_step_end(double t)
    {
        if (m_res.impacting && t - m_last_impact > m_opt.quiet_time) {
            m_res.impacting = false;
            m_res.transient_impacts = m_impacts;
            m_res.points.clear();
            m_res.impacts.clear();
            m_res.switchings.clear();
            m_res.series.clear();
            begin_recording(t);
            if (m_opt.section.type == section_choice::kind::impacts) m_done = true;
        }
        return m_done || m_sample_limit ? flow_control::stop : flow_control::proceed;
    }
    // A time before which on_step_end returns proceed and changes nothing (core/first_beyond.hpp):
    // the SIMD lanes' driver leaves the steps that end before it in its lanes, and then reports
    // their gaps' largest values in one on_gap_maximum call at the last step's end time (an
    // observer offering this must not need the time of each step's gap; this one compares it
    // with the start of its recording only, which every such step ends after).
    [[nodiscard]] double step_end_acts_from() const
    {
        if (m_done || m_sample_limit) return -std::numeric_limits<double>::infinity();
        if (!m_res.impacting) return std::numeric_limits<double>::infinity();
        return m_acts_from;
    }
    // The series reached protocol_options::max_samples (the run stops at the step's end).
    [[nodiscard]] bool sample_limit() const { return m_sample_limit; }
    void set_start(double t)
    {
        set_last_impact(t);
        if (m_recording) begin_recording(t);
    }

    // The flow watches one event: the chosen section.
    flow_control on_section(int, crossing, double t, const vec<N>& x)
    {
        if (!m_recording) return flow_control::proceed;
        m_res.points.push_back(t, x);
        return finished_at(t) ? flow_control::stop : flow_control::proceed;
    }

    void on_stick(int, double t, const vec<N>&)
    {
        m_in_contact = true;
        m_contact_since = t;
    }
    void on_release(int, double t, const vec<N>&)
    {
        add_contact(t);
        m_in_contact = false;
    }
    void on_gap_maximum(int surface, double t, double gap)
    {
        auto& best = m_res.max_gap[static_cast<std::size_t>(surface)];
        if (m_recording && t >= m_res.t_record_start && !(gap <= best)) best = gap;
    }
    // At the run's end (t_final): the recorded window ends at its last point, or at t_final
    // when the run ended otherwise; a contact phase still going on counts up to that end.
    void finish(double t_final)
    {
        // A run that ended before recording began (chattering in the transient) has an empty
        // window.
        if (!m_end_set) m_res.t_record_end = m_recording ? t_final : m_res.t_record_start;
        m_end_set = true;
        if (m_in_contact) add_contact(t_final);
    }

    flow_control on_impact(int surface, double t, const vec<N>& pre, const vec<N>& post)
    {
        ++m_impacts;
        if (!recording_after_event(t, post)) return flow_control::proceed;
        m_res.impacts.push_back(t, surface, pre, post);
        if (m_opt.sample_dt > 0.0) {
            m_res.series.push_back(t, pre);
            m_res.series.push_back(t, post);
        }
        if (m_opt.section.type == section_choice::kind::impacts &&
            (m_opt.section.index < 0 || m_opt.section.index == surface))
            m_res.points.push_back(t, post);
        return finished_at(t) ? flow_control::stop : flow_control::proceed;
    }

    // A crossing of a switch is an event of the non-smooth motion as an impact is: it counts
    // towards the transient and keeps the P0 rule from applying (a compliant stop's periodic
    // orbit is labelled by its period, not P0).
    flow_control on_switch(int k, double t, const vec<N>& pre, const vec<N>& post)
    {
        ++m_crossings;
        if (!recording_after_event(t, post)) return flow_control::proceed;
        m_res.switchings.push_back(t, k, pre, post);
        // A reset that moved the state: the series shows the jump, as at an impact.
        if (m_opt.sample_dt > 0.0 && pre != post) {
            m_res.series.push_back(t, pre);
            m_res.series.push_back(t, post);
        }
        return flow_control::proceed;
    }

    template <class D>
    void on_segment(const D& d, double ta, double tb, flow_mode)
    {
        while (m_next_sample <= tb && !m_sample_limit) {
            if (m_next_sample > ta || (m_next_sample == ta && m_res.series.empty()))
                m_res.series.push_back(m_next_sample, d.value(m_next_sample));
            const double previous = m_next_sample;
            m_next_sample = m_res.t_record_start + static_cast<double>(++m_sample_index) * m_opt.sample_dt;
            // A sample_dt below the time's resolution (t + dt == t) would never leave this loop.
            m_sample_limit = m_next_sample <= previous || static_cast<long>(m_res.series.size()) >= m_opt.max_samples;
        }
    }

private:
    void begin_recording(double t)
    {
        m_recording = true;
        m_res.t_record_start = t;
        m_res.contact_time = 0.0;
        std::fill(m_res.max_gap.begin(), m_res.max_gap.end(), std::numeric_limits<double>::quiet_NaN());
        m_sample_index = 0;
        m_next_sample = t;
    }
    [[nodiscard]] bool finished() const { return static_cast<long>(m_res.points.size()) >= m_opt.record_points; }
    [[nodiscard]] bool finished_at(double t)
    {
        if (!finished()) return false;
        m_res.t_record_end = t;
        m_end_set = true;
        return true;
    }
    // The contact phase from m_contact_since to t, the part inside the recorded window.
    void add_contact(double t)
    {
        if (m_end_set) t = std::min(t, m_res.t_record_end);
        if (m_recording) m_res.contact_time += std::max(0.0, t - std::max(m_contact_since, m_res.t_record_start));
    }

    void set_last_impact(double t)
    {
        m_last_impact = t;
        m_acts_from = first_beyond(t, m_opt.quiet_time);
    }
    // An impact or a crossing at t (`post`: the state after it), counted: the P0 rule's clock
    // starts again, and the event that completes the transient begins the recording. Whether
    // it was recorded (false during the transient).
    bool recording_after_event(double t, const vec<N>& post)
    {
        set_last_impact(t);
        if (m_recording) return true;
        if (m_impacts + m_crossings >= m_opt.transient_impacts) {
            m_res.transient_impacts = m_impacts;
            begin_recording(t);
            if (m_opt.sample_dt > 0.0) m_res.series.push_back(t, post);
        }
        return false;
    }

    const protocol_options& m_opt;
    simulation& m_res;
    bool m_recording = false;
    bool m_done = false;
    bool m_sample_limit = false;
    bool m_in_contact = false;
    bool m_end_set = false;
    double m_contact_since = 0.0;
    long m_impacts = 0;
    long m_crossings = 0;  // of switches
    double m_last_impact = 0.0;
    // first_beyond(m_last_impact, quiet_time), computed once per impact: the lanes' driver asks
    // for it after every step that goes back through the run.
    double m_acts_from = first_beyond(0.0, m_opt.quiet_time);
    double m_next_sample = 0.0;
    long m_sample_index = 0;
};

// The flow options of a protocol run: the surfaces on, the chosen section watched.
inline flow_options protocol_flow(const protocol_options& opt, crossing direction)
{
    flow_options fo = opt.flow;
    fo.surfaces = true;
    fo.gap_maxima = true;  // the excursion of the impact statistics
    fo.events.clear();
    if (opt.section.type == section_choice::kind::crossing)
        fo.events.push_back(flow_event::section(opt.section.index, direction));
    return fo;
}

// One protocol run: its flow, observer and result, set up from (0, x0). run_protocol runs it
// alone; the SIMD lanes of hybrid/flow_lanes.hpp step several at once. Not movable (the
// observer holds the result).
template <template <int> class Method, engine_model Model>
struct protocol_run {
    static constexpr int N = Model::dim;
    simulation res;
    hybrid_flow<Model, Method> flow;
    protocol_observer<N> obs;

    protocol_run(const Model& model, const vec<N>& x0, const protocol_options& opt)
        : res(empty_result(model)), flow(model, protocol_flow(opt, section_direction(model, opt))), obs(opt, res)
    {
        flow.start(0.0, x0);
        obs.set_start(0.0);
        if (flow.mode() == flow_mode::sticking) obs.on_stick(flow.contact_surface(), 0.0, flow.x());
    }
    protocol_run(const protocol_run&) = delete;
    protocol_run& operator=(const protocol_run&) = delete;

    simulation finish(outcome status)
    {
        obs.finish(flow.t());
        res.status = status;
        if (obs.sample_limit() && res.status == outcome::ok) res.status = outcome::sample_limit;
        res.final_state = to_dynamic(flow.x());
        res.stats = flow.stats();
        return std::move(res);
    }

private:
    static simulation empty_result(const Model& model)
    {
        simulation r;
        const int n = state_dim(model);
        r.points = state_series(n);
        r.impacts = impact_series(n);
        r.switchings = impact_series(n);
        r.series = state_series(n);
        r.max_gap.assign(static_cast<std::size_t>(model.surface_count()), std::numeric_limits<double>::quiet_NaN());
        return r;
    }
    static crossing section_direction(const Model& model, const protocol_options& opt)
    {
        return opt.section.type == section_choice::kind::crossing ? model.section_direction(opt.section.index)
                                                                  : crossing::down;
    }
};

template <template <int> class Method, engine_model Model>
simulation run_protocol(const Model& model, const vec<Model::dim>& x0, const protocol_options& opt)
{
    protocol_run<Method, Model> r(model, x0, opt);
    return r.finish(r.flow.run(r.obs));
}

}  // namespace vimpact::engine
