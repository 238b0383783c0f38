#include "vimpact/analysis/continuation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <functional>
#include <limits>
#include <optional>

#include <Eigen/Eigenvalues>

#include "arclength.hpp"
#include "orbit_system.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/model/model_phrases.hpp"
#include "jobs/job_loop.hpp"

namespace vimpact {

using detail::arc_point;
using detail::forced_system;
using detail::orbit_system;

long continuation_point::impacts() const
{
    long n = 0;
    for (const long k : impacts_by_surface) n += k;
    return n;
}

double multiplier_test(const std::vector<std::complex<double>>& mu, bifurcation_type type)
{
    std::complex<double> prod = 1.0;
    if (type == bifurcation_type::neimark_sacker) {
        for (std::size_t i = 0; i < mu.size(); ++i)
            for (std::size_t j = i + 1; j < mu.size(); ++j) prod *= mu[i] * mu[j] - 1.0;
    } else {
        const double c = type == bifurcation_type::period_doubling ? -1.0 : 1.0;
        for (const auto& m : mu) prod *= m - c;
    }
    // Conjugate pairs make the product real; what is left is rounding.
    return prod.real();
}

std::string end_reason(const continuation_branch& b, std::string_view parameter)
{
    std::string what;
    switch (b.end) {
        case branch_end::range: return "range";
        case branch_end::closed: return "closed";
        case branch_end::point_limit: what = "max points"; break;
        case branch_end::step_too_small: what = "step too small"; break;
        case branch_end::section_impact: what = "section meets an impact"; break;
        case branch_end::grazing: what = "grazing"; break;
        case branch_end::failed: what = "map failed (" + std::string(to_string(b.failure)) + ")"; break;
        case branch_end::interrupted: what = "interrupted"; break;
    }
    if (b.points.empty()) return what;
    return what + " at " + std::string(parameter) + " = " + format_double(b.points.back().parameter);
}

void validate(const arclength_options& a)
{
    check_options(a);
    if (a.min_step > 0.0 && a.max_step > 0.0 && a.min_step > a.max_step)
        throw input_error("ds_min (" + format_double(a.min_step) + ") exceeds ds_max (" + format_double(a.max_step) + ")");
    validate(a.integration);
}

void validate(const model& m, const continuation_options& o)
{
    if (m.dim() < 2) throw input_error("continuation needs at least 2 state variables");
    const int P = static_cast<int>(m.parameters().size());
    if (o.parameter < 0 || o.parameter >= P)
        throw input_error("continuation parameter index " + std::to_string(o.parameter) + " is out of range [0, " +
                          std::to_string(P - 1) + "]");
    if (!std::isfinite(o.start) || !std::isfinite(o.end))
        throw input_error("the continuation range must be finite");
    if (o.start == o.end)
        throw input_error("the continuation range is empty (start = end = " + format_double(o.start) + ")");
    // The parameter's own valid range: with_parameter names it.
    (void)m.with_parameter(o.parameter, o.start);
    (void)m.with_parameter(o.parameter, o.end);
    check_options(o);
    validate(o.protocol);
    validate(m, o.protocol.section);
    if (o.protocol.section.type != section_choice::kind::crossing)
        throw option_error("section", ": continuation needs a section crossing, not the impacts (" +
                                          sections_it_has(m.info()) + ")");
    if (!o.from_attractor && o.returns < 1)
        throw input_error("a continuation from a given point needs its section returns per period (>= 1)");
    validate(o.arclength);
}

namespace detail {

// A root of test(point(s)) for s in [0, s_b] along a's tangent, by the Illinois method
// (regula falsi that halves the retained end's value), with a bisection whenever the bracket
// has not halved in three steps; until the bracket is below `tol` in arclength (the
// parameter's error is then below `tol` too: |dp/ds| <= 1).
struct located_point {
    bool converged = false;
    arc_point point;
    double bracket = 0.0;
};

using test_function = std::function<std::optional<double>(const arc_point&)>;

std::optional<located_point> locate(const arc_system& f, const arc_point& a, const arc_point& b, const test_function& test,
                                    double tol, const arc_settings& st)
{
    const std::optional<double> fa = test(a), fb = test(b);
    if (!fa || !fb) return std::nullopt;
    double s_lo = 0.0, s_hi = a.t.dot(b.u - a.u);
    double f_lo = *fa, f_hi = *fb;
    if (!(s_hi > 0.0) || f_lo * f_hi > 0.0) return std::nullopt;
    located_point best{false, std::abs(f_lo) < std::abs(f_hi) ? a : b, s_hi};
    int side = 0;  // which end moved last: -1 lo, +1 hi
    double width_before = s_hi;
    for (int it = 0; it < 200 && s_hi - s_lo > tol; ++it) {
        double s = (s_lo * f_hi - s_hi * f_lo) / (f_hi - f_lo);
        if (it % 3 == 2) {
            if (s_hi - s_lo > 0.5 * width_before) s = 0.5 * (s_lo + s_hi);
            width_before = s_hi - s_lo;
        }
        if (!(s > s_lo && s < s_hi)) s = 0.5 * (s_lo + s_hi);
        std::optional<arc_point> p = point_at(f, a, s, st.tolerance, st.newton_iterations);
        std::optional<double> fs = p ? test(*p) : std::nullopt;
        if (!fs) {
            // A trial point the corrector cannot reach, or that has no test value: bisect.
            s = 0.5 * (s_lo + s_hi);
            p = point_at(f, a, s, st.tolerance, st.newton_iterations);
            fs = p ? test(*p) : std::nullopt;
            if (!fs) break;
        }
        best.point = *p;
        if (*fs == 0.0) {
            s_lo = s_hi = s;
            break;
        }
        if ((*fs < 0.0) == (f_lo < 0.0)) {
            s_lo = s;
            f_lo = *fs;
            if (side == -1) f_hi *= 0.5;
            side = -1;
        } else {
            s_hi = s;
            f_hi = *fs;
            if (side == 1) f_lo *= 0.5;
            side = 1;
        }
    }
    best.bracket = s_hi - s_lo;
    best.converged = best.bracket <= tol;
    return best;
}

// The end of a family of orbits: where `test`, positive on it, comes down to 0 and the family
// ceases (past it the corrector fails, or finds orbits that are not `valid` members, or test
// <= 0), so that no sign change can be bracketed. From the family's last point a and an
// earlier one, by the secant method through points of the family: each trial aims a
// hundredth short of the secant's root, so that it usually lands on the family, and a trial
// that misses bounds the search, which then bisects towards it. Converged when the secant
// (or that bound) puts the end within `tol` of the last point in arclength; the parameter is
// then known to tol as well (|dp/ds| <= 1). The located point is the last point on the family.
std::optional<located_point> locate_edge(const arc_system& f, const arc_point& a, const arc_point& before,
                                         const test_function& test, const std::function<bool(const arc_point&)>& valid,
                                         double tol, const arc_settings& st)
{
    const std::optional<double> fa = test(a), fb = test(before);
    if (!fa || !fb || !(*fa > 0.0) || !(*fb > *fa)) return std::nullopt;
    double s0 = 0.0, g0 = *fa;                      // the last point on the family
    double s1 = a.t.dot(before.u - a.u), g1 = *fb;  // one before it
    if (!(s1 < 0.0)) return std::nullopt;
    double miss = std::numeric_limits<double>::infinity();  // the nearest trial off the family
    located_point best{false, a, std::numeric_limits<double>::infinity()};
    for (int it = 0; it < 80; ++it) {
        double remaining = g1 > g0 ? g0 * (s0 - s1) / (g1 - g0) : std::numeric_limits<double>::infinity();
        remaining = std::min(remaining, miss - s0);
        best.bracket = remaining;
        if (remaining <= tol) {
            best.converged = true;
            break;
        }
        if (!std::isfinite(remaining)) break;
        double s = s0 + 0.99 * remaining;
        if (s >= miss || remaining == miss - s0) s = s0 + 0.5 * (miss - s0);
        std::optional<arc_point> p = point_at(f, a, s, st.tolerance, st.newton_iterations);
        const std::optional<double> g = p && valid(*p) ? test(*p) : std::nullopt;
        if (g && *g > 0.0 && *g < g0) {
            s1 = s0;
            g1 = g0;
            s0 = s;
            g0 = *g;
            best.point = std::move(*p);
        } else {
            miss = s;
        }
    }
    return best;
}

// The surfaces whose impact count differs between two orbits; the first such one.
int changed_surface(const continuation_point& a, const continuation_point& b)
{
    for (std::size_t i = 0; i < a.impacts_by_surface.size(); ++i)
        if (a.impacts_by_surface[i] != b.impacts_by_surface[i]) return static_cast<int>(i);
    return -1;
}

// What a branch job returns: the branch, its bifurcations (branch indices local: 0), and
// what switching at each period doubling needs.
struct switch_seed {
    int bifurcation = -1;   // local index
    Eigen::VectorXd u;      // the bifurcation point
    Eigen::VectorXd v;      // eigenvector of DP for -1 (chart coordinates)
    orbit_map_value orbit;  // the orbit there
};

struct branch_record {
    outcome status = outcome::ok;
    std::string label;
    bool has_branch = false;
    continuation_branch branch;
    std::vector<bifurcation> bifurcations;
    std::vector<switch_seed> seeds;
    long tangent_maps = 0, plain_maps = 0;
};

// A switched branch to compute: the bifurcation point, the direction and the parent's system.
struct leg_job {
    int parent = -1, origin = -1;
    int returns = 1;       // of the new branch
    int chart = 0;
    Eigen::VectorXd guess;
    switch_seed seed;
};

class branch_runner {
public:
    branch_runner(const model& m, const continuation_options& o) : m_model(m), m_opt(o)
    {
        const double lo = std::min(o.start, o.end), hi = std::max(o.start, o.end);
        m_range = hi - lo;
        m_bounds = {arc_bound{m.dim() - 1, lo, hi}};
        m_settings = settings_of(o.arclength, m_range, m_bounds, o.cancel);
    }

