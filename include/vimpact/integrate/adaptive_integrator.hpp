#pragma once
// Step-size control around an embedded Runge-Kutta pair. One call to advance() makes one
// accepted step (possibly after rejections); the interpolant of that step is built lazily, so
// methods whose interpolant costs extra stages (DOP853) pay only on steps that need it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "vimpact/core/state.hpp"
#include "vimpact/integrate/integrator_options.hpp"
#include "vimpact/integrate/runge_kutta.hpp"
#include "vimpact/integrate/step_control.hpp"

namespace vimpact {

// retracted: the caller took the step back (hybrid/flow.hpp: too long for an event function
// to be resolved on it); the integrator never returns it itself.
enum class step_status { ok, step_underflow, non_finite, retracted };

struct integrator_counters {
    long steps = 0;
    long rejected = 0;
    long rhs_calls = 0;
    double h_min = std::numeric_limits<double>::infinity();
    double h_max = 0.0;
};

// A method's hold band when the options give none; 0 (off) for a stepper that names none.
template <class MethodType>
constexpr double default_hold_band()
{
    if constexpr (requires { MethodType::default_hold_band; }) return MethodType::default_hold_band;
    else return 0.0;
}

// MethodType: the stepper, Method<N> unless a caller substitutes one with the same interface
// (hybrid/stepper.hpp).
template <int N, template <int> class Method, class MethodType = Method<N>>
class adaptive_integrator {
public:
    using method_type = MethodType;
    using dense_type = typename method_type::dense_type;

    explicit adaptive_integrator(const integrator_options& opt = {}) : m_opt(opt) {}

    [[nodiscard]] const integrator_options& options() const { return m_opt; }
    [[nodiscard]] const integrator_counters& counters() const { return m_count; }

    // (Re)starts at (t, x). A positive h_hint carries the step size across a restart, e.g.
    // after an impact, instead of estimating a new one.
    template <class F>
    void start(F&& rhs, double t, const vec<N>& x, double h_hint = 0.0)
    {
        m_t = t;
        m_x = x;
        m_f = rhs(x);
        ++m_count.rhs_calls;
        if (h_hint > 0.0)
            m_h = std::min(h_hint, m_opt.h_max);
        else if (m_opt.h_init > 0.0)
            m_h = std::min(m_opt.h_init, m_opt.h_max);
        else
            m_h = initial_step(rhs);
        m_dense_ready = false;
        m_stage_source = {};
        m_log_err_old = log2_err_floor;
        ++m_starts;
    }
    // How often start() was called: a driver that keeps a copy of the state learns of restarts.
    [[nodiscard]] long starts() const { return m_starts; }

    // One accepted step, ending no later than t_stop (> t()).
    template <class F>
    step_status advance(F&& rhs, double t_stop)
    {
        m_stage_source = {};
        bool rejected_before = false;
        for (;;) {
            const auto plan = plan_trial(m_t, m_h, m_opt.h_max, t_stop);
            if (plan.underflow) return step_status::step_underflow;
            const double err2 = m_method.attempt(rhs, m_x, m_f, plan.h, m_opt.rtol, m_opt.atol, m_x_new, m_f_new);
            // x * 0 is 0 for finite x and NaN otherwise: one vector sum instead of Eigen's
            // allFinite, which GCC leaves out of line.
            const bool finite = is_finite(err2) && (m_x_new * 0.0 + m_f_new * 0.0).sum() == 0.0;
            const controller_constants c = constants();
            // control_step's outcome for a held step, taken before its logarithm and power.
            if (step_held(c, err2, finite && err2 <= 1.0)) {
                accept(plan.h, plan.clipped ? t_stop : m_t + plan.h, m_x_new, m_f_new, m_h, m_log_err_old);
                return step_status::ok;
            }
            const auto out = control_step(c, err2, finite, plan.h, m_h, plan.clipped, rejected_before, m_log_err_old);
            if (out.accepted) {
                accept(plan.h, plan.clipped ? t_stop : m_t + plan.h, m_x_new, m_f_new, out.h_next, out.log2_err_old);
                return step_status::ok;
            }
            rejected_before = true;
            if (reject(plan, out.h_next, finite)) return step_status::non_finite;
        }
    }

