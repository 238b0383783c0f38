#pragma once
// Numerical continuation of impacting periodic orbits in one parameter, stable and unstable
// alike, with their bifurcations located and period doublings switched onto.
//
// The orbits. A periodic orbit that crosses the section Sigma k times per period is a zero of
//   G(z, p) = chart(P^k(x(z); p) - x(z))          (analysis/orbit_map.hpp)
// in the chart coordinates z of Sigma (dim - 1 numbers) and the parameter p: n equations in
// n + 1 unknowns u = (z, p), whose solutions form curves (branches).
//
// Pseudo-arclength continuation. From a point u_j with unit tangent t_j (the null vector of
// [G_z G_p], oriented along the branch), the predictor u_j + ds t_j is corrected by Newton's
// method on G(u) = 0, t_j . (u - u_j - ds t_j) = 0. The matrix [G_z G_p; t_j^T] stays regular
// at folds, so the branch is followed around them and onto its unstable part. G_z = DP - I
// comes from the tangent flow (saltation matrices at the impacts); G_p by central differences
// of the map in p. The step ds grows after easy corrections and shrinks after hard or failed
// ones, and when the branch turns by more than 30 degrees in one step.
//
// Every point carries its period, its impacts per surface, all Floquet multipliers (of the
// monodromy with saltation; trivial first) and its closure |G|_inf <= tolerance.
//
// Bifurcations, between consecutive points with the same impact sequence, by the sign of
//   fold             t_p, the parameter component of the tangent (a multiplier through +1)
//   period doubling  det(DP + I) (a multiplier through -1)
//   Neimark-Sacker   prod_{i<j} (mu_i mu_j - 1) over the multipliers of DP (a complex pair
//                    through the unit circle; a real pair with mu_i mu_j = 1, a neutral saddle,
//                    changes its sign too and is not reported)
// and grazing, where the impact sequence changes: a local minimum of a gap reaching 0, or an
// impact's velocity going to 0. A switch is grazed where the number of its crossings per
// period changes: an extremum of its switching function goes through 0 (the test function:
// the extremum nearest 0, signed). The orbit's flow is continuous there, so the branch goes
// on through it. Each is located on the branch by the Illinois method on the
// arclength (every trial point corrected onto the branch) until the parameter is known to
// `locate_tolerance`. The grazing test function is the smallest gap minimum of the surface on
// the side without the new impact (that surface made absent where the orbit does not hit it
// there, so that the gap goes smoothly through 0), and minus the penetration v^2 / (2 g'') the
// free flow would make at the new impact on the other side.
//
// Branch switching at a period doubling of P^k: the fixed points of P^2k near it form a
// pitchfork whose legs leave the bifurcation point u* along +-v (v the eigenvector of DP for
// -1). The two legs are the same orbit (P^k maps one onto the other), so one is followed: it
// is started at z* + eps v with that component held fixed, then continued like any branch
// (all its section points are in every point). A step of a branch of P^2k onto an orbit of
// P^k (the old branch taken twice round, which crosses it at u*) is refused.
#include <atomic>
#include <complex>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "vimpact/analysis/orbit_map.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/option.hpp"

