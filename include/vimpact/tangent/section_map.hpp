#pragma once
// The section map and its Jacobian, and Newton shooting for its fixed points: the building
// blocks of Floquet analysis, reusable by a continuation solver.
//
// The section is one of the model's sections, Sigma = { s(x) = 0 } crossed in its direction.
// A point of Sigma is given by chart coordinates z: the state without one coordinate x_c, the
// one along which s changes fastest at the starting point (|ds/dx_c| largest; for the paper's
// section s = ydot that is ydot itself). x_c follows from s(x) = 0 (Newton in x_c; exact in
// one step for a coordinate section). P^k(z) is the point of the k-th return to Sigma,
// through any impacts on the way.
//
// Jacobian. With Phi = dx(t)/dx0 at fixed t (flow STMs and impact jumps multiplied in order,
// integrated as the tangent part of variational_model) and the return time fixed by
// s(x(t)) = 0, the derivative of the return point is
//   dx_end/dx0 = (I - F(x_end) grad s(x_end)^T / (grad s . F)(x_end)) Phi,
// and in the chart dz_end/dz = [that without row c] E, where E = dx0/dz has the columns
// e_j - (ds/dx_j / ds/dx_c) e_c, j != c.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/LU>

#include "vimpact/core/input_error.hpp"
#include "vimpact/core/outcome.hpp"
#include "vimpact/core/state_series.hpp"
#include "vimpact/hybrid/flow.hpp"
#include "vimpact/tangent/variational.hpp"

namespace vimpact {

template <int N>
using chart_point = vec<dim_less_one(N)>;

// The chart of a section near a point: which coordinate is solved for.
template <engine_model Model>
class section_chart {
public:
    static constexpr int N = Model::dim;
    static constexpr int K = dim_less_one(N);

    section_chart(const Model& m, int section, const vec<N>& near) : m_model(&m), m_section(section), m_n(state_dim(m))
    {
        const vec<N> g = m.section_gradient(section, near);
        m_dropped = 0;
        for (int j = 1; j < m_n; ++j)
            if (std::abs(g[j]) > std::abs(g[m_dropped])) m_dropped = j;
    }

    // A chart that solves for coordinate `dropped` (a continuation keeps one chart along its
    // branch, chosen at its start).
    section_chart(const Model& m, int section, int dropped)
        : m_model(&m), m_section(section), m_n(state_dim(m)), m_dropped(dropped)
    {
        if (dropped < 0 || dropped >= m_n) throw input_error("section chart coordinate out of range");
    }

    [[nodiscard]] int dropped() const { return m_dropped; }

    [[nodiscard]] chart_point<N> to_chart(const vec<N>& x) const
    {
        chart_point<N> z = sized<chart_point<N>>(m_n - 1);
        for (int i = 0, k = 0; i < m_n; ++i)
            if (i != m_dropped) z[k++] = x[i];
        return z;
    }

    // The point of the section with chart coordinates z, x_c found by Newton's method from
    // `guess` (NaN if it does not converge: the chart does not reach the section there).
    [[nodiscard]] vec<N> from_chart(const chart_point<N>& z, const vec<N>& guess) const
    {
        vec<N> x = sized<vec<N>>(m_n);
        for (int i = 0, k = 0; i < m_n; ++i) x[i] = (i == m_dropped) ? guess[i] : z[k++];
        for (int it = 0; it < 30; ++it) {
            const double s = m_model->section(m_section, x);
            if (s == 0.0) return x;
            const double ds = m_model->section_gradient(m_section, x)[m_dropped];
            if (!(ds != 0.0)) break;
            const double step = s / ds;
            x[m_dropped] -= step;
            if (std::abs(step) <= 4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(x[m_dropped])))
                return x;
        }
        return vec<N>::Constant(m_n, std::numeric_limits<double>::quiet_NaN());
    }

