#pragma once
// The hybrid flow: smooth flight integrated by an adaptive Runge-Kutta method, impacts located
// on the interpolant and mapped by the model's reset, sections recorded as events, and
// chattering resolved into a sticking phase.
//
// Chattering and sticking (the rule, see docs/model.md): an impact whose rebound velocity
// u = r |v-| is below `sticking_velocity`, or whose hop height u^2 / (2 |a|) is below
// sticking_height() (not resolvable in y near the barrier), while the free acceleration at rest on the barrier,
// a(sigma, 0, x, w), does not point away from it (a <= 0) ends a chatter sequence: the
// structure sticks, y = sigma and v = 0, and the rest of the state follows the model's
// constrained field. It is released when a(X) crosses zero upwards. With r < 1 the rebound
// velocities of a chatter sequence shrink geometrically, so the rule is reached after about
// log(u_stop / v0) / log(r) impacts, u_stop = max(sticking_velocity, sqrt(2 |a| height)):
// a bounded, not infinite, number. A step that leaves the barrier and ends below it without
// the guard ever being positive (a hop below the resolution of y) also ends in sticking.
#include <algorithm>
#include <atomic>
#include <limits>
#include <string>

#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/hybrid/outcome.hpp"
#include "vimpact/hybrid/run_stats.hpp"
#include "vimpact/integrate/adaptive_integrator.hpp"
#include "vimpact/integrate/event_location.hpp"
#include "vimpact/model/concepts.hpp"

namespace vimpact {

enum class section_kind { maximum, minimum };
enum class flow_mode { free, sticking };
enum class flow_control { proceed, stop };

struct flow_options {
    integrator_options integration{};
    bool barrier = true;          // false: the barrier-free system (grazing analysis)
    bool track_maxima = true;     // section v = 0, v decreasing (the paper's Sigma)
    bool track_minima = false;    // v = 0, v increasing
    double sticking_velocity = 1e-8;
    // Hop height below which a rebound is not resolvable in y (< 0: 256 ulps of
    // max(1, |sigma|)); see sticking_height().
    double sticking_height = -1.0;
    double t_max = std::numeric_limits<double>::infinity();
    long max_steps = 200'000'000;
    long max_impacts = std::numeric_limits<long>::max();
    int event_subdivisions = 8;   // interpolant samples per step when an event may be inside
    // Polled after every step; when set, the run ends with outcome::interrupted. Lets a
    // caller (a Python session's Ctrl-C, a job loop being stopped) cut a long run short.
    const std::atomic<bool>* cancel = nullptr;
};

// The rebound hop height u^2 / (2 |a|) under which the structure counts as at rest.
inline double sticking_height(const flow_options& o, double barrier)
{
    if (o.sticking_height >= 0.0) return o.sticking_height;
    return 256.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(barrier));
}

// Default (no-op) observer; derive and shadow what you need.
struct flow_observer {
    [[nodiscard]] bool wants_segments() const { return false; }
    template <class X>
    flow_control on_section(section_kind, double, const X&) { return flow_control::proceed; }
    template <class X>
    flow_control on_impact(double, const X&, const X&) { return flow_control::proceed; }
    template <class X>
    void on_stick(double, const X&) {}
    template <class X>
    void on_release(double, const X&) {}
    template <class D>
    void on_segment(const D&, double, double, flow_mode) {}
    flow_control on_step_end(double) { return flow_control::proceed; }
};

template <sticking_model Model, template <int> class Method = dop853>
class hybrid_flow {
public:
    static constexpr int N = Model::dim;
    using state = vec<N>;
    using integrator_type = adaptive_integrator<N, Method>;
    using dense_type = typename integrator_type::dense_type;

    hybrid_flow(const Model& model, const flow_options& opt)
        : m_model(model), m_opt(opt), m_integ(opt.integration)
    {
    }

    // Starts at (t, x). Throws input_error if x is not admissible (below the barrier).
    void start(double t, const state& x)
    {
        if (!x.allFinite()) throw input_error("initial state must be finite");
        m_t = t;
        m_x = x;
        m_mode = flow_mode::free;
        if (m_opt.barrier) {
            const double g = m_model.guard(x);
            const double rate = m_model.guard_gradient(x).dot(m_model.rhs(x));
            if (g < 0.0 || (g == 0.0 && rate < 0.0))
                throw input_error("initial state is not admissible: y = " + format_double(x[Model::position]) +
                                  " must lie above the barrier sigma = " +
                                  format_double(m_model.barrier()) +
                                  " (or on it, moving away)");
            if (g == 0.0 && x[Model::velocity] == 0.0 && m_model.free_acceleration(x) <= 0.0)
                m_mode = flow_mode::sticking;
        }
        restart(0.0);
    }

