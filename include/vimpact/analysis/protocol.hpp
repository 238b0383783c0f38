#pragma once
// The paper's simulation protocol (Section 3): run from an initial state, discard a transient
// of impacts, then record points on a section.
//
// Non-impacting runs (P0): if no impact happens for `quiet_time` time units, the orbit is
// taken to have settled away from the barrier; any transient bookkeeping is dropped and the
// section points recorded from then on describe the barrier-free steady state. The default,
// 2000 time units, is about 318 wake periods (the wake frequency is 1 in these units) and far
// longer than the gaps between impacts of any impacting orbit we have seen (< 100).
#include <limits>
#include <string_view>
#include <vector>

#include "vimpact/core/input_error.hpp"
#include "vimpact/hybrid/flow.hpp"

namespace vimpact {

enum class section_choice { maxima, minima, impacts };

constexpr std::string_view to_string(section_choice s)
{
    switch (s) {
        case section_choice::maxima: return "maxima";
        case section_choice::minima: return "minima";
        case section_choice::impacts: return "impacts";
    }
    return "unknown";
}

struct protocol_options {
    long transient_impacts = 500;
    long record_points = 200;
    section_choice section = section_choice::maxima;
    double quiet_time = 2000.0;
    double sample_dt = 0.0;  // > 0: sample the recorded window every sample_dt (time series)
    flow_options flow{.t_max = 1e6};
};

template <int N>
struct timed_state {
    double t;
    vec<N> x;
};

template <int N>
struct impact_event {
    double t;
    vec<N> pre;   // state at the barrier just before the reset
    vec<N> post;  // state just after
};

template <int N>
struct protocol_result {
    outcome status = outcome::ok;
    bool impacting = true;        // false: no impact for quiet_time (label P0)
    long transient_impacts = 0;   // impacts discarded
    std::vector<timed_state<N>> points;    // recorded section points
    std::vector<impact_event<N>> impacts;  // impacts in the recorded window
    std::vector<timed_state<N>> series;    // time series of the recorded window (sample_dt > 0)
    double t_record_start = 0.0;
    vec<N> final_state;
    run_stats stats;
};

inline void validate(const protocol_options& o)
{
    if (o.transient_impacts < 0)
        throw input_error("transient must be >= 0 impacts (got " + std::to_string(o.transient_impacts) + ")");
    if (o.record_points < 1)
        throw input_error("record must be >= 1 section points (got " + std::to_string(o.record_points) + ")");
    if (!(o.quiet_time > 0.0)) throw input_error("quiet_time must be > 0");
    if (!(o.sample_dt >= 0.0) || !std::isfinite(o.sample_dt)) throw input_error("sample_dt must be >= 0 and finite");
    const auto& in = o.flow.integration;
    if (!(in.rtol > 0.0 && in.rtol < 1.0) || !std::isfinite(in.rtol))
        throw input_error("rtol = " + format_double(in.rtol) + " is outside its valid range (0, 1)");
    if (!(in.atol > 0.0 && in.atol < 1.0) || !std::isfinite(in.atol))
        throw input_error("atol = " + format_double(in.atol) + " is outside its valid range (0, 1)");
    if (in.rtol < 1e-15 || in.atol < 1e-300)
        throw input_error("rtol must be >= 1e-15 (double precision cannot do better)");
}

namespace detail {

template <int N>
class protocol_observer : public flow_observer {
public:
    protocol_observer(const protocol_options& opt, protocol_result<N>& res) : m_opt(opt), m_res(res)
    {
        m_recording = opt.transient_impacts == 0;
    }

    [[nodiscard]] bool wants_segments() const { return m_recording && m_opt.sample_dt > 0.0; }

    // After every accepted step: the quiet-time rule.
    flow_control on_step_end(double t)
    {
        check_quiet(t);
        return m_done ? flow_control::stop : flow_control::proceed;
    }

    void check_quiet(double t)
    {
        if (m_res.impacting && t - m_last_impact > m_opt.quiet_time) {
            m_res.impacting = false;
            m_res.transient_impacts = m_impacts;
            m_res.points.clear();
            m_res.impacts.clear();
            m_res.series.clear();
            begin_recording(t);
            if (m_opt.section == section_choice::impacts) m_done = true;
        }
    }
    [[nodiscard]] bool done() const { return m_done; }
    void set_start(double t)
    {
        m_last_impact = t;
        if (m_recording) begin_recording(t);
    }

    flow_control on_section(section_kind k, double t, const vec<N>& x)
    {
        if (!m_recording) return flow_control::proceed;
        const bool wanted = (k == section_kind::maximum && m_opt.section == section_choice::maxima) ||
                            (k == section_kind::minimum && m_opt.section == section_choice::minima);
        if (wanted) m_res.points.push_back({t, x});
        return finished() ? flow_control::stop : flow_control::proceed;
    }

    flow_control on_impact(double t, const vec<N>& pre, const vec<N>& post)
    {
        ++m_impacts;
        m_last_impact = t;
        if (!m_recording) {
            if (m_impacts >= m_opt.transient_impacts) {
                m_res.transient_impacts = m_impacts;
                begin_recording(t);
                if (m_opt.sample_dt > 0.0) m_res.series.push_back({t, post});
            }
            return flow_control::proceed;
        }
        m_res.impacts.push_back({t, pre, post});
        if (m_opt.sample_dt > 0.0) {
            m_res.series.push_back({t, pre});
            m_res.series.push_back({t, post});
        }
        if (m_opt.section == section_choice::impacts) m_res.points.push_back({t, post});
        return finished() ? flow_control::stop : flow_control::proceed;
    }

    template <class D>
    void on_segment(const D& d, double ta, double tb, flow_mode)
    {
        while (m_next_sample <= tb) {
            if (m_next_sample > ta || (m_next_sample == ta && m_res.series.empty()))
                m_res.series.push_back({m_next_sample, d.value(m_next_sample)});
            m_next_sample = m_res.t_record_start + static_cast<double>(++m_sample_index) * m_opt.sample_dt;
        }
    }

private:
    void begin_recording(double t)
    {
        m_recording = true;
        m_res.t_record_start = t;
        m_sample_index = 0;
        m_next_sample = t;
    }
    [[nodiscard]] bool finished() const
    {
        return static_cast<long>(m_res.points.size()) >= m_opt.record_points;
    }

    const protocol_options& m_opt;
    protocol_result<N>& m_res;
    bool m_recording = false;
    bool m_done = false;
    long m_impacts = 0;
    double m_last_impact = 0.0;
    double m_next_sample = 0.0;
    long m_sample_index = 0;
};

}  // namespace detail

// Runs the protocol on `model` from (0, x0). Throws input_error for invalid options or an
// inadmissible initial state; numerical trouble is reported in result.status.
template <template <int> class Method = dop853, sticking_model Model>
protocol_result<Model::dim> run_protocol(const Model& model, const vec<Model::dim>& x0,
                                         const protocol_options& opt)
{
    validate(opt);
    constexpr int N = Model::dim;
    protocol_result<N> res;
    flow_options fo = opt.flow;
    fo.track_maxima = opt.section == section_choice::maxima;
    fo.track_minima = opt.section == section_choice::minima;
    hybrid_flow<Model, Method> flow(model, fo);
    flow.start(0.0, x0);
    detail::protocol_observer<N> obs(opt, res);
    obs.set_start(0.0);
    const outcome o = flow.run(obs);
    res.status = o;
    res.final_state = flow.x();
    res.stats = flow.stats();
    return res;
}

}  // namespace vimpact