    // The same step taken outside, in a SIMD lane of several jobs (hybrid/flow_lanes.hpp):
    // the lane planned it with plan_trial, tried it and ran control_step on it exactly as
    // advance() does, and hands over the outcome. `stages` fills the method's stages when the
    // step's interpolant is needed (called at most once, before the next step).
    using stage_filler = void (*)(const void* context, method_type& method);
    struct stage_source {
        stage_filler fill = nullptr;
        const void* context = nullptr;
    };
    void accept_external(const trial_plan<double, bool>& plan, double t_stop, const vec<N>& x_new,
                         const vec<N>& f_new, double h_next, double log2_err_old, stage_source stages)
    {
        accept(plan.h, plan.clipped ? t_stop : m_t + plan.h, x_new, f_new, h_next, log2_err_old);
        m_stage_source = stages;
    }
    // Several steps accepted outside and left there (hybrid/flow_lanes.hpp keeps the quiet
    // steps of a lane in its arrays), taken over at once: as many accept_external calls,
    // without the interpolants (no caller asks for a step's interpolant once the next one is
    // taken). The step counters move by `steps`; the last step went from (t_prev, x_prev,
    // f_prev) by h_taken to (t, x, f); h_min and h_max are the extremes of all their sizes;
    // h_next and log2_err_old the controller's state after the last trial.
    struct external_steps {
        long steps;
        double t_prev, h_taken, t, h_min, h_max, h_next, log2_err_old;
        vec<N> x_prev, f_prev, x, f;
    };
    void accept_external_steps(const external_steps& s)
    {
        m_count.rhs_calls += s.steps * method_type::stages_per_step;
        m_count.steps += s.steps;
        m_count.h_min = std::min(m_count.h_min, s.h_min);
        m_count.h_max = std::max(m_count.h_max, s.h_max);
        m_log_err_old = s.log2_err_old;
        m_t_prev = s.t_prev;
        m_x_prev = s.x_prev;
        m_f_prev = s.f_prev;
        m_h_taken = s.h_taken;
        m_t = s.t;
        m_x = s.x;
        m_f = s.f;
        m_h = s.h_next;
        m_dense_ready = false;
        m_stage_source = {};
    }
    // Takes the last accepted step (of advance() or accept_external()) back, as if its trial
    // had been rejected: the state, time
    // and counters are those before it, and the next trial has size h_next. For a caller that
    // finds the step too long for something the error estimate does not see (an event
    // function that turns inside it). Counts as a start, so that a driver keeping a copy of
    // the state (hybrid/flow_lanes.hpp) reads it again.
    void retract(double h_next)
    {
        m_count = m_count_before_accept;
        m_count.rhs_calls += method_type::stages_per_step;
        ++m_count.rejected;
        m_t = m_t_prev;
        m_x = m_x_prev;
        m_f = m_f_prev;
        m_h = h_next;
        m_dense_ready = false;
        m_stage_source = {};
        ++m_starts;
    }
    // A rejected trial taken outside; true when the step ends in non-finite numbers.
    bool reject_external(const trial_plan<double, bool>& plan, double h_next, bool finite)
    {
        return reject(plan, h_next, finite);
    }
    [[nodiscard]] double log2_err_old() const { return m_log_err_old; }
    [[nodiscard]] controller_constants constants() const
    {
        const double band = m_opt.hold_band.value_or(default_hold_band<method_type>());
        return {m_opt.safety,  m_opt.factor_min, m_opt.factor_max, m_opt.pi_beta, method_type::error_exponent_order,
                band > 0.0 ? band * band : std::numeric_limits<double>::infinity()};
    }

    // Interpolant of the last accepted step [t_prev(), t()].
    template <class F>
    const dense_type& dense(F&& rhs)
    {
        if (!m_dense_ready) {
            if (m_stage_source.fill) {
                m_stage_source.fill(m_stage_source.context, m_method);
                m_stage_source = {};
            }
            m_method.build_dense(rhs, m_t_prev, m_h_taken, m_x_prev, m_x, m_dense);
            m_count.rhs_calls += method_type::dense_extra_stages;
            m_dense_ready = true;
        }
        return m_dense;
    }

    [[nodiscard]] double t() const { return m_t; }
    [[nodiscard]] const vec<N>& x() const { return m_x; }
    [[nodiscard]] const vec<N>& f() const { return m_f; }
    [[nodiscard]] double t_prev() const { return m_t_prev; }
    [[nodiscard]] const vec<N>& x_prev() const { return m_x_prev; }
    [[nodiscard]] const vec<N>& f_prev() const { return m_f_prev; }
    [[nodiscard]] double step_size() const { return m_h; }
    [[nodiscard]] double last_step() const { return m_h_taken; }

private:
    void accept(double h, double t_new, const vec<N>& x_new, const vec<N>& f_new, double h_next, double log2_err)
    {
        m_count_before_accept = m_count;
        m_count.rhs_calls += method_type::stages_per_step;
        m_log_err_old = log2_err;
        m_t_prev = m_t;
        m_x_prev = m_x;
        m_f_prev = m_f;
        m_h_taken = h;
        m_t = t_new;
        m_x = x_new;
        m_f = f_new;
        m_h = h_next;
        ++m_count.steps;
        m_count.h_min = std::min(m_count.h_min, h);
        m_count.h_max = std::max(m_count.h_max, h);
        m_dense_ready = false;
    }
    bool reject(const trial_plan<double, bool>& plan, double h_next, bool finite)
    {
        m_count.rhs_calls += method_type::stages_per_step;
        ++m_count.rejected;
        m_h = h_next;
        return !finite && !(m_h > plan.h_floor);
    }

    template <class F>
    double initial_step(F&& rhs)
    {
        const vec<N> sc = error_scale<N>(m_x, m_x, m_opt.rtol, m_opt.atol);
        const double n = double(m_x.size());
        const double d0 = std::sqrt(m_x.cwiseQuotient(sc).squaredNorm() / n);
        const double d1 = std::sqrt(m_f.cwiseQuotient(sc).squaredNorm() / n);
        double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
        h0 = std::min(h0, m_opt.h_max);
        const vec<N> x1 = m_x + h0 * m_f;
        const vec<N> f1 = rhs(x1);
        ++m_count.rhs_calls;
        const double d2 = std::sqrt((f1 - m_f).cwiseQuotient(sc).squaredNorm() / n) / h0;
        const double dmax = std::max(d1, d2);
        const double h1 = dmax <= 1e-15 ? std::max(1e-6, h0 * 1e-3)
                                        : std::pow(0.01 / dmax, 1.0 / method_type::order);
        return std::min({100.0 * h0, h1, m_opt.h_max});
    }

    integrator_options m_opt;
    integrator_counters m_count, m_count_before_accept;
    method_type m_method;
    dense_type m_dense;
    bool m_dense_ready = false;
    stage_source m_stage_source;
    long m_starts = 0;
    double m_log_err_old = log2_err_floor;
    double m_t = 0.0, m_t_prev = 0.0, m_h = 0.0, m_h_taken = 0.0;
    vec<N> m_x, m_f, m_x_prev, m_f_prev, m_x_new, m_f_new;
};

}  // namespace vimpact