    // Integrates until the observer asks to stop (outcome::ok), t_max, or another limit.
    template <class Observer>
    outcome run(Observer& obs)
    {
        m_stop = false;
        for (;;) {
            if (m_integ.counters().steps >= m_opt.max_steps) return finish(outcome::step_limit);
            if (m_t >= m_opt.t_max) return finish(outcome::time_limit);
            if (m_stats.impacts >= m_opt.max_impacts) return finish(outcome::impact_limit);
            if (m_opt.cancel && m_opt.cancel->load(std::memory_order_relaxed)) return finish(outcome::interrupted);
            const step_status st = (m_mode == flow_mode::free) ? step_free(obs) : step_sticking(obs);
            if (st == step_status::step_underflow) return finish(outcome::step_underflow);
            if (st == step_status::non_finite) return finish(outcome::non_finite);
            if (!m_stop && obs.on_step_end(m_t) == flow_control::stop) m_stop = true;
            if (m_stop) return finish(outcome::ok);
        }
    }

    [[nodiscard]] double t() const { return m_t; }
    [[nodiscard]] const state& x() const { return m_x; }
    [[nodiscard]] flow_mode mode() const { return m_mode; }
    [[nodiscard]] const Model& model() const { return m_model; }
    [[nodiscard]] const flow_options& options() const { return m_opt; }
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

private:
    auto free_rhs() const
    {
        return [this](const state& x) { return m_model.rhs(x); };
    }
    auto sticking_rhs() const
    {
        return [this](const state& x) { return m_model.sticking_rhs(x); };
    }

    outcome finish(outcome o) { return o; }

    void restart(double h_hint)
    {
        if (m_mode == flow_mode::free) m_integ.start(free_rhs(), m_t, m_x, h_hint);
        else m_integ.start(sticking_rhs(), m_t, m_x, h_hint);
    }

    // A scalar event function of the state as seen along the interpolant.
    template <class Rhs, class Value, class Gradient>
    auto event_on_dense(Rhs& rhs, Value&& value, Gradient&& gradient)
    {
        return [this, &rhs, value, gradient](double theta) {
            const dense_type& d = m_integ.dense(rhs);
            state p, dp;
            d.value_and_slope(theta, p, dp);
            return scalar_sample{value(p), gradient(p).dot(dp)};
        };
    }

    template <class Observer>
    step_status step_free(Observer& obs)
    {
        auto rhs = free_rhs();
        const step_status st = m_integ.advance(rhs, m_opt.t_max);
        if (st != step_status::ok) return st;
        const double h = m_integ.last_step();
        const double t0 = m_integ.t_prev();
        const state& x0 = m_integ.x_prev();
        const state& f0 = m_integ.f_prev();
        const state& x1 = m_integ.x();
        const state& f1 = m_integ.f();

        // Terminal event: the first impact inside (t0, t1].
        double theta_impact = 2.0;
        if (m_opt.barrier) {
            auto g = event_on_dense(
                rhs, [this](const state& x) { return m_model.guard(x); },
                [this](const state& x) { return m_model.guard_gradient(x); });
            const scalar_sample s0{m_model.guard(x0), m_model.guard_gradient(x0).dot(f0) * h};
            const scalar_sample s1{m_model.guard(x1), m_model.guard_gradient(x1).dot(f1) * h};
            find_crossings(crossing_direction::down, g, s0, s1,
                           [&](double th) { theta_impact = th; return false; },
                           m_opt.event_subdivisions);
            // A rebound too small for doubles: the step left the barrier (g = 0) and ended
            // below it without g ever being positive, so no crossing exists to find. The
            // hop was below the resolution of y; the structure is at rest on the barrier.
            if (theta_impact > 1.0 && s0.value == 0.0 && s1.value < 0.0) {
                state rest = x0;
                rest[Model::velocity] = 0.0;
                if (m_model.free_acceleration(rest) <= 0.0) {
                    enter_sticking(obs, t0, rest);
                    return step_status::ok;
                }
            }
        }

        // Sections (non-terminal) up to the impact, in time order.
        if (m_opt.track_maxima || m_opt.track_minima) {
            constexpr int V = Model::velocity;
            auto gv = event_on_dense(
                rhs, [](const state& x) { return x[V]; },
                [](const state&) { state e = state::Zero(); e[V] = 1.0; return e; });
            const scalar_sample s0{x0[V], f0[V] * h};
            const scalar_sample s1{x1[V], f1[V] * h};
            std::array<std::pair<double, section_kind>, 8> found{};
            int nfound = 0;
            auto collect = [&](section_kind k) {
                return [&, k](double th) {
                    if (th > theta_impact || nfound >= static_cast<int>(found.size())) return false;
                    found[nfound++] = {th, k};
                    return true;
                };
            };
            if (m_opt.track_maxima)
                find_crossings(crossing_direction::down, gv, s0, s1,
                               collect(section_kind::maximum), m_opt.event_subdivisions);
            if (m_opt.track_minima)
                find_crossings(crossing_direction::up, gv, s0, s1,
                               collect(section_kind::minimum), m_opt.event_subdivisions);
            // Insertion sort: at most a handful of crossings (std::sort trips a false
            // -Warray-bounds in GCC 12 here).
            for (int i = 1; i < nfound; ++i)
                for (int j = i; j > 0 && found[j].first < found[j - 1].first; --j)
                    std::swap(found[j], found[j - 1]);
            for (int i = 0; i < nfound; ++i) {
                ++m_stats.sections;
                if (m_stop) continue;
                const auto& d = m_integ.dense(rhs);
                state p = d.value_at(found[i].first);
                p[V] = 0.0;  // on the section by definition; removes interpolation round-off
                if (obs.on_section(found[i].second, t0 + found[i].first * h, p) == flow_control::stop)
                    m_stop = true;
            }
        }

        if (theta_impact > 1.0) {
            if (!m_stop && obs.wants_segments())
                obs.on_segment(m_integ.dense(rhs), t0, m_integ.t(), flow_mode::free);
            m_t = m_integ.t();
            m_x = x1;
            return step_status::ok;
        }

        const auto& d = m_integ.dense(rhs);
        const double t_impact = (theta_impact >= 1.0) ? m_integ.t() : t0 + theta_impact * h;
        if (!m_stop && obs.wants_segments()) obs.on_segment(d, t0, t_impact, flow_mode::free);
        state pre = (theta_impact >= 1.0) ? x1 : d.value_at(theta_impact);
        pre[Model::position] = m_model.barrier();
        state post = m_model.reset(pre);
        ++m_stats.impacts;
        if (!m_stop && obs.on_impact(t_impact, pre, post) == flow_control::stop) m_stop = true;

        m_t = t_impact;
        m_x = post;
        state rest = post;
        rest[Model::velocity] = 0.0;
        const double a_rest = m_model.free_acceleration(rest);
        const double u = post[Model::velocity];
        // The rebound is negligible if slow, or if its hop height u^2 / (2 |a|) is too small
        // to resolve in y near the barrier.
        const double hop = sticking_height(m_opt, m_model.barrier());
        const bool negligible = u < m_opt.sticking_velocity || (a_rest < 0.0 && u * u < 2.0 * hop * -a_rest);
        if (negligible && a_rest <= 0.0) {
            enter_sticking(obs, m_t, rest);
            return step_status::ok;
        }
        restart(m_integ.step_size());
        return step_status::ok;
    }