    [[nodiscard]] orbit_map_request request(int returns, int chart, const Eigen::VectorXd& guess) const
    {
        orbit_map_request r;
        r.section = m_opt.protocol.section.index;
        r.returns = returns;
        r.chart_coordinate = chart;
        r.guess = guess;
        r.integration = m_opt.arclength.integration;
        r.cancel = m_opt.cancel;
        return r;
    }

    // The first branch from an initial state.
    branch_record from_start(const Eigen::VectorXd& x0) const
    {
        branch_record rec;
        const model m0 = m_model.with_parameter(m_opt.parameter, m_opt.start);
        Eigen::VectorXd xg = x0;
        int returns = m_opt.returns;
        if (m_opt.from_attractor) {
            protocol_options po = m_opt.protocol;
            if (!po.flow.cancel) po.flow.cancel = m_opt.cancel;
            const simulation run = simulate(m0, x0, po);
            if (run.status != outcome::ok || run.points.empty()) {
                rec.status = run.status == outcome::ok ? outcome::aperiodic : run.status;
                rec.label = std::string(to_string(rec.status));
                return rec;
            }
            const auto distance = [&](int i, int j) {
                return state_distance(m0.info(), run.points.x(static_cast<std::size_t>(i)),
                                      run.points.x(static_cast<std::size_t>(j)));
            };
            const int period = smallest_period(static_cast<int>(run.points.size()), m_opt.period_tolerance, distance);
            rec.label = !run.impacting ? "P0" : period > 0 ? "P" + std::to_string(period) : "aperiodic";
            if (period <= 0) {
                rec.status = outcome::aperiodic;
                return rec;
            }
            if (returns == 0) returns = period;
            xg = run.points.x(0);
        }
        const int section = m_opt.protocol.section.index;
        const int chart = default_chart_coordinate(m0, section, xg);
        const orbit_system sys(m_model, {m_opt.parameter}, request(returns, chart, xg));
        const int K = sys.chart_size();
        Eigen::VectorXd u(K + 1);
        u << chart_of(xg, chart), m_opt.start;
        Eigen::VectorXd e = Eigen::VectorXd::Zero(K + 1);
        e[K] = 1.0;
        outcome why = outcome::ok;
        std::optional<arc_point> first =
            correct(sys.as_function(), u, e, m_opt.arclength.tolerance, 2 * m_opt.arclength.newton_iterations, &why);
        if (!first) {
            rec.status = why == outcome::ok ? outcome::not_converged : why;
            count(rec, sys);
            return rec;
        }
        set_tangent(*first, e * (m_opt.end > m_opt.start ? 1.0 : -1.0));
        follow(sys, std::move(*first), rec);
        rec.branch.returns = returns;
        rec.branch.chart_coordinate = chart;
        return rec;
    }

    // The doubled branch at a period doubling, from the bifurcation point along +v.
    branch_record from_switch(const leg_job& job) const
    {
        branch_record rec;
        const orbit_system sys(m_model, {m_opt.parameter}, request(job.returns, job.chart, job.guess));
        const int K = sys.chart_size();
        Eigen::VectorXd d = Eigen::VectorXd::Zero(K + 1);
        d.head(K) = job.seed.v.normalized();
        const double scale = 1.0 + job.seed.u.head(K).cwiseAbs().maxCoeff();
        std::optional<arc_point> first;
        for (const double eps : {1e-3, 3e-3, 3e-4, 1e-2}) {
            first = correct(sys.as_function(), job.seed.u + eps * scale * d, d, m_opt.arclength.tolerance,
                            2 * m_opt.arclength.newton_iterations);
            // Not the old orbit taken twice round: its half-way return is another point.
            if (first && half_way_distance(first->at.orbit, job.returns) > 1e-3 * eps * scale) break;
            first.reset();
        }
        if (!first) {
            rec.status = outcome::not_converged;
            count(rec, sys);
            return rec;
        }
        set_tangent(*first, d);
        // The bifurcation point itself starts the branch: the old orbit taken twice round, where
        // the new branch meets it.
        // (Taken as it is: at the branch point Newton's matrix is singular.)
        std::optional<arc_point> start = correct(sys.as_function(), job.seed.u, d, m_opt.arclength.tolerance, 0);
        if (start) {
            start->t = d;
            first->s = (first->u - start->u).norm();
        }
        follow(sys, std::move(*first), rec);
        if (start) rec.branch.points.insert(rec.branch.points.begin(), sys.to_point(*start));
        if (start)
            for (auto& b : rec.bifurcations) ++b.after_point;
        rec.branch.returns = job.returns;
        rec.branch.chart_coordinate = job.chart;
        rec.branch.parent = job.parent;
        rec.branch.origin = job.origin;
        return rec;
    }

private:
    // Two orbits of the same returns are the same (to `tol` of their size) from any of their
    // section points: the one started from a shifted point of the other.
    static bool same_orbit(const orbit_map_value& a, const orbit_map_value& b, double tol)
    {
        const std::size_t k = a.crossings.size();
        if (k == 0 || k != b.crossings.size()) return false;
        const double scale = tol * (1.0 + a.x.cwiseAbs().maxCoeff());
        // Section point i of an orbit: x for i = 0, else its i-th return.
        const auto at = [k](const orbit_map_value& o, std::size_t i) -> const Eigen::VectorXd& {
            return i % k == 0 ? o.x : o.crossings[i % k - 1];
        };
        for (std::size_t shift = 0; shift < k; ++shift) {
            bool all = true;
            for (std::size_t i = 0; i < k && all; ++i) all = (at(a, i + shift) - at(b, i)).cwiseAbs().maxCoeff() <= scale;
            if (all) return true;
        }
        return false;
    }

