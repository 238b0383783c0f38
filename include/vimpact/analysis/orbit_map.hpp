#pragma once
// The section map of any model as a function of chart coordinates: the one evaluation that
// continuation (analysis/continuation.hpp) and bifurcation curves are built on.
//
// A point of the section Sigma_k = { s_k(x) = 0 } is given by its chart coordinates z, the
// state without the coordinate x_c that the section is solved for (tangent/section_map.hpp).
// The map returns the point of the `returns`-th crossing of Sigma_k, through every impact on
// the way, and the residual
//   G(z) = chart(P^k(x(z)) - x(z))     (phases compared modulo their period),
// whose zeros are the periodic orbits that cross Sigma_k k times per period. With the tangent,
// also DG = dG/dz = DP - I (DP the chart Jacobian of P^k, saltation matrices at the impacts)
// and the monodromy of the orbit segment: at a zero of G, the eigenvalues of DP are the
// orbit's nontrivial Floquet multipliers and those of the monodromy all of them (the
// trivial one, 1, among them).
//
// What a continuation watches for grazing is recorded too: every impact's normal velocity
// (minus the gap rate before the reset) and gap acceleration, and every local minimum of every
// gap between impacts. Surfaces may be made absent (passed through) so that the depth by
// which an orbit crosses a surface it only grazed stays a smooth function (its gap minimum
// goes negative instead of turning into an impact).
#include <complex>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "vimpact/core/outcome.hpp"
#include "vimpact/hybrid/flow_options.hpp"
#include "vimpact/hybrid/run_stats.hpp"
#include "vimpact/model/model.hpp"

namespace vimpact {

struct orbit_map_request {
    int section = 0;
    int returns = 1;
    int chart_coordinate = -1;   // x_c; -1: where |ds/dx_j| is largest at `guess`
    Eigen::VectorXd z;           // chart coordinates (dim - 1 numbers)
    Eigen::VectorXd guess;       // a state near the point (its x_c starts the solve for x_c)
    bool tangent = true;         // also DG, the monodromy and the multipliers
    std::uint64_t absent_surfaces = 0;  // see flow_options::absent_surfaces, with its window
    double absent_from = -std::numeric_limits<double>::infinity();  // (time from the start)
    double absent_until = std::numeric_limits<double>::infinity();
    // >= 0 (with the tangent, and that surface absent around forced_time): an impact on this
    // surface forced at forced_time whether or not the orbit reaches it there: its reset is
    // applied to the state at that time. Near a grazing the family of orbits with the new
    // impact is smooth in (z, p, forced_time), while its section map is not (its Jacobian
    // grows like 1 / v); see orbit_map_value::forced_*.
    int forced_surface = -1;
    double forced_time = 0.0;
    // Newton closes orbits to 1e-10 only if the map is much more accurate: 1e-12 by default.
    integrator_options integration{.rtol = 1e-12, .atol = 1e-12};
    // Near grazing the map loses accuracy: an error e in the gap at a soft impact of normal
    // velocity v moves the impact by e / v in time and the state after it by
    // |F(post) - R F(pre)| e / v (impact_record::sensitivity). When an impact's sensitivity
    // exceeds `sensitivity_limit`, the map is run again with both tolerances divided by
    // sensitivity / sensitivity_limit, down to `tightest_tolerance` (measured on the forced
    // impact oscillator at v = 0.002: sensitivity 1100, the residual off by 5e-10 at 1e-12, by
    // 1e-11 after the rerun). The limit sits above what a model's coupling gives at any impact
    // velocity: the paper's model, whose field jumps in proportion to v, has sensitivity
    // (1 + r) A alpha, about 15, at every impact. 0 or infinity: no rerun.
    double sensitivity_limit = 100.0;
    double tightest_tolerance = 1e-14;
    double t_max = 1e4;          // flight time allowed for the returns
    long max_steps = 50'000'000;
    const std::atomic<bool>* cancel = nullptr;
};

// One impact of the orbit segment, for grazing: velocity = -g'(x-) >= 0 and the gap's
// acceleration g''(x-) of the free flow there (g'' > 0: the free orbit would turn back after
// a penetration of about velocity^2 / (2 g'')).
struct impact_record {
    double t = 0.0;
    int surface = 0;
    double velocity = 0.0;
    double acceleration = 0.0;
    // |F(post) - R F(pre)|_inf / velocity: how far the state after the impact moves per unit
    // error in the gap before it (R the reset's Jacobian); grows like 1 / v towards grazing.
    double sensitivity = 0.0;
};

struct gap_minimum_record {
    double t = 0.0;
    int surface = 0;
    double gap = 0.0;
};

// A local extremum of a switching function h along the orbit, on either side of its switch.
struct switch_extremum_record {
    double t = 0.0;
    int k = 0;      // the switch
    double h = 0.0;
};

struct orbit_map_value {
    // ok; inadmissible (the point lies beyond a surface); not_converged (the chart does not
    // reach the section at z); sticking (a contact phase: no tangent map); or a run's outcome.
    outcome status = outcome::ok;
    int chart_coordinate = 0;
    Eigen::VectorXd x;           // the point of the section
    Eigen::VectorXd x_end;       // P^k(x)
    Eigen::VectorXd residual;    // G(z)
    double period = 0.0;         // time of the k-th return
    std::vector<Eigen::VectorXd> crossings;  // the state at each return (the last is x_end)
    std::vector<impact_record> impacts;
    std::vector<gap_minimum_record> gap_minima;
    // Per switch, its crossings before the last return; and the extrema of every switching
    // function (a branch grazes a switch where one of them goes through 0).
    std::vector<long> crossings_by_switch;
    std::vector<switch_extremum_record> switch_extrema;
    // With the tangent:
    Eigen::MatrixXd residual_jacobian;  // DG = DP - I
    Eigen::MatrixXd monodromy;          // dx(T)/dx(0), N x N, impacts included
    std::vector<std::complex<double>> multipliers;  // of the monodromy: trivial first, then by modulus
    std::vector<std::complex<double>> section_multipliers;  // of DP, by decreasing modulus
    // With a forced impact: the gap g just before it, dg/dz (chart), dg/dt_i (minus the impact
    // velocity) and dG/dt_i.
    double forced_gap = 0.0;
    Eigen::VectorXd forced_gap_gradient;
    double forced_gap_rate = 0.0;
    Eigen::VectorXd residual_time_derivative;
    run_stats stats;

    [[nodiscard]] bool ok() const { return status == outcome::ok; }
    // Impacts on each of `surfaces` surfaces.
    [[nodiscard]] std::vector<long> impacts_by_surface(int surfaces) const;
    // The sequence of surfaces hit, in time order.
    [[nodiscard]] std::vector<int> impact_sequence() const;
};

// Throws input_error for a request that does not fit the model (section, sizes, returns).
orbit_map_value orbit_map(const model& m, const orbit_map_request& r);

// The chart coordinate a request with chart_coordinate = -1 would choose at x.
int default_chart_coordinate(const model& m, int section, const Eigen::VectorXd& x);

// Chart coordinates of x (x without coordinate c).
Eigen::VectorXd chart_of(const Eigen::VectorXd& x, int c);

}  // namespace vimpact
