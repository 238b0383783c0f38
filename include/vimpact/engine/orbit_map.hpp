#pragma once
// The section map in chart coordinates (analysis/orbit_map.hpp) on an engine model.
#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "vimpact/analysis/orbit_map.hpp"
#include "vimpact/engine/floquet.hpp"
#include "vimpact/hybrid/flow.hpp"
#include "vimpact/tangent/section_map.hpp"

namespace vimpact::engine {

// Event `event` >= 1 of an orbit map's run at x: a gap's minimum (the surfaces' events come
// first), or an extremum of a switching function.
template <engine_model Model>
void record_extremum(orbit_map_value& out, const Model& m, int event, double t, const vec<Model::dim>& x)
{
    const int i = event - 1, S = m.surface_count();
    if (i < S) {
        out.gap_minima.push_back({t, i, m.gap(i, x)});
    } else {
        if constexpr (switching_model<Model>) out.switch_extrema.push_back({t, i - S, m.switching(i - S, x)});
    }
}

// The events an orbit map watches after its section: each gap's minima, each switching
// function's extrema.
template <engine_model Model>
void add_extremum_events(flow_options& fo, const Model& m)
{
    for (int i = 0; i < m.surface_count(); ++i) fo.events.push_back(flow_event::gap_extrema(i, crossing::up));
    for (int k = 0; k < switch_count(m); ++k) fo.events.push_back(flow_event::switch_extrema(k, crossing::both));
}

// The k-th return without the tangent: the residual only (what finite differences in a
// parameter need), at a fraction of the tangent flow's cost.
template <engine_model Model>
class plain_return_observer : public flow_observer {
public:
    static constexpr int N = Model::dim;
    plain_return_observer(const Model& m, int returns, orbit_map_value& out)
        : m_model(m), m_returns(returns), m_out(out), m_end(vec<N>::Zero(state_dim(m)))
    {
    }
    [[nodiscard]] bool reached() const { return m_seen >= m_returns; }
    [[nodiscard]] const vec<N>& end_state() const { return m_end; }

    flow_control on_section(int event, crossing, double t, const vec<N>& x)
    {
        if (reached()) return flow_control::proceed;
        if (event > 0) {
            record_extremum(m_out, m_model, event, t, x);
            return flow_control::proceed;
        }
        m_out.crossings.push_back(to_dynamic(x));
        if (++m_seen < m_returns) return flow_control::proceed;
        m_end = x;
        m_out.period = t;
        return flow_control::stop;
    }
    flow_control on_impact(int surface, double t, const vec<N>& pre, const vec<N>&)
    {
        if (reached()) return flow_control::stop;
        m_out.impacts.push_back(impact_of(m_model, surface, t, pre));
        return flow_control::proceed;
    }
    template <class X>
    flow_control on_switch(int k, double, const X&, const X&)
    {
        if (reached()) return flow_control::stop;
        ++m_out.crossings_by_switch[static_cast<std::size_t>(k)];
        return flow_control::proceed;
    }
    template <class X>
    void on_stick(int, double, const X&)
    {
        if (!reached()) ++m_sticking;
    }
    [[nodiscard]] long sticking_phases() const { return m_sticking; }

    static impact_record impact_of(const Model& m, int surface, double t, const vec<N>& pre)
    {
        const double v = -gap_rate(m, surface, pre);
        const vec<N> f = m.rhs(pre);
        const vec<N> jump = m.rhs(m.reset(surface, pre)) - m.reset_jacobian(surface, pre) * f;
        const double size = jump.cwiseAbs().maxCoeff();
        const double sensitivity = v > 0.0 ? size / v : std::numeric_limits<double>::infinity();
        return {t, surface, v, gap_rate_gradient(m, surface, pre).dot(f), sensitivity};
    }

private:
    const Model& m_model;
    int m_returns;
    orbit_map_value& m_out;
    int m_seen = 0;
    long m_sticking = 0;
    vec<N> m_end;
};

template <int K>
std::vector<std::complex<double>> eigenvalues_by_modulus(const mat<K>& m)
{
    std::vector<std::complex<double>> v;
    if constexpr (K != 0) {
        Eigen::EigenSolver<Eigen::Matrix<long double, K, K>> es(m.template cast<long double>(), false);
        for (int i = 0; i < m.rows(); ++i)
            v.emplace_back(static_cast<double>(es.eigenvalues()[i].real()), static_cast<double>(es.eigenvalues()[i].imag()));
    }
    std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) {
        if (std::abs(a) != std::abs(b)) return std::abs(a) > std::abs(b);
        if (a.real() != b.real()) return a.real() > b.real();
        return a.imag() > b.imag();
    });
    return v;
}