    // Where a branch of P^2j turns next to an orbit of P^j (its half-way return within 1e-2 of
    // its first point): that orbit's period doubling, located on the P^j family by its test
    // function between two points on either side.
    std::optional<bifurcation> half_period_doubling(const orbit_system& sys, const arc_point& near) const
    {
        const int k = sys.returns();
        const int K = sys.chart_size();
        const double scale = 1.0 + near.at.orbit.x.cwiseAbs().maxCoeff();
        if (k % 2 != 0 || half_way_distance(near.at.orbit, k) > 1e-2 * scale) return std::nullopt;
        const orbit_system half = sys.with_returns(k / 2);
        const arc_system fh = half.as_function();
        Eigen::VectorXd hold = Eigen::VectorXd::Zero(K + 1);
        hold[K] = 1.0;
        std::optional<arc_point> mid = correct(fh, near.u, hold, m_settings.tolerance, 2 * m_settings.newton_iterations);
        if (!mid || minimal_returns(mid->at.orbit, k / 2) != k / 2) return std::nullopt;
        set_tangent(*mid, hold);
        const auto pd = [](const arc_point& p) -> std::optional<double> {
            return multiplier_test(p.at.orbit.section_multipliers, bifurcation_type::period_doubling);
        };
        for (const double ds : {1e-4 * m_range, 1e-3 * m_range, 1e-2 * m_range}) {
            const auto a = point_at(fh, *mid, -ds, m_settings.tolerance, m_settings.newton_iterations);
            const auto b = point_at(fh, *mid, ds, m_settings.tolerance, m_settings.newton_iterations);
            if (!a || !b) continue;
            const auto fa = pd(*a), fb = pd(*b);
            if (!fa || !fb || !(*fa * *fb < 0.0)) continue;
            const auto loc = locate(fh, *a, *b, pd, m_opt.locate_tolerance, m_settings);
            if (!loc) return std::nullopt;
            bifurcation bf;
            bf.type = bifurcation_type::period_doubling;
            bf.point = half.to_point(loc->point);
            if (!has_critical_multiplier(bf.point.section_multipliers, bf.type)) return std::nullopt;
            bf.parameter = bf.point.parameter;
            bf.located = loc->converged;
            bf.bracket = loc->bracket;
            return bf;
        }
        return std::nullopt;
    }

    // The smallest d dividing k with the orbit's d-th return on its first point (to 1e-7 of
    // its size): k for a genuine period-k orbit.
    static int minimal_returns(const orbit_map_value& o, int k)
    {
        const double scale = 1.0 + o.x.cwiseAbs().maxCoeff();
        for (int d = 1; d < k; ++d)
            if (k % d == 0 && static_cast<std::size_t>(d) <= o.crossings.size() &&
                (o.crossings[static_cast<std::size_t>(d - 1)] - o.x).cwiseAbs().maxCoeff() <= 1e-7 * scale)
                return d;
        return k;
    }

    static double half_way_distance(const orbit_map_value& o, int returns)
    {
        const auto h = static_cast<std::size_t>(returns / 2 - 1);
        if (returns < 2 || o.crossings.size() <= h) return 0.0;
        return (o.crossings[h] - o.x).cwiseAbs().maxCoeff();
    }

    static void count(branch_record& rec, const orbit_system& sys)
    {
        rec.tangent_maps += sys.tangent_maps();
        rec.plain_maps += sys.plain_maps();
    }

