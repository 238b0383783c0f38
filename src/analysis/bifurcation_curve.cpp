#include "vimpact/analysis/bifurcation_curve.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <Eigen/LU>
#include <Eigen/SVD>

#include "arclength.hpp"
#include "orbit_system.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "jobs/job_loop.hpp"

namespace vimpact {

bool second_parameter_in_range(const model& m, const curve_options& c)
{
    const double q = m.parameters().at(static_cast<std::size_t>(c.parameter2));
    return q >= c.lo2 && q <= c.hi2;
}

void validate(const model& m, const continuation_options& o, const curve_options& c)
{
    validate(m, o);
    const int P = static_cast<int>(m.parameters().size());
    if (c.parameter2 < 0 || c.parameter2 >= P)
        throw input_error("second parameter index " + std::to_string(c.parameter2) + " is out of range [0, " +
                          std::to_string(P - 1) + "]");
    if (c.parameter2 == o.parameter)
        throw input_error("the second parameter must differ from the continued one (" +
                          m.info().parameters[static_cast<std::size_t>(o.parameter)].name + ")");
    if (!std::isfinite(c.lo2) || !std::isfinite(c.hi2) || !(c.lo2 < c.hi2))
        throw input_error("the second parameter's range must be finite with lo < hi (got " + format_double(c.lo2) +
                          ", " + format_double(c.hi2) + ")");
    (void)m.with_parameter(c.parameter2, c.lo2);
    (void)m.with_parameter(c.parameter2, c.hi2);
    if (!second_parameter_in_range(m, c))
        throw input_error("the second parameter's value " +
                          format_double(m.parameters()[static_cast<std::size_t>(c.parameter2)]) +
                          " is outside its range [" + format_double(c.lo2) + ", " + format_double(c.hi2) +
                          "]: the curves start there");
    validate(c.arclength);
    if (c.types.empty()) throw input_error("no bifurcation type chosen for the curves");
    for (const auto t : c.types)
        if (t == bifurcation_type::neimark_sacker)
            throw input_error("curves of Neimark-Sacker points are not computed (fold, period_doubling, grazing)");
}

namespace detail {
namespace {

// The bifurcation condition g(u) and the periodic-orbit equations as one arclength system in
// u = (z, p, q). The border (fold, period doubling) and the grazing window follow the curve:
// they are renewed at each accepted point, which changes g's scale but not its zeros. A
// switch's grazing (switch_surface >= 0) needs neither: g is the extremum of its switching
// function nearest 0 on the orbit.
class curve_system {
public:
    curve_system(orbit_system sys, bifurcation_type type, grazing_window window, int switch_surface = -1)
        : m_sys(std::move(sys)), m_type(type), m_window(window), m_switch(switch_surface)
    {
        if (surface_grazing()) m_sys = m_sys.with_absent(m_window);
    }
    [[nodiscard]] bool surface_grazing() const { return m_type == bifurcation_type::grazing && m_switch < 0; }

    [[nodiscard]] const orbit_system& orbits() const { return m_sys; }
    [[nodiscard]] int unknowns() const { return m_sys.chart_size() + 2; }

    // B = DP - I (fold) or DP + I (period doubling) from DG = DP - I.
    [[nodiscard]] Eigen::MatrixXd singular_matrix(const orbit_map_value& o) const
    {
        Eigen::MatrixXd B = o.residual_jacobian;
        if (m_type == bifurcation_type::period_doubling) B += 2.0 * Eigen::MatrixXd::Identity(B.rows(), B.cols());
        return B;
    }

    // The border: B's singular vectors for its smallest singular value.
    void renew(const orbit_map_value& o)
    {
        if (m_type == bifurcation_type::grazing && m_switch >= 0) return;
        if (m_type == bifurcation_type::grazing) {
            if (const auto gm = grazing_minimum(o, m_window)) {
                const grazing_window w = window_around(o, m_window.surface, gm->t);
                m_window = w;
                m_sys = m_sys.with_absent(w);
            }
            return;
        }
        const Eigen::JacobiSVD<Eigen::MatrixXd> svd(singular_matrix(o), Eigen::ComputeFullU | Eigen::ComputeFullV);
        const Eigen::Index k = svd.singularValues().size() - 1;
        m_b = svd.matrixU().col(k);
        m_c = svd.matrixV().col(k);
    }

