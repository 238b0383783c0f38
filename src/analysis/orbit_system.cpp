#include "orbit_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vimpact/core/input_error.hpp"

namespace vimpact::detail {

orbit_system orbit_system::with_returns(int k) const
{
    orbit_map_request r = m_request;
    r.returns = k;
    return {m_base, m_parameters, r};
}

orbit_system orbit_system::with_absent(const grazing_window& w) const
{
    orbit_map_request r = m_request;
    r.absent_surfaces = w.surface < 64 ? std::uint64_t{1} << w.surface : 0;
    r.absent_from = w.from;
    r.absent_until = w.until;
    return {m_base, m_parameters, r};
}

model orbit_system::model_at(const Eigen::VectorXd& u) const
{
    const int K = chart_size();
    std::vector<double> values = m_base.parameters();
    for (int j = 0; j < parameter_count(); ++j)
        values[static_cast<std::size_t>(m_parameters[static_cast<std::size_t>(j)])] = u[K + j];
    return m_base.with_parameters(values);
}

orbit_map_value orbit_system::map(const Eigen::VectorXd& u, bool tangent, int forced_surface, double forced_time) const
{
    const int K = chart_size();
    orbit_map_request r = m_request;
    r.z = u.head(K);
    r.tangent = tangent || forced_surface >= 0;
    r.forced_surface = forced_surface;
    r.forced_time = forced_time;
    ++(tangent ? m_tangent_maps : m_plain_maps);
    try {
        return orbit_map(model_at(u), r);
    } catch (const input_error&) {
        // A Newton iterate outside a parameter's valid range (r > 1, a negative damping...):
        // not an orbit of the model, like a point beyond a surface.
        orbit_map_value v;
        v.status = outcome::inadmissible;
        return v;
    }
}

bool same_impacts(const orbit_map_value& a, const orbit_map_value& b)
{
    return a.ok() && b.ok() && a.impact_sequence() == b.impact_sequence();
}

Eigen::VectorXd orbit_system::parameter_derivative(const Eigen::VectorXd& u, int j, const orbit_map_value& centre) const
{
    const int K = chart_size();
    const double p = u[K + j];
    // The map is smooth in p on the scale of the orbit's distance to grazing: v^2 for an impact
    // of normal velocity v (a free flight would go about v^2 / (2 g'') deep), g for a gap
    // minimum g > 0. A central difference of step h errs by about h^2 |G'''| + eps / h, the map
    // accurate to eps (1e-12 at the default tolerances): h = 1e-6 max(1, |p|) away from
    // grazing, a thousandth of that scale near it.
    double scale = std::numeric_limits<double>::infinity();
    for (const auto& i : centre.impacts) scale = std::min(scale, i.velocity * i.velocity);
    for (const auto& g : centre.gap_minima)
        if (g.gap > 0.0) scale = std::min(scale, g.gap);
    const double size = std::max(1.0, std::abs(p));
    const double h = std::max(std::min(1e-6 * size, 1e-3 * scale), 1e-11 * size);
    Eigen::VectorXd up = u, dn = u;
    up[K + j] += h;
    dn[K + j] -= h;
    const orbit_map_value a = map(up, false);
    const orbit_map_value b = map(dn, false);
    // One-sided where one side fails (the end of the parameter's valid range, an orbit beyond
    // a surface) or makes other impacts (the step crosses a point where the map is not smooth,
    // such as an impact passing through the section).
    const bool a_ok = same_impacts(a, centre), b_ok = same_impacts(b, centre);
    if (a_ok && b_ok) return (a.residual - b.residual) / (2.0 * h);
    if (a_ok && centre.ok()) return (a.residual - centre.residual) / h;
    if (b_ok && centre.ok()) return (centre.residual - b.residual) / h;
    if (a.ok() && b.ok()) return (a.residual - b.residual) / (2.0 * h);
    return Eigen::VectorXd::Constant(K, std::numeric_limits<double>::quiet_NaN());
}

arc_eval orbit_system::operator()(const Eigen::VectorXd& u, bool jacobian) const
{
    arc_eval e;
    e.orbit = map(u, jacobian);
    e.status = e.orbit.status;
    if (!e.ok()) return e;
    e.F = e.orbit.residual;
    if (!jacobian) return e;
    const int K = chart_size();
    e.J.resize(K, K + parameter_count());
    e.J.leftCols(K) = e.orbit.residual_jacobian;
    for (int j = 0; j < parameter_count(); ++j) e.J.col(K + j) = parameter_derivative(u, j, e.orbit);
    if (!e.J.allFinite()) e.status = outcome::non_finite;
    return e;
}

orbit_map_value forced_system::map(const Eigen::VectorXd& u) const
{
    const int K = m_orbits.chart_size();
    return m_orbits.map(u.head(K + 1), true, m_surface, u[K + 1]);
}

arc_eval forced_system::operator()(const Eigen::VectorXd& u, bool jacobian) const
{
    const int K = m_orbits.chart_size();
    arc_eval e;
    e.orbit = map(u);
    e.status = e.orbit.status;
    if (!e.ok()) return e;
    e.F.resize(K + 1);
    e.F << e.orbit.residual, e.orbit.forced_gap;
    if (!jacobian) return e;
    // The parameter's column by a central difference: the forced family is smooth. One-sided
    // where one side fails or makes other impacts: next to where the forced impact meets the
    // section, a step in the parameter can move the section's return before the forced time,
    // or bring another impact in before it.
    const double h = 1e-6 * std::max(1.0, std::abs(u[K]));
    Eigen::VectorXd up = u, dn = u;
    up[K] += h;
    dn[K] -= h;
    const orbit_map_value a = map(up), b = map(dn);
    const bool a_ok = same_impacts(a, e.orbit), b_ok = same_impacts(b, e.orbit);
    if (!a_ok && !b_ok) {
        e.status = a.ok() ? outcome::not_converged : a.status;
        return e;
    }
    const orbit_map_value& hi = a_ok ? a : e.orbit;
    const orbit_map_value& lo = b_ok ? b : e.orbit;
    const double width = (a_ok ? h : 0.0) + (b_ok ? h : 0.0);
    e.J.resize(K + 1, K + 2);
    e.J.topLeftCorner(K, K) = e.orbit.residual_jacobian;
    e.J.block(0, K, K, 1) = (hi.residual - lo.residual) / width;
    e.J.block(0, K + 1, K, 1) = e.orbit.residual_time_derivative;
    e.J.block(K, 0, 1, K) = e.orbit.forced_gap_gradient.transpose();
    e.J(K, K) = (hi.forced_gap - lo.forced_gap) / width;
    e.J(K, K + 1) = e.orbit.forced_gap_rate;
    if (!e.J.allFinite()) e.status = outcome::non_finite;
    return e;
}

bool stable_multipliers(const std::vector<std::complex<double>>& section_multipliers)
{
    for (const auto& m : section_multipliers)
        if (!(std::abs(m) < 1.0)) return false;
    return true;
}

grazing_window window_around(const orbit_map_value& o, int i, double t)
{
    double gap = o.period;
    for (const auto& im : o.impacts)
        if (std::abs(im.t - t) > 1e-9 * std::max(1.0, o.period)) gap = std::min(gap, std::abs(im.t - t));
    // Impacts of the next period seen from the start, and of the last seen from the end.
    for (const auto& im : o.impacts) gap = std::min(gap, std::abs(im.t + o.period - t));
    for (const auto& im : o.impacts) gap = std::min(gap, std::abs(t + o.period - im.t));
    const double w = 0.25 * gap;
    return {i, t - w, t + w};
}

std::optional<gap_minimum_record> grazing_minimum(const orbit_map_value& o, const grazing_window& w)
{
    std::optional<gap_minimum_record> best;
    for (const auto& m : o.gap_minima)
        if (m.surface == w.surface && m.t >= w.from && m.t <= w.until && (!best || m.gap < best->gap)) best = m;
    return best;
}

std::optional<double> nearest_switch_extremum(const orbit_map_value& o, int k)
{
    std::optional<double> best;
    for (const auto& e : o.switch_extrema)
        if (e.k == k && (!best || std::abs(e.h) < std::abs(*best))) best = e.h;
    return best;
}

std::optional<double> grazing_test(const orbit_map_value& o, const grazing_window& w)
{
    const auto m = grazing_minimum(o, w);
    if (!m) return std::nullopt;
    return m->gap;
}

continuation_point orbit_system::to_point(const arc_point& p) const
{
    const int K = chart_size();
    const int S = m_base.surface_count();
    const orbit_map_value& o = p.at.orbit;
    continuation_point c;
    c.parameter = p.u[K];
    c.state = o.x;
    c.section_points = state_series(m_base.dim());
    c.section_points.push_back(0.0, o.x);
    for (std::size_t i = 0; i + 1 < o.crossings.size(); ++i) c.section_points.push_back(0.0, o.crossings[i]);
    c.period = o.period;
    c.impacts_by_surface = o.impacts_by_surface(S);
    c.impact_sequence = o.impact_sequence();
    c.multipliers = o.multipliers;
    c.section_multipliers = o.section_multipliers;
    c.stable = stable_multipliers(o.section_multipliers);
    c.closure = o.residual.size() ? o.residual.cwiseAbs().maxCoeff() : 0.0;
    c.newton_iterations = p.iterations;
    c.arclength = p.s;
    const double inf = std::numeric_limits<double>::infinity();
    c.min_gap.assign(static_cast<std::size_t>(S), inf);
    c.min_impact_velocity.assign(static_cast<std::size_t>(S), inf);
    for (const auto& g : o.gap_minima)
        c.min_gap[static_cast<std::size_t>(g.surface)] = std::min(c.min_gap[static_cast<std::size_t>(g.surface)], g.gap);
    for (const auto& i : o.impacts)
        c.min_impact_velocity[static_cast<std::size_t>(i.surface)] =
            std::min(c.min_impact_velocity[static_cast<std::size_t>(i.surface)], i.velocity);
    return c;
}

}  // namespace vimpact::detail