    void follow(const orbit_system& sys, arc_point first, branch_record& rec) const
    {
        const int K = sys.chart_size();
        const arc_system f = sys.as_function();
        std::deque<orbit_system> helpers;  // alive while their functions are used; counted at the end
        std::vector<arc_point> points;     // of the pieces before the current one
        long piece_accepted = 0;           // steps accepted in the current piece
        std::optional<grazing_turn> turn;  // where a piece ended at a grazing
        auto on_step = [&](const arc_point& a, const arc_point& b) {
            const int after = static_cast<int>(static_cast<long>(points.size()) + piece_accepted);
            if (m_opt.cancel && m_opt.cancel->load()) return step_verdict::accept;
            const continuation_point pa = sys.to_point(a), pb = sys.to_point(b);
            if (pa.impact_sequence != pb.impact_sequence) {
                // A grazing lies between a and b: the branch ends at it and goes on, if it can,
                // on the family the grazing turns it onto. A step that merely jumped to another
                // family (no grazing found from a) is retried shorter.
                const int i = changed_surface(pa, pb);
                if (i < 0) return step_verdict::reject;
                const bool impacting = pa.impacts_by_surface[static_cast<std::size_t>(i)] >
                                       pb.impacts_by_surface[static_cast<std::size_t>(i)];
                grazing_turn t = turn_at_grazing(sys, a, i, impacting, after, rec, helpers);
                if (!t.located) return step_verdict::reject;
                turn = std::move(t);
                return step_verdict::stop_before;
            }
            // A branch of P^2j whose orbit turns into one of P^j is the old branch taken twice
            // round (it meets the new one at a period doubling): not this branch.
            if (minimal_returns(b.at.orbit, sys.returns()) < minimal_returns(a.at.orbit, sys.returns()))
                return step_verdict::reject;
            ++piece_accepted;
            if (!m_opt.detect) return step_verdict::accept;
            const auto fold = [K](const arc_point& p) -> std::optional<double> { return p.t[K]; };
            const auto pd = [](const arc_point& p) -> std::optional<double> {
                return multiplier_test(p.at.orbit.section_multipliers, bifurcation_type::period_doubling);
            };
            const auto ns = [](const arc_point& p) -> std::optional<double> {
                return multiplier_test(p.at.orbit.section_multipliers, bifurcation_type::neimark_sacker);
            };
            const std::pair<bifurcation_type, test_function> tests[] = {
                {bifurcation_type::fold, fold}, {bifurcation_type::period_doubling, pd}, {bifurcation_type::neimark_sacker, ns}};
            for (const auto& [type, test] : tests) {
                const std::optional<double> fa = test(a), fb = test(b);
                if (!fa || !fb || !(*fa * *fb < 0.0)) continue;
                const auto loc = locate(f, a, b, test, m_opt.locate_tolerance, m_settings);
                if (!loc) continue;
                const continuation_point c = sys.to_point(loc->point);
                // A test function also changes sign where a multiplier passes through infinity,
                // or the tangent turns at a non-smooth point (a grazing): only a multiplier at
                // +1, -1 or a complex pair on the circle makes the bifurcation.
                if (!has_critical_multiplier(c.section_multipliers, type)) continue;
                bifurcation bf;
                bf.type = type;
                bf.after_point = after;
                bf.located = loc->converged;
                bf.parameter = c.parameter;
                bf.bracket = loc->bracket;
                bf.point = c;
                // The turn of a branch of P^2j at an orbit of P^j is that orbit's period
                // doubling (a pitchfork of P^2j), not a fold; it is located on the P^j family,
                // where it is a regular point (the branch itself crosses the doubled orbit
                // there and cannot reach it).
                if (type == bifurcation_type::fold) {
                    if (auto half = half_period_doubling(sys, loc->point)) {
                        bf = std::move(*half);
                        bf.after_point = after;
                        rec.bifurcations.push_back(std::move(bf));
                        continue;
                    }
                }
                // A branch that passes a period doubling twice (on the two legs of a loop of
                // orbits) switches there once.
                const bool seen = std::any_of(rec.seeds.begin(), rec.seeds.end(), [&](const switch_seed& s) {
                    return same_orbit(s.orbit, loc->point.at.orbit, 1e-7);
                });
                if (type == bifurcation_type::period_doubling && !seen)
                    rec.seeds.push_back({static_cast<int>(rec.bifurcations.size()), loc->point.u,
                                         flip_vector(loc->point.at.orbit.residual_jacobian), loc->point.at.orbit});
                rec.bifurcations.push_back(std::move(bf));
            }
            for (int k = 0; k < static_cast<int>(a.at.orbit.crossings_by_switch.size()); ++k)
                if (auto bf = switch_grazing(sys, f, a, b, k)) {
                    bf->after_point = after;
                    rec.bifurcations.push_back(std::move(*bf));
                }
            return step_verdict::accept;
        };
        detail::arc_curve curve = follow_curve(f, std::move(first), m_settings, on_step);
        std::vector<orbit_map_value> grazings;  // the grazing orbits the branch met
        for (;;) {
            for (auto& p : curve.points) points.push_back(std::move(p));
            piece_accepted = 0;
            rec.branch.end = curve.end;
            rec.branch.failure = curve.failure;
            if (!turn && (curve.end == branch_end::step_too_small || curve.end == branch_end::failed)) {
                // Stalled: near a grazing the corrector's reach shrinks like the square of the
                // grazing impact's velocity, and the branch cannot be stepped past it; where the
                // section point meets an impact it cannot step at all.
                turn = through_grazing(sys, points, rec, helpers);
                if (!turn->located) turn = past_stall(sys, points, rec);
            }
            if (!turn || !turn->located) break;
            // The grazing orbit (or the one whose section point meets an impact) ends this piece;
            // it starts the next one if the branch goes on. One met before (from either of the
            // orbit's points on the section): the branch has gone round a loop of orbits.
            const bool repeated = std::any_of(grazings.begin(), grazings.end(), [&](const orbit_map_value& o) {
                return same_orbit(o, turn->point.at.orbit, 1e-7);
            });
            grazings.push_back(turn->point.at.orbit);
            rec.branch.end = repeated ? branch_end::closed : turn->end;
            rec.branch.failure = outcome::ok;
            const long extra = static_cast<long>(turn->extra.size());
            if (!turn->next || repeated || static_cast<long>(points.size()) + 1 + extra >= m_settings.max_points) {
                if (turn->next && !repeated) rec.branch.end = branch_end::point_limit;
                points.push_back(std::move(turn->point));
                break;
            }
            // The orbit itself, where the next piece does not start from it, and from its other
            // section point.
            if (turn->next->u != turn->point.u) points.push_back(turn->point);
            for (auto& e : turn->extra) points.push_back(std::move(e));
            const arc_point& from = extra > 0 ? points.back() : turn->point;
            arc_settings rest = m_settings;
            rest.max_points = m_settings.max_points - static_cast<long>(points.size());
            // Off a grazing onto the family with the new impact, the corrector's reach grows with
            // the distance from it: the first step is no longer than that distance.
            if (turn->next->u != from.u)
                rest.step = std::clamp((turn->next->u - from.u).norm(), m_settings.min_step, m_settings.step);
            arc_point next = std::move(*turn->next);
            turn.reset();
            curve = follow_curve(f, std::move(next), rest, on_step);
        }
        rec.has_branch = true;
        for (const auto& p : points) rec.branch.points.push_back(sys.to_point(p));
        std::sort(rec.bifurcations.begin(), rec.bifurcations.end(),
                  [](const bifurcation& x, const bifurcation& y) { return x.after_point < y.after_point; });
        count(rec, sys);
        for (const auto& h : helpers) count(rec, h);
    }

    // The impact of an orbit on surface i with the smallest velocity (its time), if any.
    static std::optional<double> softest_impact(const orbit_map_value& o, int i)
    {
        std::optional<double> t;
        double v = std::numeric_limits<double>::infinity();
        for (const auto& im : o.impacts)
            if (im.surface == i && im.velocity < v) {
                v = im.velocity;
                t = im.t;
            }
        return t;
    }

    // The gap minimum of an orbit on surface i closest to 0 (its time), if any.
    static std::optional<double> closest_minimum(const orbit_map_value& o, int i)
    {
        std::optional<double> t;
        double g = std::numeric_limits<double>::infinity();
        for (const auto& m : o.gap_minima)
            if (m.surface == i && m.gap < g) {
                g = m.gap;
                t = m.t;
            }
        return t;
    }

    // The grazing of switch k between consecutive points a and b whose orbits cross it a
    // different number of times, located on the branch; none when the test does not change
    // sign there.
    std::optional<bifurcation> switch_grazing(const orbit_system& sys, const arc_system& f, const arc_point& a,
                                              const arc_point& b, int k) const
    {
        const auto& ca = a.at.orbit.crossings_by_switch;
        const auto& cb = b.at.orbit.crossings_by_switch;
        const auto kk = static_cast<std::size_t>(k);
        if (kk >= cb.size() || ca[kk] == cb[kk]) return std::nullopt;
        const test_function test = [k](const arc_point& p) { return nearest_switch_extremum(p.at.orbit, k); };
        const std::optional<double> fa = test(a), fb = test(b);
        if (!fa || !fb || !(*fa * *fb < 0.0)) return std::nullopt;
        const auto loc = locate(f, a, b, test, m_opt.locate_tolerance, m_settings);
        if (!loc) return std::nullopt;
        bifurcation bf;
        bf.type = bifurcation_type::grazing;
        bf.located = loc->converged;
        bf.point = sys.to_point(loc->point);
        bf.parameter = bf.point.parameter;
        bf.bracket = loc->bracket;
        bf.switch_surface = k;
        bf.crossings_before = ca[kk];
        bf.crossings_after = cb[kk];
        double nearest = std::numeric_limits<double>::infinity();
        for (const auto& e : loc->point.at.orbit.switch_extrema)
            if (e.k == k && std::abs(e.h) < nearest) {
                nearest = std::abs(e.h);
                bf.time = e.t;
            }
        bf.sequence_before = bf.sequence_after = bf.point.impact_sequence;
        return bf;
    }