    // g at an evaluated orbit (with the tangent for fold and period doubling).
    [[nodiscard]] std::optional<double> condition(const orbit_map_value& o) const
    {
        if (!o.ok()) return std::nullopt;
        if (m_type == bifurcation_type::grazing)
            return m_switch >= 0 ? nearest_switch_extremum(o, m_switch) : grazing_test(o, m_window);
        const Eigen::MatrixXd B = singular_matrix(o);
        const Eigen::Index n = B.rows();
        Eigen::MatrixXd A(n + 1, n + 1);
        A.topLeftCorner(n, n) = B;
        A.topRightCorner(n, 1) = m_b;
        A.bottomLeftCorner(1, n) = m_c.transpose();
        A(n, n) = 0.0;
        Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + 1);
        rhs[n] = 1.0;
        const Eigen::VectorXd x = A.fullPivLu().solve(rhs);
        if (!x.allFinite()) return std::nullopt;
        return x[n];
    }

    [[nodiscard]] bool needs_tangent() const { return m_type != bifurcation_type::grazing; }

    arc_eval operator()(const Eigen::VectorXd& u, bool jacobian) const
    {
        arc_eval e = m_sys(u, jacobian || needs_tangent());
        if (!e.ok()) return e;
        const auto g = condition(e.orbit);
        if (!g) {
            e.status = outcome::non_finite;
            return e;
        }
        const Eigen::Index K = e.F.size();
        Eigen::VectorXd F(K + 1);
        F << e.F, *g;
        e.F = F;
        if (!jacobian) return e;
        // g's gradient by central differences (one-sided where one side fails).
        Eigen::RowVectorXd dg(u.size());
        for (Eigen::Index i = 0; i < u.size(); ++i) {
            const double h = 1e-6 * std::max(1.0, std::abs(u[i]));
            Eigen::VectorXd up = u, dn = u;
            up[i] += h;
            dn[i] -= h;
            const auto gu = condition(m_sys.map(up, needs_tangent()));
            const auto gd = condition(m_sys.map(dn, needs_tangent()));
            if (gu && gd) dg[i] = (*gu - *gd) / (2.0 * h);
            else if (gu) dg[i] = (*gu - *g) / h;
            else if (gd) dg[i] = (*g - *gd) / h;
            else {
                e.status = outcome::non_finite;
                return e;
            }
        }
        Eigen::MatrixXd J(K + 1, u.size());
        J.topRows(K) = e.J;
        J.row(K) = dg;
        e.J = J;
        return e;
    }

    [[nodiscard]] arc_system as_function() const
    {
        return [this](const Eigen::VectorXd& u, bool jac) { return (*this)(u, jac); };
    }

    [[nodiscard]] curve_point to_point(const arc_point& p) const
    {
        const int K = m_sys.chart_size();
        const orbit_map_value& o = p.at.orbit;
        curve_point c;
        c.parameter = p.u[K];
        c.parameter2 = p.u[K + 1];
        c.state = o.x;
        c.period = o.period;
        c.impacts_by_surface = o.impacts_by_surface(m_sys.base().surface_count());
        c.multipliers = o.multipliers;
        c.section_multipliers = o.section_multipliers;
        c.closure = p.at.F.head(K).cwiseAbs().maxCoeff();
        c.condition = std::abs(p.at.F[K]);
        return c;
    }

private:
    orbit_system m_sys;
    bifurcation_type m_type;
    grazing_window m_window;
    int m_switch = -1;
    Eigen::VectorXd m_b, m_c;
};

// The grazing window of a located grazing point: around the surface's gap minimum nearest to
// 0, or its softest impact, on the orbit with every surface present.
std::optional<grazing_window> window_of(const orbit_system& sys, const Eigen::VectorXd& u, const bifurcation& b)
{
    const orbit_map_value o = sys.map(u, false);
    if (!o.ok()) return std::nullopt;
    std::optional<double> t;
    double best = std::numeric_limits<double>::infinity();
    for (const auto& m : o.gap_minima)
        if (m.surface == b.surface && std::abs(m.gap) < best) {
            best = std::abs(m.gap);
            t = m.t;
        }
    for (const auto& i : o.impacts)
        if (i.surface == b.surface && std::abs(i.velocity) < best) {
            best = std::abs(i.velocity);
            t = i.t;
        }
    if (!t) return std::nullopt;
    return window_around(o, b.surface, *t);
}

}  // namespace
}  // namespace detail