// Counts section returns (and records what a continuation watches) over the two runs of a
// forced impact, with the tangent.
template <class VModel>
class forced_observer : public flow_observer {
public:
    static constexpr int N = VModel::base_dim;
    forced_observer(const VModel& vm, int returns, orbit_map_value& out) : m_vm(vm), m_returns(returns), m_out(out) {}
    [[nodiscard]] bool reached() const { return m_seen >= m_returns; }
    [[nodiscard]] const typename VModel::state& end_state() const { return m_end; }
    flow_control on_section(int event, crossing, double t, const typename VModel::state& X)
    {
        if (reached()) return flow_control::proceed;
        const vec<N> x = VModel::point(X);
        if (event > 0) {
            record_extremum(m_out, m_vm.base(), event, t, x);
            return flow_control::proceed;
        }
        m_out.crossings.push_back(to_dynamic(x));
        if (++m_seen < m_returns) return flow_control::proceed;
        m_end = X;
        m_out.period = t;
        return flow_control::stop;
    }
    flow_control on_impact(int surface, double t, const typename VModel::state& pre, const typename VModel::state&)
    {
        if (reached()) return flow_control::stop;
        m_out.impacts.push_back(plain_return_observer<typename VModel::base_model>::impact_of(m_vm.base(), surface, t,
                                                                                             VModel::point(pre)));
        return flow_control::proceed;
    }
    template <class X>
    flow_control on_switch(int k, double, const X&, const X&)
    {
        if (reached()) return flow_control::stop;
        ++m_out.crossings_by_switch[static_cast<std::size_t>(k)];
        return flow_control::proceed;
    }
    template <class X>
    void on_stick(int, double, const X&)
    {
        if (!reached()) ++m_sticking;
    }
    [[nodiscard]] long sticking_phases() const { return m_sticking; }

private:
    const VModel& m_vm;
    int m_returns;
    orbit_map_value& m_out;
    int m_seen = 0;
    long m_sticking = 0;
    typename VModel::state m_end;
};