    // Where a branch meets a point it cannot step across: a grazing, or its section point
    // meeting an impact.
    struct grazing_turn {
        bool located = false;           // the point was located (a grazing also recorded)
        arc_point point;                // the orbit there
        std::vector<arc_point> extra;   // the same orbit from another section point (section_impact)
        std::optional<arc_point> next;  // where the branch goes on
        branch_end end = branch_end::grazing;  // the branch's end there when it does not go on
    };

    // A branch that stalled where one grazing does not explain it: its section point meeting an
    // impact, or several grazings at once.
    grazing_turn past_stall(const orbit_system& sys, const std::vector<arc_point>& points, branch_record& rec) const
    {
        if (points.size() < 2) return {};
        grazing_turn t = through_section_impact(sys, points, rec);
        if (t.located) return t;
        return at_grazings(sys, points, rec);
    }

    // The impact of an orbit nearest to its section point in time, from either end of the
    // period, if nearer than `fraction` of the period: its index, and whether it comes just
    // after the section point (else just before the return to it).
    struct impact_near_section {
        std::size_t index = 0;
        bool after_start = true;
    };

    static std::optional<impact_near_section> impact_at_section(const orbit_map_value& o, double fraction)
    {
        std::optional<impact_near_section> best;
        double closest = fraction * o.period;
        for (std::size_t k = 0; k < o.impacts.size(); ++k)
            for (const bool after : {true, false}) {
                const double d = after ? o.impacts[k].t : o.period - o.impacts[k].t;
                if (d >= 0.0 && d < closest) {
                    closest = d;
                    best = impact_near_section{k, after};
                }
            }
        return best;
    }

    // A branch stalled where its section point meets an impact (the orbit hits a surface at the
    // section). The orbits are smooth through it, but their point on the section jumps from the
    // state before the impact to the state after it (or back), and the corrector cannot step
    // across. The last orbit E before it is located along the branch, where the surface's gap at
    // the section point comes down to 0 (locate_edge); the other state of E at the section (the
    // reset of its section point, or the state before the impact that precedes the return,
    // from a run with the surface absent there) is E's section point on the far side. From it
    // the family is followed with that impact forced (forced_system, smooth in the impact's
    // time) away from the section until the section map closes its orbits again, and the
    // branch goes on from there. Located but with no way on (a reset that moves the state off
    // the section, a forced family that leads nowhere), the branch ends at E as section_impact.
    grazing_turn through_section_impact(const orbit_system& sys, const std::vector<arc_point>& points,
                                        branch_record& rec) const
    {
        grazing_turn turn;
        const arc_point& L = points.back();
        const std::optional<impact_near_section> near = impact_at_section(L.at.orbit, 1e-3);
        if (!near) return turn;
        const int surface = L.at.orbit.impacts[near->index].surface;
        const bool after_start = near->after_start;
        const int K = sys.chart_size();
        const int N = sys.base().dim();
        const vimpact_model_table& tb = sys.base().table();
        const auto gap_at_section = [&](const arc_point& p) -> std::optional<double> {
            const model mp = sys.model_at(p.u);
            return tb.gap(mp.context(), surface, p.at.orbit.x.data());
        };
        const std::vector<int> sequence = L.at.orbit.impact_sequence();
        const auto same_family = [&](const arc_point& p) {
            const auto n = impact_at_section(p.at.orbit, 1e-3);
            return n && n->after_start == after_start && p.at.orbit.impact_sequence() == sequence;
        };
        const std::optional<located_point> loc = locate_edge(sys.as_function(), L, points[points.size() - 2],
                                                             gap_at_section, same_family, m_opt.locate_tolerance, m_settings);
        if (!loc) return turn;
        turn.located = true;
        turn.end = branch_end::section_impact;
        turn.point = loc->point;
        turn.point.s = L.s + (turn.point.u - L.u).norm();
        const orbit_map_value& oe = turn.point.at.orbit;
        const std::optional<impact_near_section> ev = impact_at_section(oe, 1e-3);
        if (!ev) return turn;
        const double T = oe.period;
        // The forced impact's window: a quarter of the time to the orbit's other impacts.
        double spacing = T;
        for (std::size_t k = 0; k < oe.impacts.size(); ++k)
            if (k != ev->index) spacing = std::min({spacing, oe.impacts[k].t, T - oe.impacts[k].t});
        const auto window_at = [&](double t) { return grazing_window{surface, t - 0.25 * spacing, t + 0.25 * spacing}; };
        // On the far side the impact comes just before the return (after_start) or just after
        // the start.
        const grazing_window w = window_at(after_start ? T : 0.0);
        const model me = sys.model_at(turn.point.u);
        Eigen::VectorXd xb(N);
        if (after_start) {
            tb.reset(me.context(), surface, oe.x.data(), xb.data());
        } else {
            const orbit_map_value through = sys.with_absent(window_at(T)).map(turn.point.u, false);
            if (!through.ok()) return turn;
            xb = through.x_end;
        }
        // Phases as E's own (the run's end carries the period it ran).
        for (int j = 0; j < N; ++j) {
            const double period = sys.base().info().state[static_cast<std::size_t>(j)].period;
            if (period > 0.0) xb[j] -= period * std::round((xb[j] - oe.x[j]) / period);
        }
        // The other state is a section point only if the reset leaves the section where it was
        // and the flow crosses it the section's way there.
        const int k = sys.request().section;
        Eigen::VectorXd grad(N), field(N);
        tb.section_gradient(me.context(), k, xb.data(), grad.data());
        tb.rhs(me.context(), xb.data(), field.data());
        const double rate = grad.dot(field);
        const crossing way = sys.base().info().sections[static_cast<std::size_t>(k)].direction;
        const bool crosses = way == crossing::up ? rate > 0.0 : way == crossing::down ? rate < 0.0 : rate != 0.0;
        const double s_b = tb.section(me.context(), k, xb.data());
        if (!crosses || !(std::abs(s_b) <= 1e-9 * (1.0 + grad.cwiseAbs().maxCoeff() * xb.cwiseAbs().maxCoeff())))
            return turn;
        // Just off E on the far side, the parameter a little beyond E's (on in the branch's
        // direction) and the forced impact and the section point free, from E's other state with
        // the impact just inside the period.
        const forced_system forced(sys, w);
        const arc_system ff = forced.as_function();
        const double onward = L.t[K] > 0.0 ? 1.0 : -1.0;
        Eigen::VectorXd hold_p = Eigen::VectorXd::Zero(K + 2);
        hold_p[K] = 1.0;
        std::optional<arc_point> first;
        for (double delta = 1e-6 * m_range; !first && delta <= 1e-3 * m_range; delta *= 10.0) {
            Eigen::VectorXd U(K + 2);
            U << chart_of(xb, sys.request().chart_coordinate), turn.point.u[K] + onward * delta,
                after_start ? T * (1.0 - 1e-9) : T * 1e-9;
            first = correct(ff, U, hold_p, m_settings.tolerance, 2 * m_settings.newton_iterations);
        }
        std::optional<arc_point> found;
        if (first) {
            set_tangent(*first, onward * hold_p);
            found = off_forced_family(sys, ff, *first);
        }
        count(rec, forced.orbits());
        if (!found) return turn;
        // E itself from its other section point: the same orbit, its impact on the section
        // moved from one end of the period to the other.
        arc_point other = turn.point;
        orbit_map_value& oo = other.at.orbit;
        oo.x = xb;
        oo.x_end = xb;
        if (!oo.crossings.empty()) oo.crossings.back() = xb;
        impact_record moved = oo.impacts[ev->index];
        oo.impacts.erase(oo.impacts.begin() + static_cast<std::ptrdiff_t>(ev->index));
        if (after_start) {
            moved.t = T;
            oo.impacts.push_back(moved);
        } else {
            moved.t = 0.0;
            oo.impacts.insert(oo.impacts.begin(), moved);
        }
        other.u.head(K) = chart_of(xb, sys.request().chart_coordinate);
        found->s = other.s + (found->u - other.u).norm();
        turn.extra.push_back(std::move(other));
        turn.next = std::move(found);
        return turn;
    }

