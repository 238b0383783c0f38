#pragma once
// Two-parameter continuation of bifurcation points: from a fold, period doubling or grazing
// located by a one-parameter continuation (analysis/continuation.hpp), the curve of such
// points in the plane of the continued parameter p and a second parameter q.
//
// Unknowns U = (z, p, q): the orbit's chart coordinates and both parameters; equations
//   G(z, p, q) = 0                 the periodic orbit (analysis/orbit_map.hpp)
//   g(z, p, q) = 0                 the bifurcation condition
// n + 1 equations in n + 2 unknowns, followed by pseudo-arclength continuation like a branch.
//
// Fold and period doubling: B = DP - I (fold) or DP + I (period doubling) is singular. The
// condition is minimally augmented: g is the last component of the solution of
//   [B  b] [w]   [0]
//   [c' 0] [g] = [1],
// b and c the left and right singular vectors of B for its smallest singular value at the
// previous point of the curve, so that the bordered matrix stays regular and g vanishes
// exactly where B is singular. Its derivatives are central differences of the tangent map.
// Grazing: g is the grazing test function of the one-parameter continuation (the smallest gap
// minimum of the surface on the side where the orbit does not hit it, the surface made absent
// there when the orbit does not hit it at all), by differences of the map.
#include <vector>

#include "vimpact/analysis/continuation.hpp"

namespace vimpact {

struct curve_options {
    int parameter2 = 0;
    double lo2 = 0.0, hi2 = 0.0;   // q stays in [lo2, hi2]; p in the continuation's range
    arclength_options arclength{};  // steps 0: from the ranges
    std::vector<bifurcation_type> types{bifurcation_type::fold, bifurcation_type::period_doubling,
                                        bifurcation_type::grazing};  // which points get a curve
};

struct curve_point {
    double parameter = 0.0;    // p
    double parameter2 = 0.0;   // q
    Eigen::VectorXd state;     // the orbit's point on the section
    double period = 0.0;
    std::vector<long> impacts_by_surface;
    std::vector<std::complex<double>> multipliers;          // trivial first
    std::vector<std::complex<double>> section_multipliers;  // the nontrivial ones
    double closure = 0.0;      // |G|_inf
    double condition = 0.0;    // |g|: the bifurcation condition's residual
};

struct bifurcation_curve {
    bifurcation_type type = bifurcation_type::fold;
    int origin = -1;           // the bifurcation it starts from (continuation_result::bifurcations)
    int surface = -1;          // grazing: the surface, or -1 and
    int switch_surface = -1;   // the switch
    // In order along the curve; the starting point is the one nearest to the origin's q
    // (both directions are followed from it).
    std::vector<curve_point> points;
    std::size_t start = 0;     // index of the starting point in `points`
    branch_end end_backward = branch_end::range, end_forward = branch_end::range;
    outcome failure = outcome::ok;  // the start did not converge, or a map's failure at an end
};

void validate(const model& m, const continuation_options& o, const curve_options& c);
// Whether [lo2, hi2] holds the model's value of the second parameter, where the curves start
// (validate refuses it otherwise; a front end with its own units may say so in them first).
bool second_parameter_in_range(const model& m, const curve_options& c);

// The curve through bifurcation `index` of `r` (computed by continuation with options `o`).
bifurcation_curve continue_bifurcation(const model& m, const continuation_result& r, int index,
                                       const continuation_options& o, const curve_options& c);

// A curve through every bifurcation of `r` of the chosen types, in parallel through the job
// loop (threads: 0 every core; results never depend on it); the order is that of r.bifurcations.
std::vector<bifurcation_curve> continue_bifurcations(const model& m, const continuation_result& r,
                                                     const continuation_options& o, const curve_options& c,
                                                     int threads = 0);

}  // namespace vimpact