    // dx/dz at x: the N x (N-1) matrix E of the header.
    [[nodiscard]] Eigen::Matrix<double, N, K> embedding(const vec<N>& x) const
    {
        const vec<N> g = m_model->section_gradient(m_section, x);
        Eigen::Matrix<double, N, K> E = Eigen::Matrix<double, N, K>::Zero(m_n, m_n - 1);
        for (int j = 0, k = 0; j < m_n; ++j) {
            if (j == m_dropped) continue;
            E(j, k) = 1.0;
            E(m_dropped, k) = -g[j] / g[m_dropped];
            ++k;
        }
        return E;
    }

    [[nodiscard]] Eigen::Matrix<double, K, N> projection() const
    {
        Eigen::Matrix<double, K, N> P = Eigen::Matrix<double, K, N>::Zero(m_n - 1, m_n);
        for (int i = 0, k = 0; i < m_n; ++i)
            if (i != m_dropped) P(k++, i) = 1.0;
        return P;
    }

private:
    const Model* m_model;
    int m_section;
    int m_n;  // the state dimension
    int m_dropped = 0;
};

struct section_map_options {
    // Newton closes the orbit to 1e-11 only if the map itself is that accurate. t_max is the
    // flight time allowed for the requested returns; the analysis sets the events.
    flow_options flow{.integration{.rtol = 1e-12, .atol = 1e-12}, .t_max = 1e4, .max_steps = 50'000'000};
    int section = 0;
    impact_tangent jump = impact_tangent::saltation;
    double sample_dt = 0.0;       // > 0: also sample the orbit (state part) every sample_dt
    // Also record every local minimum of every gap, every extremum of every switching
    // function and each switch's crossings (grazing).
    bool gap_minima = false;
};

// A local minimum of a gap between impacts: how closely the orbit passes a surface it does
// not hit there (its value reaching 0 is a grazing).
struct gap_minimum {
    double t = 0.0;
    int surface = 0;
    double gap = 0.0;
};

// A local extremum of switching function k, on either side of its switch.
struct switch_extremum {
    double t = 0.0;
    int k = 0;
    double h = 0.0;
};

template <int N>
struct section_return {
    // n: the state dimension (a dynamic N has none at compile time).
    explicit section_return(int n = N == Eigen::Dynamic ? 0 : N) : impact_list(n), crossings(n), samples(n) {}

    outcome status = outcome::ok;       // ok: the requested returns were reached
    long sticking_phases = 0;           // > 0: the tangent is not valid (see variational.hpp)
    vec<N> x0;
    vec<N> x_end;                       // state at the last return
    double time = 0.0;                  // return time
    long impacts = 0;                   // impacts before the last return
    mat<N> monodromy;                   // dx(time)/dx0, impacts included
    mat<N> return_derivative;           // dx_end/dx0 along the section (the projected monodromy)
    double divergence_integral = 0.0;   // integral of div F over [0, time]
    double log_det_jumps = 0.0;         // sum of ln|det(jump)| over the impacts
    impact_series impact_list;          // reference states at the impacts
    std::vector<gap_minimum> gap_minima;  // before the last return (section_map_options::gap_minima)
    std::vector<switch_extremum> switch_extrema;  // the same
    std::vector<long> switch_crossings;           // per switch, before the last return
    state_series crossings;             // the state at each return (the last is x_end)
    state_series samples;               // the orbit every sample_dt (if asked)
    run_stats stats;

    [[nodiscard]] bool valid() const { return status == outcome::ok && sticking_phases == 0; }
};

namespace detail {

template <class VModel>
class section_return_observer : public flow_observer {
public:
    static constexpr int N = VModel::base_dim;
    section_return_observer(const VModel& vm, int returns, double sample_dt, section_return<N>& out)
        : m_vm(vm), m_returns(returns), m_dt(sample_dt), m_out(out), m_next(sample_dt)
    {
        m_out.switch_crossings.assign(static_cast<std::size_t>(switch_count(vm.base())), 0);
    }
    [[nodiscard]] bool wants_segments() const { return m_dt > 0.0; }
    [[nodiscard]] bool reached() const { return m_seen >= m_returns; }
    [[nodiscard]] const typename VModel::state& end_state() const { return m_end; }