    // A branch stalled next to grazings that turn_at_grazing does not take: several surfaces at
    // once (a symmetric orbit touching both stops together), where the family without the new
    // impacts cannot be followed with one surface absent. Where the approaches' measures come
    // down to 0 along the branch is located (locate_edge on the smallest), each approach that
    // reaches 0 there is recorded as a grazing of its surface, and the branch ends there.
    grazing_turn at_grazings(const orbit_system& sys, const std::vector<arc_point>& points, branch_record& rec) const
    {
        grazing_turn turn;
        const std::vector<approach> near = approaches(sys, points);
        if (near.empty()) return turn;
        const arc_point& L = points.back();
        const std::vector<int> sequence = L.at.orbit.impact_sequence();
        const auto closest = [&](const arc_point& p) -> std::optional<double> {
            std::optional<double> g;
            for (const auto& a : near)
                if (const auto m = approach_measure(p.at.orbit, a)) g = g ? std::min(*g, m->first) : m->first;
            return g;
        };
        const auto same = [&](const arc_point& p) { return p.at.orbit.impact_sequence() == sequence; };
        const std::optional<located_point> loc = locate_edge(sys.as_function(), L, points[points.size() - 2], closest,
                                                             same, m_opt.locate_tolerance, m_settings);
        if (!loc) return turn;
        turn.point = loc->point;
        turn.point.s = L.s + (turn.point.u - L.u).norm();
        const continuation_point at = sys.to_point(turn.point);
        // What an orbit just past the grazings does with the surfaces present.
        const double past = std::max(10.0 * loc->bracket, 1e-7 * m_range);
        const orbit_map_value beyond = sys.map(turn.point.u + past * turn.point.t, false);
        for (const auto& a : near) {
            const std::optional<double> when = grazed(turn.point.at.orbit, a);
            if (!when) continue;
            bifurcation bf;
            bf.type = bifurcation_type::grazing;
            bf.after_point = static_cast<int>(points.size()) - 1;
            bf.located = loc->converged;
            bf.bracket = loc->bracket;
            bf.point = at;
            bf.parameter = at.parameter;
            bf.surface = a.surface;
            bf.time = *when;
            bf.sequence_before = sequence;
            bf.sequence_after = beyond.ok() ? beyond.impact_sequence() : sequence;
            rec.bifurcations.push_back(std::move(bf));
            turn.located = true;
        }
        return turn;
    }

    // A branch that stalls close to grazing a surface: an impact's velocity goes to 0, or a gap
    // minimum goes to 0, while the corrector cannot step past it. The surface and side are
    // those whose approach shrank the most (to below 5 % of its largest on the branch).
    grazing_turn through_grazing(const orbit_system& sys, const std::vector<arc_point>& points, branch_record& rec,
                                 std::deque<orbit_system>& helpers) const
    {
        const std::vector<approach> near = approaches(sys, points);
        if (near.empty()) return {};
        grazing_turn t = turn_at_grazing(sys, points.back(), near.front().surface, near.front().impacting,
                                         static_cast<int>(points.size()) - 1, rec, helpers);
        if (!t.located) return t;
        // Other surfaces grazed by the same orbit (a symmetric orbit touches both stops at
        // once): recorded with it.
        const bifurcation first = rec.bifurcations.back();
        for (std::size_t k = 1; k < near.size(); ++k) {
            const std::optional<double> when = grazed(t.point.at.orbit, near[k]);
            if (near[k].surface == first.surface || !when) continue;
            bifurcation also = first;
            also.surface = near[k].surface;
            also.time = *when;
            rec.bifurcations.push_back(std::move(also));
        }
        return t;
    }

    // A surface a branch approaches: an impact on it softening (impacting) or a gap minimum
    // coming down to it, now below 5 % of the largest it had on the branch (`largest`).
    struct approach {
        int surface = 0;
        bool impacting = false;
        double ratio = 0.0, largest = 0.0;
    };

    // The approaches at the branch's last point, the closest (smallest ratio) first.
    static std::vector<approach> approaches(const orbit_system& sys, const std::vector<arc_point>& points)
    {
        std::vector<approach> out;
        const continuation_point pl = sys.to_point(points.back());
        const int S = sys.base().surface_count();
        for (int i = 0; i < S && i < 64; ++i) {
            const auto k = static_cast<std::size_t>(i);
            for (const bool imp : {true, false}) {
                double largest = 0.0;
                for (const auto& p : points) {
                    const orbit_map_value& o = p.at.orbit;
                    if (imp)
                        for (const auto& im : o.impacts)
                            if (im.surface == i) largest = std::max(largest, im.velocity);
                    if (!imp)
                        for (const auto& g : o.gap_minima)
                            if (g.surface == i) largest = std::max(largest, g.gap);
                }
                const double now = imp ? pl.min_impact_velocity[k] : pl.min_gap[k];
                if (!(largest > 0.0) || !std::isfinite(now) || !(now >= 0.0) || now / largest >= 0.05) continue;
                out.push_back({i, imp, now / largest, largest});
            }
        }
        std::stable_sort(out.begin(), out.end(), [](const approach& a, const approach& b) { return a.ratio < b.ratio; });
        return out;
    }

    // When the orbit o grazes as approach a measures it (its measure below 1e-6 of the largest
    // it had on the branch): the time along o; none when it does not.
    static std::optional<double> grazed(const orbit_map_value& o, const approach& a)
    {
        const auto m = approach_measure(o, a);
        const double scale = a.impacting ? a.largest * a.largest : a.largest;
        if (!m || !(m->first <= 1e-6 * scale)) return std::nullopt;
        return m->second;
    }

