#pragma once
// Floquet analysis (analysis/floquet.hpp) on an engine model.
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include <Eigen/Eigenvalues>

#include "vimpact/analysis/floquet.hpp"
#include "vimpact/engine/protocol.hpp"
#include "vimpact/tangent/section_map.hpp"

namespace vimpact::engine {

// Eigenvalues of a monodromy, the trivial one first, then by decreasing modulus (ties by real,
// then imaginary part, for determinism). The trivial multiplier is the eigenvalue mu for which
// F(x*) is most nearly an eigenvector, i.e. |Phi F - mu F| / |F| is smallest. Computed in long
// double: a few more digits for the smallest multipliers.
template <int N>
void fill_multipliers(floquet_result& res, const mat<N>& monodromy, const vec<N>& flow_direction)
{
    using extended = Eigen::Matrix<long double, N, N>;
    Eigen::EigenSolver<extended> es(monodromy.template cast<long double>(), false);
    const int n = static_cast<int>(monodromy.rows());
    std::vector<std::complex<double>> vals(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i)
        vals[static_cast<std::size_t>(i)] = {static_cast<double>(es.eigenvalues()[i].real()),
                                             static_cast<double>(es.eigenvalues()[i].imag())};
    const vec<N> MF = monodromy * flow_direction;
    const double fnorm = flow_direction.norm();
    std::size_t trivial = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < vals.size(); ++i) {
        double sq = 0.0;
        for (int k = 0; k < n; ++k) sq += std::norm(MF[k] - vals[i] * flow_direction[k]);
        const double residual = std::sqrt(sq) / fnorm;
        if (residual < best) {
            best = residual;
            trivial = i;
        }
    }
    std::vector<std::complex<double>> rest;
    for (std::size_t i = 0; i < vals.size(); ++i)
        if (i != trivial) rest.push_back(vals[i]);
    std::sort(rest.begin(), rest.end(), [](const auto& a, const auto& b) {
        if (std::abs(a) != std::abs(b)) return std::abs(a) > std::abs(b);
        if (a.real() != b.real()) return a.real() > b.real();
        return a.imag() > b.imag();
    });
    res.multipliers.clear();
    res.multipliers.push_back(vals[trivial]);
    res.multipliers.insert(res.multipliers.end(), rest.begin(), rest.end());
    res.trivial_error = std::abs(vals[trivial] - 1.0);
    res.trivial_residual = best;
    res.max_nontrivial_modulus = rest.empty() ? 0.0 : std::abs(rest.front());
}

inline shooting_options shooting_of(const floquet_options& o)
{
    shooting_options so;
    so.tolerance = o.newton_tolerance;
    so.max_iterations = o.newton_iterations;
    so.map.flow = o.protocol.flow;
    so.map.flow.integration = o.tangent_integration;
    so.map.flow.t_max = 1e4;
    so.map.flow.max_steps = 50'000'000;
    so.map.section = o.protocol.section.index;
    return so;
}

template <template <int> class Method, engine_model Model>
floquet_result floquet_from_point(const Model& model, const vec<Model::dim>& x_guess, int returns,
                                  const floquet_options& opt)
{
    constexpr int N = Model::dim;
    floquet_result res;
    res.jump = opt.jump;
    res.section_returns = returns;
    const shooting_options so = shooting_of(opt);
    const periodic_orbit<N> orb = find_periodic_orbit<Method>(model, x_guess, returns, so);
    res.initial_closure = orb.initial_closure;
    res.closure = orb.closure;
    res.newton_iterations = orb.iterations;
    res.orbit_point = to_dynamic(orb.x);
    res.map_evaluations = orb.map_evaluations;
    res.tangent_stats = orb.map.stats;
    if (orb.status != outcome::ok && orb.status != outcome::not_converged) {
        res.status = orb.status;
        return res;
    }
    section_return<N> map = orb.map;
    if (opt.jump != impact_tangent::saltation || opt.sample_dt > 0.0) {
        section_map_options mo = so.map;
        mo.jump = opt.jump;
        mo.sample_dt = opt.sample_dt;
        map = section_map<Method>(model, orb.x, returns, mo);
        ++res.map_evaluations;
        res.tangent_stats = map.stats;
        if (!map.valid()) {
            res.status = map.sticking_phases > 0 ? outcome::sticking : map.status;
            return res;
        }
    }
    res.period = map.time;
    res.impacts_per_period = map.impacts;
    res.impacts_by_surface.assign(static_cast<std::size_t>(model.surface_count()), 0);
    for (const int s : map.impact_list.surface) ++res.impacts_by_surface[static_cast<std::size_t>(s)];
    res.monodromy = to_dynamic(map.monodromy);
    res.divergence_integral = map.divergence_integral;
    res.log_det_jumps = map.log_det_jumps;
    res.det_monodromy = map.monodromy.determinant();
    res.liouville_det = std::exp(map.divergence_integral + map.log_det_jumps);
    res.impacts = map.impact_list;
    res.orbit = map.samples;
    fill_multipliers<N>(res, map.monodromy, vec<N>(model.rhs(orb.x)));
    res.status = orb.status;
    return res;
}

// Steps 2-4 after the protocol's run `pr` (step 1).
template <template <int> class Method, engine_model Model>
floquet_result floquet_after_protocol(const Model& model, const simulation& pr, const floquet_options& opt,
                                      const model_info& info)
{
    floquet_result res;
    res.protocol_stats = pr.stats;
    res.section_points = pr.points;
    if (pr.status != outcome::ok || pr.points.empty()) {
        res.label = std::string(to_string(pr.status));
        res.status = pr.status;
        return res;
    }
    double closure = 0.0;
    const auto distance = [&](int i, int j) {
        return state_distance(info, pr.points.x(static_cast<std::size_t>(i)), pr.points.x(static_cast<std::size_t>(j)));
    };
    const int returns = smallest_period(static_cast<int>(pr.points.size()), opt.period_tolerance, distance, &closure);
    if (!pr.impacting) res.label = "P0";
    else if (returns > 0) res.label = "P" + std::to_string(returns);
    else res.label = "aperiodic";
    if (returns <= 0) {
        res.status = outcome::aperiodic;
        return res;
    }
    floquet_result fr = floquet_from_point<Method>(model, vec<Model::dim>(pr.points.x(0)), returns, opt);
    fr.label = res.label;
    fr.protocol_stats = pr.stats;
    fr.section_points = pr.points;
    return fr;
}

}  // namespace vimpact::engine