    // With sampling, the run goes on to the end of the step that holds the last return, so
    // that the step's interpolant is delivered (up to the return) before the stop. Event 0 is
    // the section; any others are the minima of the gaps, in surface order, then the extrema of
    // the switching functions.
    flow_control on_section(int event, crossing, double t, const typename VModel::state& X)
    {
        if (reached()) return flow_control::proceed;
        if (event > 0) {
            const int i = event - 1, S = m_vm.base().surface_count();
            if (i < S) {
                m_out.gap_minima.push_back({t, i, m_vm.base().gap(i, VModel::point(X))});
            } else {
                if constexpr (switching_model<typename VModel::base_model>)
                    m_out.switch_extrema.push_back({t, i - S, m_vm.base().switching(i - S, VModel::point(X))});
            }
            return flow_control::proceed;
        }
        m_out.crossings.push_back(t, VModel::point(X));
        if (++m_seen < m_returns) return flow_control::proceed;
        m_end = X;
        m_out.time = t;
        return m_dt > 0.0 ? flow_control::proceed : flow_control::stop;
    }
    flow_control on_step_end(double)
    {
        if (!reached()) return flow_control::proceed;
        if (m_dt > 0.0) m_out.samples.push_back(m_out.time, VModel::point(m_end));
        return flow_control::stop;
    }
    flow_control on_impact(int surface, double t, const typename VModel::state& pre, const typename VModel::state& post)
    {
        if (reached()) return flow_control::stop;  // after the last return, in its step
        const vec<N> x = VModel::point(pre);
        m_out.impact_list.push_back(t, surface, x, VModel::point(post));
        ++m_out.impacts;
        const mat<N> jump = impact_jump_matrix(m_vm.base(), surface, x, m_vm.jump());
        m_out.log_det_jumps += std::log(std::abs(jump.determinant()));
        return flow_control::proceed;
    }
    // A switching surface's jump S (tangent/variational.hpp) has det S = det Y+ / det Y-.
    flow_control on_switch(int k, double, const typename VModel::state& pre, const typename VModel::state& post)
    {
        if (reached()) return flow_control::stop;
        ++m_out.switch_crossings[static_cast<std::size_t>(k)];
        m_out.log_det_jumps +=
            std::log(std::abs(VModel::matrix(post).determinant())) - std::log(std::abs(VModel::matrix(pre).determinant()));
        return flow_control::proceed;
    }
    template <class X>
    void on_stick(int, double, const X&)
    {
        if (!reached()) ++m_out.sticking_phases;
    }
    template <class D>
    void on_segment(const D& d, double ta, double tb, flow_mode)
    {
        if (reached()) tb = std::min(tb, m_out.time);
        while (m_next < tb) {
            if (m_next >= ta) m_out.samples.push_back(m_next, VModel::point(d.value(m_next)));
            m_next = static_cast<double>(++m_index) * m_dt;
        }
    }

private:
    const VModel& m_vm;
    int m_returns;
    double m_dt;
    section_return<N>& m_out;
    int m_seen = 0;
    typename VModel::state m_end;
    double m_next;  // the sample at t = 0 is the start point itself
    long m_index = 1;
};

// A start on the section lies on it only up to rounding (e.g. sin(phi) = 0 to an ulp of phi).
// On the side the section is crossed from (s < 0 for an upward section, s > 0 for a downward
// one, s moving towards 0 for one counted both ways) the flow reports the start's own crossing,
// a rounding error later, as the first return (a period of 1e-14). Such a start is moved
// across, one ulp at a time along the coordinate s depends on most; a start more than 64 ulps
// away is not on the section and is left as it is.
template <engine_model Model>
vec<Model::dim> past_section(const Model& m, int k, const vec<Model::dim>& x)
{
    constexpr int N = Model::dim;
    const crossing dir = m.section_direction(k);
    auto before = [&](const vec<N>& y) {
        const double s = m.section(k, y);
        if (dir == crossing::up) return s < 0.0;
        if (dir == crossing::down) return s > 0.0;
        return s != 0.0 && (s > 0.0) != (m.section_gradient(k, y).dot(m.rhs(y)) > 0.0);
    };
    if (!before(x)) return x;
    const vec<N> g = m.section_gradient(k, x);
    int c = 0;
    for (int j = 1; j < g.size(); ++j)
        if (std::abs(g[j]) > std::abs(g[c])) c = j;
    if (!(g[c] != 0.0)) return x;
    // The way s must go: up for an upward section, down for a downward one, through 0 otherwise.
    const double s_way = dir == crossing::up ? 1.0 : dir == crossing::down ? -1.0 : (m.section(k, x) > 0.0 ? -1.0 : 1.0);
    const double toward = s_way * g[c] > 0.0 ? std::numeric_limits<double>::infinity()
                                             : -std::numeric_limits<double>::infinity();
    vec<N> y = x;
    for (int i = 0; i < 64; ++i) {
        y[c] = std::nextafter(y[c], toward);
        if (!before(y)) return y;
    }
    return x;
}

}  // namespace detail