    // How close an orbit is to grazing as approach a measures it, a smooth function along the
    // branch that vanishes at the grazing: the squared velocity of its softest impact on the
    // surface (the free flow's penetration times 2 g''), or its smallest gap minimum there;
    // with the time along the orbit where that happens.
    static std::optional<std::pair<double, double>> approach_measure(const orbit_map_value& o, const approach& a)
    {
        std::optional<std::pair<double, double>> best;
        if (a.impacting) {
            for (const auto& im : o.impacts)
                if (im.surface == a.surface && (!best || im.velocity * im.velocity < best->first))
                    best = {im.velocity * im.velocity, im.t};
        } else {
            for (const auto& g : o.gap_minima)
                if (g.surface == a.surface && (!best || g.gap < best->first)) best = {g.gap, g.t};
        }
        return best;
    }

    // The grazing of surface i next to the branch's point L, recorded as a bifurcation after
    // point `after`. With `impacting`, L's softest impact on i is the one that grazes, and the
    // grazing orbit G is found on the family without it; otherwise L's closest gap minimum on i
    // grazes. That family is followed with the surface absent around the grazing (its gap
    // minimum is then smooth through 0) from L to where the minimum is 0. From the impacting
    // side the branch goes on from G along that family, away from the surface (onward when
    // the orbits persist through the grazing, back when the two families meet at a
    // non-smooth fold); from the other side it ends at G.
    grazing_turn turn_at_grazing(const orbit_system& sys, const arc_point& L, int surface, bool impacting, int after,
                                 branch_record& rec, std::deque<orbit_system>& helpers) const
    {
        grazing_turn turn;
        const int K = sys.chart_size();
        const orbit_map_value& ol = L.at.orbit;
        const std::optional<double> tg = impacting ? softest_impact(ol, surface) : closest_minimum(ol, surface);
        if (!tg) return turn;
        const grazing_window w = window_around(ol, surface, *tg);
        helpers.push_back(sys.with_absent(w));
        const arc_system fw = helpers.back().as_function();
        const auto test = [w](const arc_point& p) { return grazing_test(p.at.orbit, w); };
        Eigen::VectorXd e = Eigen::VectorXd::Zero(K + 1);
        e[K] = 1.0;
        // The family without the grazing impact, at L's parameter.
        std::optional<arc_point> F = correct(fw, L.u, e, m_settings.tolerance, 2 * m_settings.newton_iterations);
        if (!F) return turn;
        set_tangent(*F, L.t);
        F->s = L.s;
        const std::optional<double> gF = test(*F);
        if (!gF) return turn;
        // Towards the grazing: the side where the gap minimum goes to 0, probed with a step far
        // shorter than the distance to it (the gap changes at a rate of order 1 along the tangent).
        {
            const double probe_step = std::max(m_settings.min_step, std::min(0.1 * m_settings.step, 1e-3 * std::abs(*gF)));
            const std::optional<arc_point> probe =
                point_at(fw, *F, probe_step, m_settings.tolerance, m_settings.newton_iterations);
            const std::optional<double> gp = probe ? test(*probe) : std::nullopt;
            if (!gp) return turn;
            // Away from 0 on the same side: the other way (a probe that crossed 0 went right).
            if ((*gp > 0.0) == (*gF > 0.0) && std::abs(*gp) > std::abs(*gF)) F->t = -F->t;
        }
        std::optional<arc_point> before, after_g;
        if (*gF == 0.0) {
            before = after_g = *F;
        } else {
            arc_settings march = m_settings;
            march.max_points = 100;
            march.step = std::min(m_settings.step, std::max(march.min_step, std::abs(*gF)));
            march.bounds.clear();
            march.stall_step = 0.0;  // short steps are the point here
            (void)follow_curve(fw, *F, march, [&](const arc_point& a, const arc_point& b) {
                const auto ga = test(a), gb = test(b);
                if (!ga || !gb) return step_verdict::stop_before;
                if ((*ga > 0.0) == (*gb > 0.0)) return step_verdict::accept;
                before = a;
                after_g = b;
                return step_verdict::stop_after;
            });
        }
        if (!before) return turn;
        std::optional<located_point> loc;
        if (before->u == after_g->u) loc = located_point{true, *before, 0.0};
        else loc = locate(fw, *before, *after_g, test, m_opt.locate_tolerance, m_settings);
        if (!loc) return turn;
        bifurcation bf;
        bf.type = bifurcation_type::grazing;
        bf.after_point = after;
        bf.located = loc->converged;
        bf.bracket = loc->bracket;
        bf.point = sys.to_point(loc->point);
        bf.parameter = bf.point.parameter;
        bf.surface = surface;
        if (const auto gm = grazing_minimum(loc->point.at.orbit, w)) bf.time = gm->t;
        bf.sequence_before = sys.to_point(L).impact_sequence;
        // Past G: from the impacting side, the family without the impact (G's own sequence);
        // from the other side, what an orbit just past G does with the surface present (the
        // point of the bracket that crosses the surface, where the new impact appears).
        bf.sequence_after = bf.point.impact_sequence;
        if (!impacting) {
            const arc_point& crossing = *test(*before) > 0.0 ? *after_g : *before;
            const orbit_map_value past = sys.map(crossing.u, false);
            if (past.ok()) bf.sequence_after = past.impact_sequence();
        }
        rec.bifurcations.push_back(std::move(bf));
        turn.located = true;
        arc_point G = loc->point;
        G.s = L.s + (G.u - L.u).norm();
        if (impacting) {
            // On along the family without the impact, away from the surface.
            const arc_point& clear = *test(*before) > 0.0 ? *before : *after_g;
            if ((clear.u - G.u).dot(G.t) < 0.0) G.t = -G.t;
            turn.next = G;
        } else if (const auto gm = grazing_minimum(G.at.orbit, w)) {
            turn.next = onto_impacting_family(sys, w, G, gm->t);
        }
        turn.point = std::move(G);
        return turn;
    }

    // From the grazing orbit G reached from the side without the impact, onto the family with
    // it: that family is followed from G with the impact forced (detail::forced_system, smooth
    // through G) towards impact velocities > 0, until the section map's corrector closes an
    // orbit with the same impacts next to one of its points; the branch goes on from there.
    // None when the forced family leaves the range or no such orbit is found in 40 steps.
    std::optional<arc_point> onto_impacting_family(const orbit_system& sys, const grazing_window& w, const arc_point& G,
                                                   double t_graze) const
    {
        const int K = sys.chart_size();
        const forced_system forced(sys, w);
        const arc_system ff = forced.as_function();
        Eigen::VectorXd U(K + 2);
        U << G.u, t_graze;
        Eigen::VectorXd hold_p = Eigen::VectorXd::Zero(K + 2);
        hold_p[K] = 1.0;
        std::optional<arc_point> first = correct(ff, U, hold_p, m_settings.tolerance, 2 * m_settings.newton_iterations);
        if (!first) return std::nullopt;
        set_tangent(*first, Eigen::VectorXd());
        // The physical way: the gap decreasing at the forced impact (its velocity > 0).
        {
            const std::optional<arc_point> probe =
                point_at(ff, *first, std::max(m_settings.min_step, 0.01 * m_settings.step), m_settings.tolerance,
                         m_settings.newton_iterations);
            if (!probe) return std::nullopt;
            if (probe->at.orbit.forced_gap_rate > 0.0) first->t = -first->t;
        }
        std::optional<arc_point> found = off_forced_family(sys, ff, *first);
        if (found) found->s = G.s + (found->u - G.u).norm();
        return found;
    }

