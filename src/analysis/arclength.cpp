#include "arclength.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/LU>
#include <Eigen/QR>

namespace vimpact::detail {

namespace {

double max_abs(const Eigen::VectorXd& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

bool cancelled(const std::atomic<bool>* c) { return c && c->load(std::memory_order_relaxed); }

}  // namespace

Eigen::VectorXd null_direction(const Eigen::MatrixXd& J, const Eigen::VectorXd& orient)
{
    // J^T = Q R: the last column of Q is orthogonal to every row of J.
    const Eigen::Index n1 = J.cols();
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(J.transpose());
    Eigen::VectorXd e = Eigen::VectorXd::Zero(n1);
    e[n1 - 1] = 1.0;
    Eigen::VectorXd t = qr.householderQ() * e;
    t.normalize();
    const double sign = orient.size() ? t.dot(orient) : t[n1 - 1];
    if (sign < 0.0) t = -t;
    return t;
}

arc_settings settings_of(const arclength_options& a, double range, std::vector<arc_bound> bounds,
                         const std::atomic<bool>* cancel)
{
    arc_settings s;
    s.max_step = a.max_step > 0.0 ? a.max_step : range / 20.0;
    s.step = a.step > 0.0 ? a.step : std::min(range / 100.0, s.max_step);
    s.min_step = a.min_step > 0.0 ? a.min_step : range * 1e-9;
    s.step = std::clamp(s.step, s.min_step, s.max_step);
    s.max_points = a.max_points;
    s.tolerance = a.tolerance;
    s.newton_iterations = a.newton_iterations;
    s.bounds = std::move(bounds);
    s.stall_step = std::min(range * 1e-6, s.max_step);
    s.cancel = cancel;
    return s;
}

void set_tangent(arc_point& p, const Eigen::VectorXd& orient) { p.t = null_direction(p.at.J, orient); }

namespace {

// One Newton step of the bordered system [J; d^T] du = -[F; d . (u - u_pred)].
std::optional<Eigen::VectorXd> newton_step(const Eigen::MatrixXd& J, const Eigen::VectorXd& F, const Eigen::VectorXd& d,
                                           const Eigen::VectorXd& u, const Eigen::VectorXd& u_pred)
{
    const Eigen::Index n = F.size();
    Eigen::MatrixXd A(n + 1, n + 1);
    A.topRows(n) = J;
    A.row(n) = d.transpose();
    Eigen::VectorXd rhs(n + 1);
    rhs.head(n) = -F;
    rhs[n] = -d.dot(u - u_pred);
    Eigen::VectorXd du = A.fullPivLu().solve(rhs);
    if (!du.allFinite()) return std::nullopt;
    return du;
}

}  // namespace

std::optional<arc_point> correct(const arc_system& f, const Eigen::VectorXd& u_pred, const Eigen::VectorXd& d,
                                 double tol, int iterations, outcome* last_failure, const Eigen::MatrixXd* chord)
{
    Eigen::VectorXd u = u_pred;
    double first = -1.0;
    int it = 0, chorded = 0;
    if (chord && chord->rows() > 0) {
        // Chord iterations while they converge fast; what they reach is checked (and finished)
        // by the full iterations below, which also evaluate the Jacobian at the solution.
        double last = -1.0;
        Eigen::VectorXd best = u;
        for (; it < iterations; ++it) {
            const arc_eval e = f(u, false);
            const double norm = e.ok() ? max_abs(e.F) : std::numeric_limits<double>::quiet_NaN();
            if (!std::isfinite(norm) || (last >= 0.0 && norm > 0.5 * last)) {
                u = best;  // the full iterations go on from the best iterate
                break;
            }
            best = u;
            if (first < 0.0) first = norm;
            if (norm <= tol) break;
            const auto du = newton_step(*chord, e.F, d, u, u_pred);
            if (!du) break;
            u += *du;
            last = norm;
        }
        chorded = it;
    }
    for (; it <= iterations; ++it) {
        arc_eval e = f(u, true);
        if (!e.ok()) {
            if (last_failure) *last_failure = e.status;
            return std::nullopt;
        }
        const double norm = max_abs(e.F);
        if (!std::isfinite(norm)) return std::nullopt;
        if (first < 0.0) first = norm;
        if (norm <= tol) {
            arc_point p;
            p.u = u;
            p.at = std::move(e);
            p.iterations = it - chorded;
            p.chord_iterations = chorded;
            return p;
        }
        // A corrector that moves away from the curve has left the predictor's basin.
        if (it > 0 && norm > 1e3 * std::max(first, tol)) return std::nullopt;
        if (it == iterations) break;
        const auto du = newton_step(e.J, e.F, d, u, u_pred);
        if (!du) return std::nullopt;
        u += *du;
    }
    return std::nullopt;
}

std::optional<arc_point> point_at(const arc_system& f, const arc_point& a, double s, double tol, int iterations)
{
    auto p = correct(f, a.u + s * a.t, a.t, tol, iterations);
    if (!p) return std::nullopt;
    set_tangent(*p, a.t);
    p->s = a.s + s;
    return p;
}

arc_curve follow_curve(const arc_system& f, arc_point first, const arc_settings& s, const arc_step_hook& on_step)
{
    arc_curve curve;
    const double cos_max_turn = std::cos(std::numbers::pi / 6.0);
    double ds = s.step;
    int creeping = 0;
    curve.points.push_back(std::move(first));
    const auto verdict = [&](const arc_point& a, const arc_point& b) {
        return on_step ? on_step(a, b) : step_verdict::accept;
    };
    for (;;) {
        if (cancelled(s.cancel)) {
            curve.end = branch_end::interrupted;
            return curve;
        }
        if (static_cast<long>(curve.points.size()) >= s.max_points) {
            curve.end = branch_end::point_limit;
            return curve;
        }
        const arc_point& a = curve.points.back();
        std::optional<arc_point> b;
        outcome failure = outcome::ok;
        bool map_failed_only = true;
        bool on_bound = false;
        step_verdict v = step_verdict::accept;
        while (!b) {
            if (ds < s.min_step) {
                curve.end = map_failed_only && failure != outcome::ok ? branch_end::failed : branch_end::step_too_small;
                curve.failure = failure;
                return curve;
            }
            outcome why = outcome::ok;
            b = correct(f, a.u + ds * a.t, a.t, s.tolerance, s.newton_iterations, &why, &a.at.J);
            if (b) {
                set_tangent(*b, a.t);
                // Too sharp a turn: the step jumped to another curve or cut a corner.
                if (b->t.dot(a.t) < cos_max_turn || (b->u - a.u).norm() > 2.0 * ds) b.reset();
            }
            if (b) {
                b->s = a.s + (b->u - a.u).norm();
                // Leaving the box: the step ends on the bound instead.
                on_bound = false;
                for (const arc_bound& bd : s.bounds) {
                    const double x = b->u[bd.index];
                    if (x >= bd.lo && x <= bd.hi) continue;
                    const double target = x < bd.lo ? bd.lo : bd.hi;
                    // Already on that bound (a curve started there): it ends where it is.
                    if (a.u[bd.index] == target) {
                        curve.end = branch_end::range;
                        return curve;
                    }
                    const double rate = a.t[bd.index];
                    std::optional<arc_point> e;
                    if (std::abs(rate) > 1e-12) {
                        Eigen::VectorXd dir = Eigen::VectorXd::Zero(a.u.size());
                        dir[bd.index] = 1.0;
                        Eigen::VectorXd pred = a.u + ((target - a.u[bd.index]) / rate) * a.t;
                        pred[bd.index] = target;
                        e = correct(f, pred, dir, s.tolerance, s.newton_iterations);
                    }
                    if (!e) {
                        curve.end = branch_end::range;
                        return curve;
                    }
                    set_tangent(*e, a.t);
                    e->s = a.s + (e->u - a.u).norm();
                    b = std::move(e);
                    on_bound = true;
                    break;
                }
                v = verdict(a, *b);
                if (v == step_verdict::reject) b.reset();
                map_failed_only = false;
            } else if (why == outcome::ok) {
                map_failed_only = false;
            } else {
                failure = why;
            }
            if (!b) ds *= 0.5;
            if (cancelled(s.cancel)) {
                curve.end = branch_end::interrupted;
                return curve;
            }
        }
        if (v == step_verdict::stop_before) {
            curve.stopped = true;
            return curve;
        }
        // The corrector's effort: a chord iteration (no tangent flow) counts half.
        const double its = b->iterations + 0.5 * b->chord_iterations;
        creeping = (b->u - a.u).norm() < s.stall_step ? creeping + 1 : 0;
        const bool closed = !on_bound && curve.points.size() >= 8 &&
                            (b->u - curve.points.front().u).norm() < 0.5 * ds && b->t.dot(curve.points.front().t) > 0.0;
        curve.points.push_back(std::move(*b));
        if (v == step_verdict::stop_after) {
            curve.stopped = true;
            return curve;
        }
        if (on_bound) {
            curve.end = branch_end::range;
            return curve;
        }
        if (closed) {
            curve.end = branch_end::closed;
            return curve;
        }
        if (creeping >= s.stall_steps) {
            curve.end = branch_end::step_too_small;
            return curve;
        }
        if (its <= 3.0) ds = std::min(1.5 * ds, s.max_step);
        else if (its >= 6.0) ds *= 0.6;
    }
}

}  // namespace vimpact::detail