namespace vimpact {

enum class bifurcation_type { fold, period_doubling, neimark_sacker, grazing };

constexpr std::string_view to_string(bifurcation_type b)
{
    switch (b) {
        case bifurcation_type::fold: return "fold";
        case bifurcation_type::period_doubling: return "period_doubling";
        case bifurcation_type::neimark_sacker: return "neimark_sacker";
        case bifurcation_type::grazing: return "grazing";
    }
    return "unknown";
}

// Why a branch (or a curve) ended.
enum class branch_end {
    range,            // it left the parameter range (its last point is on the range's end)
    point_limit,      // max_points reached
    step_too_small,   // the step fell below min_step without a correction converging, or crept,
                      // next to no grazing or section event that explains it
    section_impact,   // its section point meets an impact (the orbit hits a surface at the
                      // section) and the branch could not be taken on past it
    closed,           // it came back to its first point (an isola or a loop)
    grazing,          // at a grazing point it cannot be continued through
    failed,           // the map failed (the outcome says how: sticking, chattering, ...)
    interrupted,      // the cancel flag was set
};

constexpr std::string_view to_string(branch_end e)
{
    switch (e) {
        case branch_end::range: return "range";
        case branch_end::point_limit: return "point_limit";
        case branch_end::step_too_small: return "step_too_small";
        case branch_end::section_impact: return "section_impact";
        case branch_end::closed: return "closed";
        case branch_end::grazing: return "grazing";
        case branch_end::failed: return "failed";
        case branch_end::interrupted: return "interrupted";
    }
    return "unknown";
}

// The steps and tolerances of a continuation (one or two parameters).
struct arclength_options {
    double step = 0.0;        // first step in arclength (z and parameters together); 0: range / 100
    double min_step = 0.0;    // 0: range * 1e-9
    double max_step = 0.0;    // 0: range / 20
    long max_points = 2000;
    double tolerance = 1e-10;  // closure |G|_inf of every point
    int newton_iterations = 10;
    // Tangent flow and map runs: closing to 1e-10 needs a map much more accurate than that.
    integrator_options integration{.rtol = 1e-12, .atol = 1e-12};
};

// What a user sets of the steps and tolerances (the tangent runs' accuracy follows the
// protocol's: integrate/tangent_integration.hpp).
template <class V, record_of<arclength_options> O>
void declare(V& v, O& o)
{
    v(option{"ds", "first arclength step, parameter and section coordinates together (0: the range / 100)",
             at_least(0.0)},
      o.step);
    v(option{"ds_min", "smallest arclength step (0: the range * 1e-9)", at_least(0.0)}, o.min_step);
    v(option{"ds_max", "largest arclength step (0: the range / 20)", at_least(0.0)}, o.max_step);
    v(option{"max_points", "points per branch at most", between(2.0, 1e6)}, o.max_points);
    v(option{"closure_tol", "closure |P^k(z) - z| of every point", value_range{0.0, 1e-4, false, true}}, o.tolerance);
    v(option{"newton_iterations", "corrector iterations per step", between(1.0, 100.0)}, o.newton_iterations);
}

struct continuation_options {
    int parameter = 0;
    double start = 0.0;   // the branch starts here
    double end = 0.0;     // and runs towards here; it ends where the parameter leaves [start, end]
    // How the first orbit is found: the protocol's attractor from the initial state at `start`
    // (its section and its period), or, with returns > 0 and from_attractor false, Newton's
    // method from the initial state taken as a point near the orbit on the section.
    protocol_options protocol{};
    double period_tolerance = default_period_tolerance;
    bool from_attractor = true;
    int returns = 0;      // section returns per period; 0: the protocol's period
    arclength_options arclength{};
    bool detect = true;              // locate bifurcations
    double locate_tolerance = 1e-10;  // parameter accuracy of a located bifurcation
    int switch_depth = 0;            // period doublings switched onto, recursively (0: none)
    const std::atomic<bool>* cancel = nullptr;
};

// What a user sets besides the parameter, its range, the protocol and the starts.
template <class V, record_of<continuation_options> O>
void declare(V& v, O& o)
{
    v(option{"period",
             "section returns per period of the first orbit, found by Newton's method from the initial state taken "
             "as a point near it on the section (no transient; for unstable orbits); 0: the protocol's attractor",
             between(0.0, 1000.0)},
      o.returns);
    v(option{"switch", "switch onto the doubled branch at period doublings, this many times in a row",
             between(0.0, 8.0)},
      o.switch_depth);
    v(period_tolerance_option, o.period_tolerance);
    declare(v, o.arclength);
    v(option{"locate_tol", "parameter accuracy of located bifurcations", above(0.0)}, o.locate_tolerance);
    v(option{"detect", "locate folds, period doublings and Neimark-Sacker points (grazings always are)"}, o.detect);
}

struct continuation_point {
    double parameter = 0.0;
    Eigen::VectorXd state;             // the orbit's point on the section
    state_series section_points;       // its k points on the section, in order (state first)
    double period = 0.0;
    std::vector<long> impacts_by_surface;
    std::vector<int> impact_sequence;  // the surfaces hit in one period, in order
    std::vector<std::complex<double>> multipliers;  // of the monodromy: trivial first, then by modulus
    std::vector<std::complex<double>> section_multipliers;  // the nontrivial ones (of DP)
    bool stable = false;               // every nontrivial multiplier inside the unit circle
    double closure = 0.0;              // |G|_inf
    int newton_iterations = 0;
    double arclength = 0.0;            // along the branch from its first point
    // Per surface: the smallest local gap minimum between impacts, and the smallest impact
    // velocity (infinity where none): how far the orbit is from grazing each surface.
    std::vector<double> min_gap;
    std::vector<double> min_impact_velocity;