    // Along a family of orbits with a forced impact (ff, a forced_system's function), from its
    // point `first` with its tangent oriented away from where the section map fails, until the
    // section map's corrector closes an orbit with the same impacts next to one of its points:
    // that orbit, with its tangent. None when the forced family leaves the range, its impact
    // turns unphysical (the gap increasing into it) or no such orbit is found in 40 steps.
    std::optional<arc_point> off_forced_family(const orbit_system& sys, const arc_system& ff, const arc_point& first) const
    {
        const int K = sys.chart_size();
        arc_settings st = m_settings;
        st.max_points = 40;
        st.step = std::max(m_settings.min_step, 0.1 * m_settings.step);
        st.stall_step = 0.0;
        st.bounds = {arc_bound{K, m_bounds.front().lo, m_bounds.front().hi}};
        Eigen::VectorXd hold = Eigen::VectorXd::Zero(K + 1);
        hold[K] = 1.0;
        std::optional<arc_point> found;
        const arc_system f = sys.as_function();
        int steps = 0;
        (void)follow_curve(ff, first, st, [&](const arc_point&, const arc_point& b) {
            if (!(b.at.orbit.forced_gap_rate < 0.0)) return step_verdict::stop_before;
            // A few steps off the start first: right next to it the section map's corrector
            // has no reach.
            if (++steps < 3) return step_verdict::accept;
            std::optional<arc_point> c =
                correct(f, b.u.head(K + 1), hold, m_settings.tolerance, m_settings.newton_iterations);
            if (c && c->at.orbit.impact_sequence() == b.at.orbit.impact_sequence() &&
                (c->u - b.u.head(K + 1)).norm() <= 1e-6 * (1.0 + c->u.norm())) {
                set_tangent(*c, b.t.head(K + 1));
                found = std::move(c);
                return step_verdict::stop_after;
            }
            return step_verdict::accept;
        });
        return found;
    }

    // The multiplier of the bifurcation at a located point: +1 (fold), -1 (period doubling),
    // or a complex pair on the unit circle (Neimark-Sacker, not a neutral saddle).
    static bool has_critical_multiplier(const std::vector<std::complex<double>>& mu, bifurcation_type type)
    {
        for (const auto& m : mu) {
            if (type == bifurcation_type::neimark_sacker && std::abs(m.imag()) > 1e-6 &&
                std::abs(std::abs(m) - 1.0) < 1e-4)
                return true;
            if (type == bifurcation_type::fold && std::abs(m - 1.0) < 1e-3) return true;
            if (type == bifurcation_type::period_doubling && std::abs(m + 1.0) < 1e-3) return true;
        }
        return false;
    }

    // The eigenvector of DP = DG + I for the eigenvalue nearest -1.
    static Eigen::VectorXd flip_vector(const Eigen::MatrixXd& DG)
    {
        const Eigen::MatrixXd DP = DG + Eigen::MatrixXd::Identity(DG.rows(), DG.cols());
        const Eigen::EigenSolver<Eigen::MatrixXd> es(DP);
        Eigen::Index best = 0;
        for (Eigen::Index k = 1; k < DP.rows(); ++k)
            if (std::abs(es.eigenvalues()[k] + 1.0) < std::abs(es.eigenvalues()[best] + 1.0)) best = k;
        Eigen::VectorXd v = es.eigenvectors().col(best).real();
        return v.normalized();
    }

    const model& m_model;
    const continuation_options& m_opt;
    double m_range = 0.0;
    std::vector<arc_bound> m_bounds;
    arc_settings m_settings;
};

}  // namespace detail

continuation_result continuation(const model& m, const std::vector<Eigen::VectorXd>& starts,
                                 const continuation_options& o, int threads)
{
    validate(m, o);
    if (starts.empty()) throw input_error("a continuation needs at least one initial state");
    for (const auto& x : starts) {
        check_state_size(m, x.size(), "the initial state");
        if (violated_surface(m.with_parameter(o.parameter, o.start), x) >= 0)
            throw input_error("the initial state lies beyond a surface at the start of the range");
    }
    const detail::branch_runner runner(m, o);
    continuation_result res;
    job_loop_options jo;
    jo.threads = threads;
    jo.stop = o.cancel;

    // Adds a job's branch (a new orbit only) and its bifurcations; returns the switching jobs
    // of its period doublings.
    std::vector<detail::leg_job> next;
    auto absorb = [&](detail::branch_record&& r, int depth) {
        res.tangent_maps += r.tangent_maps;
        res.plain_maps += r.plain_maps;
        if (!r.has_branch) return;
        // The same orbit found from two starts (switched legs all start at their bifurcation).
        const bool duplicate = r.branch.parent < 0 &&
                               std::any_of(res.branches.begin(), res.branches.end(), [&](const continuation_branch& b) {
            return b.parent < 0 && b.returns == r.branch.returns && !b.points.empty() && !r.branch.points.empty() &&
                   b.points.front().parameter == r.branch.points.front().parameter &&
                   state_distance(m.info(), b.points.front().state, r.branch.points.front().state) < 1e-6;
        });
        if (duplicate) return;
        const int index = static_cast<int>(res.branches.size());
        const int first_bif = static_cast<int>(res.bifurcations.size());
        for (auto& b : r.bifurcations) {
            b.branch = index;
            res.bifurcations.push_back(std::move(b));
        }
        if (depth < o.switch_depth)
            for (const auto& s : r.seeds) {
                detail::leg_job j;
                j.parent = index;
                j.origin = first_bif + s.bifurcation;
                j.returns = 2 * r.branch.returns;
                j.chart = r.branch.chart_coordinate;
                j.guess = res.bifurcations[static_cast<std::size_t>(j.origin)].point.state;
                j.seed = s;
                next.push_back(std::move(j));
            }
        res.branches.push_back(std::move(r.branch));
    };

    std::vector<detail::branch_record> first(starts.size());
    run_jobs<detail::branch_record>(
        {static_cast<long>(starts.size()), 0}, jo, {},
        [&](long j, const detail::branch_record*) { return runner.from_start(starts[static_cast<std::size_t>(j)]); },
        [&](long j, detail::branch_record&& r) { first[static_cast<std::size_t>(j)] = std::move(r); });
    for (auto& r : first) {
        if (res.start_label.empty()) res.start_label = r.label;
        if (!r.has_branch && res.status == outcome::ok && res.branches.empty()) res.status = r.status;
        absorb(std::move(r), 0);
    }
    if (!res.branches.empty()) res.status = outcome::ok;
    for (int depth = 1; !next.empty(); ++depth) {
        const std::vector<detail::leg_job> jobs = std::move(next);
        next.clear();
        std::vector<detail::branch_record> recs(jobs.size());
        run_jobs<detail::branch_record>(
            {static_cast<long>(jobs.size()), 0}, jo, {},
            [&](long j, const detail::branch_record*) { return runner.from_switch(jobs[static_cast<std::size_t>(j)]); },
            [&](long j, detail::branch_record&& r) { recs[static_cast<std::size_t>(j)] = std::move(r); });
        for (auto& r : recs) absorb(std::move(r), depth);
    }
    return res;
}

}  // namespace vimpact