// P^returns from x0 (on the section) with the tangent. Time starts at 0. A start that rounding
// left just before the section is moved across it first (detail::past_section; out.x0 is the
// start integrated).
template <template <int> class Method, engine_model Model>
section_return<Model::dim> section_map(const Model& model, const vec<Model::dim>& x0, int returns,
                                       const section_map_options& opt = {})
{
    constexpr int N = Model::dim;
    if (returns < 1) throw input_error("section returns must be >= 1 (got " + std::to_string(returns) + ")");
    using VM = variational_model<Model>;
    const VM vm(model, opt.jump);
    flow_options fo = opt.flow;
    fo.integration = VM::integration_options(opt.flow.integration);
    fo.surfaces = true;
    fo.events = {flow_event::section(opt.section, model.section_direction(opt.section))};
    if (opt.gap_minima) {
        for (int i = 0; i < model.surface_count(); ++i) fo.events.push_back(flow_event::gap_extrema(i, crossing::up));
        for (int k = 0; k < switch_count(model); ++k) fo.events.push_back(flow_event::switch_extrema(k, crossing::both));
    }
    hybrid_flow<VM, Method> flow(vm, fo);
    const int n = state_dim(model);
    section_return<N> out(n);
    out.x0 = detail::past_section(model, opt.section, x0);
    flow.start(0.0, VM::pack(out.x0, mat<N>::Identity(n, n), 0.0));
    if (opt.sample_dt > 0.0) out.samples.push_back(0.0, out.x0);
    detail::section_return_observer<VM> obs(vm, returns, opt.sample_dt, out);
    out.status = flow.run(obs);
    out.stats = flow.stats();
    if (out.status == outcome::ok && !obs.reached()) out.status = outcome::time_limit;
    if (out.status != outcome::ok) {
        out.x_end = VM::point(flow.x());
        out.monodromy = VM::matrix(flow.x());
        out.return_derivative.setConstant(std::numeric_limits<double>::quiet_NaN());
        return out;
    }
    const auto& X = obs.end_state();
    out.x_end = VM::point(X);
    out.monodromy = VM::matrix(X);
    out.divergence_integral = VM::divergence_integral(X);
    const vec<N> F = model.rhs(out.x_end);
    const vec<N> g = model.section_gradient(opt.section, out.x_end);
    const mat<N> proj = mat<N>::Identity(n, n) - F * g.transpose() / g.dot(F);
    out.return_derivative = proj * out.monodromy;
    return out;
}

// ---- Newton shooting ---------------------------------------------------------------------

struct shooting_options {
    section_map_options map{};
    double tolerance = 1e-11;   // closure |P^k(z) - z|_inf to reach
    int max_iterations = 20;
};

