#pragma once
// Floquet multipliers of a periodic orbit with impacts (the paper's Algorithm 1, Eq. 9-10),
// with the orbit refined by Newton shooting before the monodromy is formed.
//
//  1. Run the protocol on a section of the model (transient impacts discarded, section points
//     recorded) and classify the period; P0 orbits are periodic orbits too, classified on
//     their own section points. Aperiodic or failed runs stop here: no multipliers.
//  2. Newton shooting on P^k(z) = z (k = the section returns per period) from the first
//     recorded point, until the closure |P^k(z) - z|_inf <= tolerance (1e-11).
//  3. Monodromy Phi(T) = Phi_n S_n ... S_1 Phi_1 over exactly one period from the refined
//     point: the tangent part of the variational flow, with the chosen jump at each impact.
//  4. Multipliers = eigenvalues of Phi(T). The trivial multiplier is the one whose eigenvector
//     is most nearly parallel to F(x*) (Phi F(x*) = F(x*) exactly for the true monodromy); its
//     distance from 1 measures the accuracy.
//
// Identity checked by the tests: det Phi(T) = exp(integral of div F over T) * prod det S_i.
#include <complex>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vimpact/core/option.hpp"

#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/tangent/impact_jump.hpp"

namespace vimpact {

struct floquet_options {
    protocol_options protocol{};       // transient impacts, recorded points, section (a crossing)
    double period_tolerance = default_period_tolerance;  // for the period label
    double newton_tolerance = 1e-11;   // closure |P^k(z) - z| to reach by shooting
    int newton_iterations = 20;
    // Tolerances of the tangent runs: Newton closes the orbit to 1e-11 only if the map is that
    // accurate, so never looser than 1e-12 whatever the protocol's.
    integrator_options tangent_integration{.rtol = 1e-12, .atol = 1e-12};

    impact_tangent jump = impact_tangent::saltation;  // jump used in the final monodromy
    double sample_dt = 0.0;            // >= 1e-6: sample the refined orbit over one period
};

// What a user sets besides the protocol (the tangent runs' tolerances and the orbit samples
// are set by each front end).
template <class V, record_of<floquet_options> O>
void declare(V& v, O& o)
{
    v(period_tolerance_option, o.period_tolerance);
    v(option{"newton_tol", "closure |P^k(z) - z| to reach by Newton shooting", above(0.0)}, o.newton_tolerance);
    v(option{"newton_iterations", "Newton steps allowed", between(0.0, 1000.0)}, o.newton_iterations);
    v(option{"impact_map", "jump at the impacts in the final monodromy: the saltation matrix, the reset's Jacobian "
                           "alone, or none (the last two to show what the saltation corrects)"},
      o.jump, monodromy_jumps);
}

struct floquet_result {
    // ok, not_converged (Newton missed its tolerance; multipliers given), aperiodic, sticking,
    // or the outcome of a failed run.
    outcome status = outcome::ok;
    std::string label;                 // the protocol's period label
    int section_returns = 0;           // k: section points per period
    double period = 0.0;               // T
    long impacts_per_period = 0;
    std::vector<long> impacts_by_surface;
    double initial_closure = 0.0;      // |P^k(z) - z| at the protocol's point
    double closure = 0.0;              // after Newton
    int newton_iterations = 0;
    Eigen::VectorXd orbit_point;       // refined point on the section
    Eigen::MatrixXd monodromy;
    // Trivial multiplier first, then the others by decreasing modulus.
    std::vector<std::complex<double>> multipliers;
    double trivial_error = 0.0;        // |mu_trivial - 1|
    double trivial_residual = 0.0;     // |Phi F - mu_trivial F| / |F|
    double max_nontrivial_modulus = 0.0;
    double det_monodromy = 0.0;
    double liouville_det = 0.0;        // exp(integral div F) * prod det(jump)
    double divergence_integral = 0.0;
    double log_det_jumps = 0.0;
    impact_tangent jump = impact_tangent::saltation;
    impact_series impacts;             // over one period
    state_series orbit;                // samples over one period (sample_dt > 0)
    state_series section_points;       // the protocol's recorded points (diagrams)
    run_stats protocol_stats;
    run_stats tangent_stats;           // the last map evaluation
    long map_evaluations = 0;

