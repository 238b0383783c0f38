#pragma once
// The Lyapunov spectrum of an orbit with impacts (the paper's Algorithm 2, Eq. 13).
//
// After a transient of impacts (state only), N deviation vectors of size r0 are carried along
// the reference orbit. Every t0 they are re-orthonormalised by a QR decomposition, rescaled
// to r0, and ln(R_ii / r0) is accumulated; after `warmup_intervals` intervals (not counted,
// so the vectors align with the Lyapunov directions) the averages over the following impacts
// (or time) are the exponents, sorted in descending order.
//
// How deviations cross an impact (`tdm`):
//  - saltation:    the tangent (variational) flow with Y -> S Y at each impact (first order,
//                  exact for infinitesimal deviations: the textbook Lyapunov spectrum);
//  - second_order: the tangent flow between impacts, the second-order mapping
//                  (tangent/impact_jump.hpp) applied to each finite deviation (size about r0)
//                  at each impact;
//  - trajectory:   Benettin's two-trajectory method: each x + y_i is integrated as a real
//                  orbit with its own impacts, y_i = x_i - x at the end of each interval.
// The sum of the exponents satisfies  sum = <div F> + (1/T) sum_impacts ln|det S|: reported as
// `sum_rule` (tangent modes only: the trajectory mode does not integrate div F).
// The tangent flows integrate with DOP853 whatever protocol.method (which integrates the
// transient and the trajectory mode's orbits).
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "vimpact/core/names.hpp"
#include "vimpact/core/option.hpp"
#include "vimpact/analysis/protocol.hpp"

namespace vimpact {

enum class lyapunov_tdm { saltation, second_order, trajectory };

constexpr std::string_view to_string(lyapunov_tdm t)
{
    switch (t) {
        case lyapunov_tdm::saltation: return "saltation";
        case lyapunov_tdm::second_order: return "second-order";
        case lyapunov_tdm::trajectory: return "trajectory";
    }
    return "unknown";
}
inline constexpr std::array<lyapunov_tdm, 3> all_lyapunov_tdms{lyapunov_tdm::saltation, lyapunov_tdm::second_order,
                                                               lyapunov_tdm::trajectory};

struct lyapunov_options {
    long transient_impacts = 500;
    double quiet_time = 2000.0;       // the protocol's P0 rule during the transient
    flow_options flow{.t_max = 1e6};  // integration; t_max bounds the transient
    integration_method method = integration_method::dop853;
    lyapunov_tdm tdm = lyapunov_tdm::saltation;
    double r0 = 1e-4;                 // size of the deviation vectors
    double t0 = std::numbers::pi;     // re-orthonormalisation interval
    long warmup_intervals = 16;       // intervals not counted
    long impacts = 800;               // average over this many impacts of the reference ...
    double time = 0.0;                // ... or, if > 0, over this much time
    double p0_time = 1e4;             // averaging time of an orbit without impacts (P0)
    double max_time = 1e6;            // averaging time limit (outcome time_limit)
    // Integrate div F with the tangent (sum_rule); without it the tangent flow is about a
    // third cheaper (28 -> 20 integrated components for the paper's model).
    bool divergence = true;
    // > 0: also record this many points of the section (a crossing) of the reference orbit in
    // the averaging window: the bifurcation diagram under an exponent sweep.
    long record_points = 0;
    int section = 0;
};

// What a user sets (the transient, the integration and the recorded section are the
// protocol's options).
template <class V, record_of<lyapunov_options> O>
void declare(V& v, O& o)
{
    v(option{"tdm", "mapping of the deviations at an impact: the saltation matrix (first order), the second-order "
                    "discontinuity mapping, or two trajectories (Benettin)"},
      o.tdm, all_lyapunov_tdms);
    v(option{"r0", "size of the deviation vectors", inside(0.0, 1.0)}, o.r0);
    v(option{"t0", "re-orthonormalisation interval", above(0.0)}, o.t0);
    v(option{"impacts", "average over this many impacts of the reference orbit after the warm-up", at_least(1.0)},
      o.impacts);
    v(option{"time", "average over this much time instead (0: over impacts)", at_least(0.0)}, o.time);
    v(option{"warmup", "intervals of t0 not counted while the vectors align", between(0.0, 1e6)}, o.warmup_intervals);
    v(option{"p0_time", "averaging time of an orbit without impacts (P0)", above(0.0)}, o.p0_time);
    v(option{"max_time", "averaging time limit (outcome time_limit)", above(0.0)}, o.max_time);
    v(option{"divergence", "integrate div F with the tangent for the sum rule (without it a third cheaper)"},
      o.divergence);
}

struct lyapunov_result {
    // ok, time_limit (averaging cut by max_time; exponents given), sticking, or a failed run's.
    outcome status = outcome::ok;
    lyapunov_tdm tdm = lyapunov_tdm::saltation;
    bool impacting = true;            // false: no impact during the transient's quiet time
    Eigen::VectorXd exponents;        // descending (NaN when none)
    double lle_standard_error = std::numeric_limits<double>::quiet_NaN();  // from 8 block means
    // False when the largest exponent drifts: its means over the two halves of the window
    // differ by more than 4 standard errors of their difference (and 1e-3 of the spectrum's
    // spread); a longer transient or averaging is needed. True when too few intervals to say.
    bool settled = true;
    double t_start = 0.0;             // start of the averaging window
    double time = 0.0;                // length of the averaging window
    long impacts = 0;                 // impacts of the reference in the window
    std::vector<long> impacts_by_surface;
    long intervals = 0;               // counted intervals
    double divergence_average = std::numeric_limits<double>::quiet_NaN();
    double jump_log_det_rate = std::numeric_limits<double>::quiet_NaN();  // sum ln|det S| / time
    double sum_rule = std::numeric_limits<double>::quiet_NaN();           // the two added
    // second_order: deviations whose flight-time quadratic has no real root (they miss the
    // surface to second order); trajectory: perturbed orbits whose impact count in an interval
    // differs from the reference's.
    long misses = 0;
    std::vector<double> history_t;          // end of each counted interval
    std::vector<Eigen::VectorXd> history;   // ln(R_ii / r0) of each counted interval (QR order)
    state_series section_points;            // record_points points of the window
    run_stats transient_stats;
    // Summed over the interval runs (all orbits), but impacts and switchings: the reference's
    // in the averaging window.
    run_stats stats;