template <int N>
struct periodic_orbit {
    outcome status = outcome::not_converged;  // ok, not_converged, sticking, or the map's failure
    vec<N> x;                       // the refined point on the section
    int returns = 0;
    double initial_closure = std::numeric_limits<double>::quiet_NaN();
    double closure = std::numeric_limits<double>::quiet_NaN();  // |P^k(z) - z|_inf at x
    int iterations = 0;
    section_return<N> map;          // P^k at x, with the saltation tangent
    long map_evaluations = 0;
};

// Fixed point of P^returns near x_guess by Newton's method on P^k(z) - z = 0, with step
// halving when the closure does not decrease. The result carries the last map evaluation
// (monodromy, period, impacts) at the returned point.
template <template <int> class Method, engine_model Model>
periodic_orbit<Model::dim> find_periodic_orbit(const Model& model, const vec<Model::dim>& x_guess, int returns,
                                               const shooting_options& opt = {})
{
    constexpr int N = Model::dim;
    constexpr int K = dim_less_one(N);
    static_assert(N >= 2 || N == Eigen::Dynamic, "a section map needs at least two state variables");
    const int k = state_dim(model) - 1;
    if (k < 1) throw input_error("a section map needs at least two state variables");
    if (!(opt.tolerance > 0.0)) throw input_error("Newton tolerance must be > 0");
    if (opt.max_iterations < 0) throw input_error("Newton iterations must be >= 0");
    section_map_options mo = opt.map;
    mo.jump = impact_tangent::saltation;
    periodic_orbit<N> orb;
    orb.returns = returns;
    const section_chart<Model> chart(model, mo.section, x_guess);
    auto residual_of = [&](const section_return<N>& r, const vec<N>& x) {
        return vec<K>(chart.to_chart(model.state_difference(r.x_end, x)));
    };
    auto evaluate = [&](const vec<N>& x) {
        ++orb.map_evaluations;
        return section_map<Method>(model, x, returns, mo);
    };
    vec<N> x = chart.from_chart(chart.to_chart(x_guess), x_guess);
    if (!x.allFinite()) x = x_guess;
    section_return<N> r = evaluate(x);
    auto failed = [&](const section_return<N>& e) {
        orb.status = e.sticking_phases > 0 ? outcome::sticking : e.status;
        orb.x = x;
        orb.map = e;
        return orb;
    };
    if (!r.valid()) return failed(r);
    vec<K> res = residual_of(r, x);
    double norm = res.cwiseAbs().maxCoeff();
    orb.initial_closure = norm;
    for (int it = 0; it < opt.max_iterations && norm > opt.tolerance; ++it) {
        const mat<K> A = chart.projection() * r.return_derivative * chart.embedding(x) - mat<K>::Identity(k, k);
        const vec<K> step = A.fullPivLu().solve(-res);
        if (!step.allFinite()) break;
        bool improved = false;
        double lambda = 1.0;
        for (int halving = 0; halving < 10; ++halving, lambda *= 0.5) {
            const vec<N> xt = chart.from_chart(vec<K>(chart.to_chart(x) + lambda * step), x);
            if (!xt.allFinite() || !admissible(model, xt)) continue;  // beyond a surface, or off the chart
            section_return<N> rt = evaluate(xt);
            if (!rt.valid()) continue;
            const vec<K> rest = residual_of(rt, xt);
            const double nt = rest.cwiseAbs().maxCoeff();
            if (nt < norm) {
                x = xt;
                r = std::move(rt);
                res = rest;
                norm = nt;
                improved = true;
                break;
            }
        }
        orb.iterations = it + 1;
        if (!improved) break;
    }
    orb.x = x;
    orb.closure = norm;
    orb.map = std::move(r);
    orb.status = norm <= opt.tolerance ? outcome::ok : outcome::not_converged;
    return orb;
}

}  // namespace vimpact