    [[nodiscard]] long impacts() const;
};

struct continuation_branch {
    int returns = 1;       // k
    int chart_coordinate = 0;
    int parent = -1;       // the branch it was switched from
    int origin = -1;       // the bifurcation (index in continuation_result::bifurcations)
    std::vector<continuation_point> points;
    branch_end end = branch_end::range;
    outcome failure = outcome::ok;  // end == failed: the map's outcome
};

struct bifurcation {
    bifurcation_type type = bifurcation_type::fold;
    int branch = 0;
    int after_point = 0;   // between points after_point and after_point + 1 of its branch
    bool located = true;   // false: the location did not converge (parameter to within bracket)
    double parameter = 0.0;
    double bracket = 0.0;  // width of the last parameter bracket (or change of the last step)
    continuation_point point;  // the orbit at the bifurcation
    int surface = -1;      // grazing: the surface
    int switch_surface = -1;  // grazing of a switch: the switch (surface -1) ...
    long crossings_before = 0, crossings_after = 0;  // ... and its crossings per period along the branch
    double time = 0.0;     // grazing: when, from the orbit's section point
    std::vector<int> sequence_before, sequence_after;  // grazing: impact sequences along the branch
};

struct continuation_result {
    // ok; aperiodic (the protocol found no periodic attractor to start from), not_converged
    // (Newton did not close the first orbit), or the protocol's failure.
    outcome status = outcome::ok;
    std::string start_label;   // the protocol's label at the start (from_attractor)
    std::vector<continuation_branch> branches;
    std::vector<bifurcation> bifurcations;
    long tangent_maps = 0;     // map evaluations with the tangent flow
    long plain_maps = 0;       // without it (finite differences in the parameter)
};

// Why a branch ended, in words: "range" and "closed" as they are, every other end with the
// parameter value of the branch's last point, where it happened ("step too small at w =
// 0.7890862760793447", "section meets an impact at ...", "grazing at ...", "max points at
// ...", "map failed (sticking) at ...", "interrupted at ...").
std::string end_reason(const continuation_branch& b, std::string_view parameter);

// Throw input_error for bad options (parameter, range, a section that is not a crossing...).
void validate(const arclength_options& a);
void validate(const model& m, const continuation_options& o);

// One branch from each initial state (the same orbit found twice is kept once), its
// bifurcations, and the branches switched onto; starts and switched branches are computed in
// parallel through the job loop (threads: 0 every core; results never depend on it).
continuation_result continuation(const model& m, const std::vector<Eigen::VectorXd>& starts,
                                 const continuation_options& o, int threads = 0);

// The value of a multiplier test function on a point (exposed for tests): det(DP - c I) for
// c = +1 (fold) or -1 (period doubling) from the multipliers of DP, and the Neimark-Sacker
// product prod_{i<j} (mu_i mu_j - 1).
double multiplier_test(const std::vector<std::complex<double>>& section_multipliers, bifurcation_type type);

}  // namespace vimpact