    [[nodiscard]] bool has_multipliers() const
    {
        return status == outcome::ok || status == outcome::not_converged;
    }
    [[nodiscard]] bool stable() const { return status == outcome::ok && max_nontrivial_modulus < 1.0; }
};

// What a sweep keeps of a result (its journal, its tables, Python's arrays): all but the
// monodromy, the impacts and the orbit samples. Without multipliers the period, the trivial
// error and the largest modulus are NaN and the impact counts 0.
template <class V, record_of<floquet_result> R>
void describe(V& v, R& r)
{
    v(field{"label", "the protocol's period label"}, r.label);
    v(field{"period", "the period T", "t"}, r.period);
    v(field{"impacts_per_period", "impacts per period on every surface", "", field_span::one, "impacts"},
      r.impacts_per_period);
    v(field{"trivial_error", "|mu_trivial - 1|: the accuracy of the monodromy"}, r.trivial_error);
    v(field{"max_nontrivial_modulus", "the largest modulus of the nontrivial multipliers"}, r.max_nontrivial_modulus);
    v(field{"closure", "|P^k(z) - z| after Newton shooting (NaN without a period)", "state"}, r.closure);
    v(field{"status", "ok, not_converged (multipliers given), aperiodic, sticking or a failed run's outcome", "",
            field_span::one, "outcome"},
      r.status);
    v(field{"impacts_by_surface", "impacts per period on each surface", "", field_span::per_surface,
            "impacts_{surface}"},
      r.impacts_by_surface);
    v(field{"multipliers", "the multipliers, the trivial one first, then by decreasing modulus", "",
            field_span::spectrum},
      r.multipliers);
    v(field{"section_points", "the protocol's recorded section points", "state", field_span::series}, r.section_points);
    constexpr auto one = field_span::one;
    v(field{"section_returns", "section points per period", "", one, {}, false}, r.section_returns);
    v(field{"initial_closure", "|P^k(z) - z| before Newton shooting", "state", one, {}, false}, r.initial_closure);
    v(field{"newton_iterations", "Newton steps taken", "", one, {}, false}, r.newton_iterations);
    v(field{"orbit_point", "the refined point on the section", "state", field_span::per_state, {}, false},
      r.orbit_point);
    v(field{"trivial_residual", "|Phi F - mu_trivial F| / |F|", "", one, {}, false}, r.trivial_residual);
    v(field{"det_monodromy", "det Phi(T)", "", one, {}, false}, r.det_monodromy);
    v(field{"liouville_det", "exp(integral of div F) * prod det(jump)", "", one, {}, false}, r.liouville_det);
    v(field{"divergence_integral", "integral of div F over the period", "", one, {}, false}, r.divergence_integral);
    v(field{"log_det_jumps", "sum of ln|det(jump)| over the impacts", "", one, {}, false}, r.log_det_jumps);
    v.group(field{"protocol_stats", "counters of the protocol's run", "", one, {}, false}, r.protocol_stats);
    v.group(field{"tangent_stats", "counters of the last map evaluation", "", one, {}, false}, r.tangent_stats);
    v(field{"map_evaluations", "evaluations of the return map", "", one, {}, false}, r.map_evaluations);
}

void validate(const model& m, const floquet_options& o);

// The whole analysis from an initial state.
floquet_result floquet(const model& m, const Eigen::VectorXd& x0, const floquet_options& o);

// Steps 2-4 from a point near the orbit on the section, with a known number of returns.
floquet_result floquet_from_point(const model& m, const Eigen::VectorXd& x_guess, int returns,
                                  const floquet_options& o);

}  // namespace vimpact