    template <class Observer>
    void enter_sticking(Observer& obs, double t, const state& rest)
    {
        m_t = t;
        m_x = rest;
        m_mode = flow_mode::sticking;
        ++m_stats.sticking_phases;
        if (!m_stop) obs.on_stick(m_t, m_x);
        restart(m_integ.step_size());
    }

    template <class Observer>
    step_status step_sticking(Observer& obs)
    {
        auto rhs = sticking_rhs();
        const step_status st = m_integ.advance(rhs, m_opt.t_max);
        if (st != step_status::ok) return st;
        const double h = m_integ.last_step();
        const double t0 = m_integ.t_prev();
        const state& x0 = m_integ.x_prev();
        const state& x1 = m_integ.x();

        double theta_release = 2.0;
        auto ga = event_on_dense(
            rhs, [this](const state& x) { return m_model.free_acceleration(x); },
            [this](const state& x) { return m_model.free_acceleration_gradient(x); });
        const scalar_sample s0{m_model.free_acceleration(x0),
                               m_model.free_acceleration_gradient(x0).dot(m_integ.f_prev()) * h};
        const scalar_sample s1{m_model.free_acceleration(x1),
                               m_model.free_acceleration_gradient(x1).dot(m_integ.f()) * h};
        find_crossings(crossing_direction::up, ga, s0, s1,
                       [&](double th) { theta_release = th; return false; },
                       m_opt.event_subdivisions);

        if (theta_release > 1.0) {
            if (!m_stop && obs.wants_segments())
                obs.on_segment(m_integ.dense(rhs), t0, m_integ.t(), flow_mode::sticking);
            m_stats.sticking_time += m_integ.t() - m_t;
            m_t = m_integ.t();
            m_x = x1;
            return step_status::ok;
        }
        const auto& d = m_integ.dense(rhs);
        const double t_release = (theta_release >= 1.0) ? m_integ.t() : t0 + theta_release * h;
        if (!m_stop && obs.wants_segments()) obs.on_segment(d, t0, t_release, flow_mode::sticking);
        state x = (theta_release >= 1.0) ? x1 : d.value_at(theta_release);
        x[Model::position] = m_model.barrier();
        x[Model::velocity] = 0.0;
        m_stats.sticking_time += t_release - m_t;
        m_t = t_release;
        m_x = x;
        m_mode = flow_mode::free;
        if (!m_stop) obs.on_release(m_t, m_x);
        restart(m_integ.step_size());
        return step_status::ok;
    }

    Model m_model;
    flow_options m_opt;
    integrator_type m_integ;
    run_stats m_stats;
    flow_mode m_mode = flow_mode::free;
    double m_t = 0.0;
    state m_x = state::Zero();
    bool m_stop = false;
};

}  // namespace vimpact