// The forced-impact map (orbit_map_request::forced_surface): the run to forced_time, the reset
// there, the run on to the k-th return, each with the tangent from the identity, composed.
template <template <int> class Method, engine_model Model>
void forced_orbit_map(const Model& model, const orbit_map_request& rq, const section_chart<Model>& chart,
                      const vec<Model::dim>& x, const flow_options& fo_in, orbit_map_value& out)
{
    constexpr int N = Model::dim;
    constexpr int K = dim_less_one(N);
    const int n = state_dim(model);
    using VM = variational_model<Model>;
    const VM vm(model, impact_tangent::saltation);
    flow_options fo = fo_in;
    fo.integration = VM::integration_options(rq.integration);
    fo.surfaces = true;
    fo.events = {flow_event::section(rq.section, model.section_direction(rq.section))};
    add_extremum_events(fo, model);
    forced_observer<VM> obs(vm, rq.returns, out);
    const int s = rq.forced_surface;
    // To the forced impact.
    flow_options f1 = fo;
    f1.t_max = rq.forced_time;
    hybrid_flow<VM, Method> one(vm, f1);
    one.start(0.0, VM::pack(detail::past_section(model, rq.section, x), mat<N>::Identity(n, n), 0.0));
    const outcome o1 = rq.forced_time > 0.0 ? one.run(obs) : outcome::time_limit;
    out.stats = one.stats();
    if (o1 != outcome::time_limit || obs.reached() || obs.sticking_phases() > 0) {
        // The orbit made its k returns (the observer stopped the run: o1 is ok) or failed before
        // the forced time.
        out.status = obs.sticking_phases() > 0                        ? outcome::sticking
                     : o1 == outcome::time_limit || o1 == outcome::ok ? outcome::not_converged
                                                                      : o1;
        return;
    }
    const vec<N> pre = VM::point(one.x());
    const mat<N> Y1 = VM::matrix(one.x());
    const vec<N> post = model.reset(s, pre);
    const mat<N> R = model.reset_jacobian(s, pre);
    out.impacts.push_back(plain_return_observer<Model>::impact_of(model, s, rq.forced_time, pre));
    out.impacts.back().sensitivity = 0.0;  // at a given time: no event to locate
    // On to the k-th return.
    hybrid_flow<VM, Method> two(vm, fo);
    two.start(rq.forced_time, VM::pack(post, mat<N>::Identity(n, n), 0.0));
    out.status = two.run(obs);
    out.stats.add(two.stats());
    if (out.status == outcome::ok && !obs.reached()) out.status = outcome::time_limit;
    if (out.status == outcome::ok && obs.sticking_phases() > 0) out.status = outcome::sticking;
    if (out.status != outcome::ok) return;
    const vec<N> x_end = VM::point(obs.end_state());
    const mat<N> Y2 = VM::matrix(obs.end_state());
    const vec<N> F = model.rhs(x_end);
    const vec<N> g = model.section_gradient(rq.section, x_end);
    const mat<N> proj = mat<N>::Identity(n, n) - F * g.transpose() / g.dot(F);
    const mat<N> monodromy = Y2 * R * Y1;
    const mat<K> DP = chart.projection() * proj * monodromy * chart.embedding(x);
    out.x_end = to_dynamic(x_end);
    out.residual = to_dynamic(vec<K>(chart.to_chart(model.state_difference(x_end, x))));
    out.residual_jacobian = to_dynamic(mat<K>(DP - mat<K>::Identity(n - 1, n - 1)));
    out.monodromy = to_dynamic(monodromy);
    // Moving the impact by dt moves the state after it by (R' F(pre) - F(post)) dt.
    const vec<N> shift = R * model.rhs(pre) - model.rhs(post);
    out.residual_time_derivative = to_dynamic(vec<K>(chart.projection() * proj * Y2 * shift));
    const vec<N> gg = model.gap_gradient(s, pre);
    out.forced_gap = model.gap(s, pre);
    out.forced_gap_gradient = to_dynamic(vec<K>((gg.transpose() * Y1 * chart.embedding(x)).transpose()));
    out.forced_gap_rate = gg.dot(model.rhs(pre));
    floquet_result fr;
    fill_multipliers<N>(fr, monodromy, vec<N>(model.rhs(x)));
    out.multipliers = std::move(fr.multipliers);
    out.section_multipliers = eigenvalues_by_modulus<K>(DP);
}

