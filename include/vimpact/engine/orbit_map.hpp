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

// The k-th return without the tangent: the residual only (what finite differences in a
// parameter need), at a fraction of the tangent flow's cost.
template <engine_model Model>
class plain_return_observer : public flow_observer {
public:
    static constexpr int N = Model::dim;
    plain_return_observer(const Model& m, int returns, orbit_map_value& out) : m_model(m), m_returns(returns), m_out(out)
    {
    }
    [[nodiscard]] bool reached() const { return m_seen >= m_returns; }
    [[nodiscard]] const vec<N>& end_state() const { return m_end; }

    flow_control on_section(int event, crossing, double t, const vec<N>& x)
    {
        if (reached()) return flow_control::proceed;
        if (event > 0) {
            m_out.gap_minima.push_back({t, event - 1, m_model.gap(event - 1, x)});
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
    void on_stick(int, double, const X&)
    {
        if (!reached()) ++m_sticking;
    }
    [[nodiscard]] long sticking_phases() const { return m_sticking; }

    static impact_record impact_of(const Model& m, int surface, double t, const vec<N>& pre)
    {
        return {t, surface, -gap_rate(m, surface, pre), gap_rate_gradient(m, surface, pre).dot(m.rhs(pre))};
    }

private:
    const Model& m_model;
    int m_returns;
    orbit_map_value& m_out;
    int m_seen = 0;
    long m_sticking = 0;
    vec<N> m_end = vec<N>::Zero();
};

template <int K>
std::vector<std::complex<double>> eigenvalues_by_modulus(const mat<K>& m)
{
    std::vector<std::complex<double>> v;
    if constexpr (K > 0) {
        Eigen::EigenSolver<Eigen::Matrix<long double, K, K>> es(m.template cast<long double>(), false);
        for (int i = 0; i < K; ++i)
            v.emplace_back(static_cast<double>(es.eigenvalues()[i].real()), static_cast<double>(es.eigenvalues()[i].imag()));
    }
    std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) {
        if (std::abs(a) != std::abs(b)) return std::abs(a) > std::abs(b);
        if (a.real() != b.real()) return a.real() > b.real();
        return a.imag() > b.imag();
    });
    return v;
}

template <template <int> class Method, engine_model Model>
orbit_map_value orbit_map(const Model& model, const orbit_map_request& rq)
{
    constexpr int N = Model::dim;
    constexpr int K = N - 1;
    static_assert(N >= 2, "a section map needs at least two state variables");
    orbit_map_value out;
    const vec<N> guess = rq.guess.head<N>();
    const section_chart<Model> chart =
        rq.chart_coordinate >= 0 ? section_chart<Model>(model, rq.section, rq.chart_coordinate)
                                 : section_chart<Model>(model, rq.section, guess);
    out.chart_coordinate = chart.dropped();
    const vec<K> z = rq.z.head<K>();
    const vec<N> x = chart.from_chart(z, guess);
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
        for (std::size_t i = 0; i < r.crossings.size(); ++i) out.crossings.push_back(r.crossings.x(i));
        if (!r.valid()) {
            out.status = r.sticking_phases > 0 ? outcome::sticking : r.status;
            out.x_end = to_dynamic(r.x_end);
            return out;
        }
        x_end = r.x_end;
        out.period = r.time;
        const mat<K> DP = chart.projection() * r.return_derivative * chart.embedding(x);
        out.residual_jacobian = to_dynamic(mat<K>(DP - mat<K>::Identity()));
        out.monodromy = to_dynamic(r.monodromy);
        floquet_result fr;
        fill_multipliers<N>(fr, r.monodromy, vec<N>(model.rhs(x)));
        out.multipliers = std::move(fr.multipliers);
        out.section_multipliers = eigenvalues_by_modulus<K>(DP);
    } else {
        fo.surfaces = true;
        fo.events = {flow_event::section(rq.section, model.section_direction(rq.section))};
        for (int i = 0; i < model.surface_count(); ++i) fo.events.push_back(flow_event::gap_extrema(i, crossing::up));
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

}  // namespace vimpact::engine