    [[nodiscard]] bool has_exponents() const { return status == outcome::ok || status == outcome::time_limit; }
    // The verdict every front end reports: the largest exponent lies more than 3 standard
    // errors above 0 (both finite; without an error estimate there is no verdict).
    [[nodiscard]] bool positive_largest_exponent() const
    {
        return has_exponents() && exponents.size() > 0 && std::isfinite(exponents[0]) &&
               std::isfinite(lle_standard_error) && exponents[0] > 3.0 * lle_standard_error;
    }
    // The estimates after each counted interval (a row each): the growth summed so far over the
    // time since t_start. Their last row is the exponents in QR order, before the sort.
    [[nodiscard]] std::vector<Eigen::VectorXd> running_exponents() const
    {
        std::vector<Eigen::VectorXd> out;
        out.reserve(history.size());
        Eigen::VectorXd sum = Eigen::VectorXd::Zero(history.empty() ? 0 : history.front().size());
        for (std::size_t k = 0; k < history.size(); ++k) {
            sum += history[k];
            out.push_back(sum / (history_t[k] - t_start));
        }
        return out;
    }
};

// What a sweep keeps of a result (its journal, its tables, Python's arrays): all but the
// interval history. Without exponents they and their error are NaN.
template <class V, record_of<lyapunov_result> R>
void describe(V& v, R& r)
{
    v(field{"exponents", "the exponents, descending", "1/t", field_span::per_state, "lambda{index}"}, r.exponents);
    v(field{"lle_standard_error", "standard error of the largest exponent (8 block means)", "1/t"},
      r.lle_standard_error);
    v(field{"settled", "false when the largest exponent drifts between the halves of the window"}, r.settled);
    v(field{"impacts", "impacts of the reference orbit in the averaging window"}, r.impacts);
    v(field{"time", "length of the averaging window", "t"}, r.time);
    v(field{"misses", "second_order: deviations missing a surface; trajectory: orbit-intervals with another "
                      "impact count"},
      r.misses);
    v(field{"status", "ok, time_limit (exponents given), sticking or a failed run's outcome", "", field_span::one,
            "outcome"},
      r.status);
    v(field{"impacts_by_surface", "impacts in the window on each surface", "", field_span::per_surface,
            "impacts_{surface}"},
      r.impacts_by_surface);
    v(field{"section_points", "section points of the averaging window", "state", field_span::series},
      r.section_points);
    constexpr auto one = field_span::one;
    v(field{"impacting", "false: no impact during the transient's quiet time", "", one, {}, false}, r.impacting);
    v(field{"t_start", "start of the averaging window", "t", one, {}, false}, r.t_start);
    v(field{"intervals", "counted intervals", "", one, {}, false}, r.intervals);
    v(field{"divergence_average", "<div F> over the window", "1/t", one, {}, false}, r.divergence_average);
    v(field{"jump_log_det_rate", "sum of ln|det S| over the window's impacts per time", "1/t", one, {}, false},
      r.jump_log_det_rate);
    v(field{"sum_rule", "the two added: what the exponents add up to", "1/t", one, {}, false}, r.sum_rule);
    v.group(field{"transient_stats", "counters of the transient", "", one, {}, false}, r.transient_stats);
    v.group(field{"stats", "counters of the interval runs", "", one, {}, false}, r.stats);
}

void validate(const model& m, const lyapunov_options& o);

lyapunov_result lyapunov(const model& m, const Eigen::VectorXd& x0, const lyapunov_options& o);

}  // namespace vimpact