bifurcation_curve continue_bifurcation(const model& m, const continuation_result& r, int index,
                                       const continuation_options& o, const curve_options& c)
{
    using namespace detail;
    validate(m, o, c);
    if (index < 0 || index >= static_cast<int>(r.bifurcations.size()))
        throw input_error("bifurcation index " + std::to_string(index) + " is out of range");
    const bifurcation& b = r.bifurcations[static_cast<std::size_t>(index)];
    if (b.type == bifurcation_type::neimark_sacker)
        throw input_error("curves of Neimark-Sacker points are not computed (fold, period_doubling, grazing)");
    const continuation_branch& br = r.branches[static_cast<std::size_t>(b.branch)];
    bifurcation_curve out;
    out.type = b.type;
    out.origin = index;
    out.surface = b.surface;
    out.switch_surface = b.switch_surface;

    orbit_map_request rq;
    rq.section = o.protocol.section.index;
    rq.returns = br.returns;
    rq.chart_coordinate = br.chart_coordinate;
    rq.guess = b.point.state;
    rq.integration = o.arclength.integration;
    rq.cancel = o.cancel;
    const orbit_system orbits(m, {o.parameter, c.parameter2}, rq);
    const int K = orbits.chart_size();
    Eigen::VectorXd u(K + 2);
    u << chart_of(b.point.state, br.chart_coordinate), b.parameter, m.parameters()[static_cast<std::size_t>(c.parameter2)];

    grazing_window window;
    if (b.type == bifurcation_type::grazing && b.switch_surface < 0) {
        const auto w = window_of(orbits, u, b);
        if (!w) {
            out.failure = outcome::not_converged;
            return out;
        }
        window = *w;
    }
    curve_system system(orbits, b.type, window, b.switch_surface);
    const arc_system f = system.as_function();
    const orbit_map_value o0 = system.orbits().map(u, true);
    if (!o0.ok()) {
        out.failure = o0.status;
        return out;
    }
    system.renew(o0);

    // The bifurcation point refined at the given q (the direction of q held).
    Eigen::VectorXd eq = Eigen::VectorXd::Zero(K + 2);
    eq[K + 1] = 1.0;
    outcome why = outcome::ok;
    std::optional<arc_point> first = correct(f, u, eq, c.arclength.tolerance, 2 * c.arclength.newton_iterations, &why);
    if (!first) {
        out.failure = why == outcome::ok ? outcome::not_converged : why;
        return out;
    }
    system.renew(first->at.orbit);

    const double lo = std::min(o.start, o.end), hi = std::max(o.start, o.end);
    // Steps from the larger of the two ranges (both parameters are in the arclength).
    const double range = std::max(hi - lo, c.hi2 - c.lo2);
    arc_settings st = settings_of(c.arclength, range, {arc_bound{K, lo, hi}, arc_bound{K + 1, c.lo2, c.hi2}}, o.cancel);
    const auto on_step = [&](const arc_point&, const arc_point& next) {
        system.renew(next.at.orbit);
        return step_verdict::accept;
    };
    std::vector<arc_point> backward, forward;
    for (const int dir : {-1, 1}) {
        arc_point start = *first;
        set_tangent(start, dir * eq);
        system.renew(start.at.orbit);
        arc_curve curve = follow_curve(f, start, st, on_step);
        (dir < 0 ? out.end_backward : out.end_forward) = curve.end;
        if (curve.failure != outcome::ok) out.failure = curve.failure;
        (dir < 0 ? backward : forward) = std::move(curve.points);
    }
    // Both start at the refined point: it appears once, at `start`.
    for (auto it = backward.rbegin(); it != backward.rend(); ++it) out.points.push_back(system.to_point(*it));
    out.start = backward.size() - 1;
    for (std::size_t i = 1; i < forward.size(); ++i) out.points.push_back(system.to_point(forward[i]));
    return out;
}

std::vector<bifurcation_curve> continue_bifurcations(const model& m, const continuation_result& r,
                                                     const continuation_options& o, const curve_options& c, int threads)
{
    validate(m, o, c);
    std::vector<int> chosen;
    for (std::size_t i = 0; i < r.bifurcations.size(); ++i)
        if (std::find(c.types.begin(), c.types.end(), r.bifurcations[i].type) != c.types.end())
            chosen.push_back(static_cast<int>(i));
    std::vector<bifurcation_curve> out(chosen.size());
    job_loop_options jo;
    jo.threads = threads;
    jo.stop = o.cancel;
    run_jobs<bifurcation_curve>(
        {static_cast<long>(chosen.size()), 0}, jo, {},
        [&](long j, const bifurcation_curve*) {
            return continue_bifurcation(m, r, chosen[static_cast<std::size_t>(j)], o, c);
        },
        [&](long j, bifurcation_curve&& curve) { out[static_cast<std::size_t>(j)] = std::move(curve); });
    return out;
}

}  // namespace vimpact
