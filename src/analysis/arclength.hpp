#pragma once
// Pseudo-arclength continuation of the zeros of F: R^(n+1) -> R^n, shared by branches of
// periodic orbits (one parameter) and curves of bifurcation points (two parameters, one more
// equation). The systems are those of continuation.cpp and bifurcation_curve.cpp; this file
// knows nothing about orbits beyond the map evaluation it carries along.
#include <atomic>
#include <functional>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "vimpact/analysis/continuation.hpp"
#include "vimpact/analysis/orbit_map.hpp"

namespace vimpact::detail {

struct arc_eval {
    outcome status = outcome::ok;
    Eigen::VectorXd F;
    Eigen::MatrixXd J;       // n x (n + 1), when asked for
    orbit_map_value orbit;   // the map at u (with the tangent when J was asked for)
    [[nodiscard]] bool ok() const { return status == outcome::ok; }
};

// F at u, with its Jacobian when `jacobian`.
using arc_system = std::function<arc_eval(const Eigen::VectorXd& u, bool jacobian)>;

struct arc_point {
    Eigen::VectorXd u;
    Eigen::VectorXd t;       // unit tangent, oriented along the curve
    arc_eval at;             // with J
    int iterations = 0;      // corrector iterations with the Jacobian
    int chord_iterations = 0;  // and with the previous point's (see correct)
    double s = 0.0;          // arclength from the curve's first point
};

// Newton's method on F(u) = 0, d . (u - u_pred) = 0 from u_pred, until |F|_inf <= tol; the
// result carries J at the solution. With `chord` (the Jacobian of a nearby point, the last of
// the curve) the iterates are first evaluated without their Jacobian and corrected with that
// one (a chord method: a map run without the tangent flow costs a fraction of one with it),
// as long as each step at least halves |F|; then with their own. nullopt when it does not
// converge (last_failure: the map's outcome if the map failed).
std::optional<arc_point> correct(const arc_system& f, const Eigen::VectorXd& u_pred, const Eigen::VectorXd& d,
                                 double tol, int iterations, outcome* last_failure = nullptr,
                                 const Eigen::MatrixXd* chord = nullptr);

// The unit null vector of J (n x (n + 1)), oriented to have a positive dot product with
// `orient` (or a positive last component when orient is empty).
Eigen::VectorXd null_direction(const Eigen::MatrixXd& J, const Eigen::VectorXd& orient);

// The point of the curve at arclength s from a, along a's tangent (the corrector's plane).
std::optional<arc_point> point_at(const arc_system& f, const arc_point& a, double s, double tol, int iterations);

// A box the curve must stay in: component `index` of u within [lo, hi].
struct arc_bound {
    int index = 0;
    double lo = 0.0, hi = 0.0;
};

struct arc_settings {
    double step = 0.0, min_step = 0.0, max_step = 0.0;
    long max_points = 0;
    double tolerance = 1e-10;
    int newton_iterations = 10;
    std::vector<arc_bound> bounds;
    // A curve that creeps, stall_steps accepted steps in a row each shorter than stall_step,
    // ends as if its step had fallen below min_step (near a grazing the corrector's reach
    // shrinks without bound; nowhere else do steps stay that short). 0: never.
    double stall_step = 0.0;
    int stall_steps = 5;
    const std::atomic<bool>* cancel = nullptr;
};

// The settings of a continuation over a parameter range of width `range` (zero steps of the
// options: range / 100 to start, range / 20 at most, range * 1e-9 at least; a creep below
// range * 1e-6 stalls).
arc_settings settings_of(const arclength_options& a, double range, std::vector<arc_bound> bounds,
                         const std::atomic<bool>* cancel);

// What a step hook makes of a corrected step from `previous` to `next`.
enum class step_verdict {
    accept,       // next is a point of the curve
    reject,       // the step is retried at half its length
    stop_before,  // the curve ends at previous (arc_curve::stopped), next is dropped
    stop_after,   // the curve ends at next (arc_curve::stopped)
};

// Called for every corrected step, in order (the step onto a bound included).
using arc_step_hook = std::function<step_verdict(const arc_point& previous, const arc_point& next)>;

struct arc_curve {
    std::vector<arc_point> points;
    branch_end end = branch_end::range;
    outcome failure = outcome::ok;
    bool stopped = false;  // by the step hook
};

// Follows the curve from `first` (with its tangent) until it leaves the bounds (the last point
// put on the bound), closes, or a limit. The step adapts to the corrector's effort and to the
// curve's turning (at most 30 degrees a step).
arc_curve follow_curve(const arc_system& f, arc_point first, const arc_settings& s, const arc_step_hook& on_step);

// The tangent of a corrected point, oriented like `orient`.
void set_tangent(arc_point& p, const Eigen::VectorXd& orient);

}  // namespace vimpact::detail