template <template <int> class Method, engine_model Model>
orbit_map_value orbit_map_once(const Model& model, const orbit_map_request& rq)
{
    constexpr int N = Model::dim;
    constexpr int K = dim_less_one(N);
    static_assert(N >= 2 || N == Eigen::Dynamic, "a section map needs at least two state variables");
    const int n = state_dim(model);
    orbit_map_value out;
    // Phases reduced to one period (state_difference from 0): a forcing phase carried over from
    // a long run (200 periods: 1257) holds 100 times fewer digits, and near grazing the map
    // amplifies that rounding into its residual (5e-10 at v = 0.002 on the forced oscillator).
    const vec<N> zero = vec<N>::Zero(n);
    const vec<N> guess = model.state_difference(head_as<N>(rq.guess, n), zero);
    const section_chart<Model> chart =
        rq.chart_coordinate >= 0 ? section_chart<Model>(model, rq.section, rq.chart_coordinate)
                                 : section_chart<Model>(model, rq.section, guess);
    out.chart_coordinate = chart.dropped();
    out.crossings_by_switch.assign(static_cast<std::size_t>(switch_count(model)), 0);
    const vec<K> z = head_as<K>(rq.z, n - 1);
    const vec<N> x = model.state_difference(chart.from_chart(z, guess), zero);
    out.x = to_dynamic(x);
    if (!x.allFinite()) {
        out.status = outcome::not_converged;
        return out;
    }
    for (int i = 0; i < model.surface_count(); ++i) {
        if (i < 64 && ((rq.absent_surfaces >> i) & 1U) && rq.absent_from <= 0.0) continue;
        const double g = model.gap(i, x);
        if (g < 0.0 || (g == 0.0 && gap_rate(model, i, x) < 0.0)) {
            out.status = outcome::inadmissible;
            return out;
        }
    }
    flow_options fo;
    fo.integration = rq.integration;
    fo.t_max = rq.t_max;
    fo.max_steps = rq.max_steps;
    fo.cancel = rq.cancel;
    fo.absent_surfaces = rq.absent_surfaces;
    fo.absent_from = rq.absent_from;
    fo.absent_until = rq.absent_until;

    vec<N> x_end;
    if (rq.forced_surface >= 0) {
        forced_orbit_map<Method>(model, rq, chart, x, fo, out);
        return out;
    }
    if (rq.tangent) {
        section_map_options mo;
        mo.flow = fo;
        mo.section = rq.section;
        mo.gap_minima = true;
        const section_return<N> r = section_map<Method>(model, x, rq.returns, mo);
        out.stats = r.stats;
        for (std::size_t i = 0; i < r.impact_list.size(); ++i)
            out.impacts.push_back(plain_return_observer<Model>::impact_of(
                model, r.impact_list.surface[i], r.impact_list.pre.t(i), vec<N>(r.impact_list.pre.x(i))));
        for (const auto& g : r.gap_minima) out.gap_minima.push_back({g.t, g.surface, g.gap});
        for (const auto& e : r.switch_extrema) out.switch_extrema.push_back({e.t, e.k, e.h});
        out.crossings_by_switch = r.switch_crossings;
        for (std::size_t i = 0; i < r.crossings.size(); ++i) out.crossings.push_back(r.crossings.x(i));
        if (!r.valid()) {
            out.status = r.sticking_phases > 0 ? outcome::sticking : r.status;
            out.x_end = to_dynamic(r.x_end);
            return out;
        }
        x_end = r.x_end;
        out.period = r.time;
        const mat<K> DP = chart.projection() * r.return_derivative * chart.embedding(x);
        out.residual_jacobian = to_dynamic(mat<K>(DP - mat<K>::Identity(n - 1, n - 1)));
        out.monodromy = to_dynamic(r.monodromy);
        floquet_result fr;
        fill_multipliers<N>(fr, r.monodromy, vec<N>(model.rhs(x)));
        out.multipliers = std::move(fr.multipliers);
        out.section_multipliers = eigenvalues_by_modulus<K>(DP);
    } else {
        fo.surfaces = true;
        fo.events = {flow_event::section(rq.section, model.section_direction(rq.section))};
        add_extremum_events(fo, model);
        hybrid_flow<Model, Method> flow(model, fo);
        flow.start(0.0, detail::past_section(model, rq.section, x));
        plain_return_observer<Model> obs(model, rq.returns, out);
        out.status = flow.run(obs);
        out.stats = flow.stats();
        if (out.status == outcome::ok && !obs.reached()) out.status = outcome::time_limit;
        if (out.status == outcome::ok && obs.sticking_phases() > 0) out.status = outcome::sticking;
        if (out.status != outcome::ok) {
            out.x_end = to_dynamic(flow.x());
            return out;
        }
        x_end = obs.end_state();
    }
    out.x_end = to_dynamic(x_end);
    out.residual = to_dynamic(vec<K>(chart.to_chart(model.state_difference(x_end, x))));
    return out;
}

// The map at the request's tolerances, run again more accurately where a soft impact makes it
// sensitive to the integration error (orbit_map_request::sensitivity_limit).
template <template <int> class Method, engine_model Model>
orbit_map_value orbit_map(const Model& model, const orbit_map_request& rq)
{
    orbit_map_value out = orbit_map_once<Method>(model, rq);
    if (!(rq.sensitivity_limit > 0.0) || out.impacts.empty()) return out;
    double worst = 0.0;
    for (const auto& i : out.impacts) worst = std::max(worst, i.sensitivity);
    const double factor = std::min(rq.sensitivity_limit / worst, 1.0);
    const double floor = rq.tightest_tolerance;
    if (!(factor < 1.0) || (rq.integration.rtol <= floor && rq.integration.atol <= floor)) return out;
    orbit_map_request fine = rq;
    fine.integration.rtol = std::max(rq.integration.rtol * factor, std::min(floor, rq.integration.rtol));
    fine.integration.atol = std::max(rq.integration.atol * factor, std::min(floor, rq.integration.atol));
    fine.sensitivity_limit = 0.0;
    run_stats first = out.stats;
    out = orbit_map_once<Method>(model, fine);
    first.add(out.stats);
    out.stats = first;
    return out;
}

}  // namespace vimpact::engine
