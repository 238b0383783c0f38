#pragma once
// Floquet multipliers of a periodic orbit with impacts (the paper's Algorithm 1, Eq. 9-10),
// with the orbit refined by Newton shooting before the monodromy is formed.
//
//  1. Run the protocol (transient impacts discarded, section maxima recorded) and classify the
//     period; P0 (no impacts) orbits are periodic orbits too, classified on their maxima.
//     Aperiodic or failed runs stop here and are reported as such: no multipliers.
//  2. Newton shooting on P^k(z) = z (k = the number of section returns per period) from the
//     first recorded point, until the closure |P^k(z) - z|_inf <= tolerance (1e-11).
//  3. Monodromy Phi(T) = Phi_n S_n ... S_1 Phi_1 over exactly one period from the refined
//     point: the tangent part of the variational flow, with the chosen jump at each impact.
//  4. Multipliers = eigenvalues of Phi(T) (Eigen's real Schur-based solver). The trivial
//     multiplier is the one whose eigenvector is most nearly parallel to F(x*) (Phi F(x*) =
//     F(x*) exactly for the true monodromy); its distance from 1 measures the accuracy.
//
// Identity checked by the tests: det Phi(T) = exp(integral of div F over T) * prod det S_i,
// with det S_i = r^2 for the paper's model.
#include <algorithm>
#include <complex>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "vimpact/analysis/period.hpp"
#include "vimpact/stability/section_map.hpp"

namespace vimpact {

struct floquet_options {
    protocol_options protocol{};          // transient impacts and recorded maxima
    double period_tolerance = 1e-8;       // for the period label (SPEC §2)
    shooting_options shooting{};          // Newton on the section map (closure 1e-11)
    impact_tangent jump = impact_tangent::saltation;  // jump used in the final monodromy
    double sample_dt = 0.0;               // > 0: sample the refined orbit over one period
};

enum class floquet_status { ok, aperiodic, not_converged, sticking, flow_failed };

constexpr const char* to_string(floquet_status s)
{
    switch (s) {
        case floquet_status::ok: return "ok";
        case floquet_status::aperiodic: return "aperiodic";
        case floquet_status::not_converged: return "not_converged";
        case floquet_status::sticking: return "sticking";
        case floquet_status::flow_failed: return "flow_failed";
    }
    return "unknown";
}

template <int N>
struct floquet_result {
    floquet_status status = floquet_status::flow_failed;
    std::string label;                     // the protocol's period label
    std::string flow_outcome = "ok";       // outcome of the failing run, if any
    int section_returns = 0;               // k: maxima per period
    double period = 0.0;                   // T
    long impacts_per_period = 0;
    double initial_closure = 0.0;          // |P^k(z) - z| at the protocol's point
    double closure = 0.0;                  // after Newton
    int newton_iterations = 0;
    vec<N> orbit_point;                    // refined point on Sigma
    mat<N> monodromy;
    // Trivial multiplier first, then the others by decreasing modulus.
    std::vector<std::complex<double>> multipliers;
    double trivial_error = 0.0;            // |mu_trivial - 1|
    double trivial_residual = 0.0;         // |Phi F - mu_trivial F| / |F|
    double max_nontrivial_modulus = 0.0;
    double det_monodromy = 0.0;
    double liouville_det = 0.0;            // exp(integral div F) * prod det(jump)
    double divergence_integral = 0.0;
    double log_det_jumps = 0.0;
    impact_tangent jump = impact_tangent::saltation;
    std::vector<impact_event<N>> impacts;  // over one period
    std::vector<timed_state<N>> orbit;     // samples over one period (sample_dt > 0)
    std::vector<timed_state<N>> section_points;  // the protocol's recorded maxima (diagrams)
    run_stats protocol_stats;
    run_stats tangent_stats;               // the last map evaluation
    long map_evaluations = 0;

    [[nodiscard]] bool stable() const { return status == floquet_status::ok && max_nontrivial_modulus < 1.0; }
};

// Eigenvalues of a monodromy, the trivial one first, then by decreasing modulus (ties by real,
// then imaginary part, for determinism). The trivial multiplier is the eigenvalue mu for which
// F(x*) is most nearly an eigenvector, i.e. |Phi F - mu F| / |F| is smallest: for the true
// monodromy Phi F(x*) = F(x*) exactly. The eigenvalues are computed in long double: a few
// more digits for the smallest multipliers, and no vectorised kernels (Eigen's AVX-512 code
// for double trips false -Wmaybe-uninitialized errors in GCC 12).
template <int N>
void fill_multipliers(floquet_result<N>& res, const vec<N>& flow_direction)
{
    using extended = Eigen::Matrix<long double, N, N>;
    Eigen::EigenSolver<extended> es(res.monodromy.template cast<long double>(), false);
    Eigen::Matrix<std::complex<double>, N, 1> vals;
    for (int i = 0; i < N; ++i)
        vals[i] = {static_cast<double>(es.eigenvalues()[i].real()),
                   static_cast<double>(es.eigenvalues()[i].imag())};
    const vec<N> MF = res.monodromy * flow_direction;
    const double fnorm = flow_direction.norm();
    int trivial = 0;
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < N; ++i) {
        double sq = 0.0;
        for (int k = 0; k < N; ++k) sq += std::norm(MF[k] - vals[i] * flow_direction[k]);
        const double residual = std::sqrt(sq) / fnorm;
        if (residual < best) {
            best = residual;
            trivial = i;
        }
    }
    std::vector<std::complex<double>> rest;
    for (int i = 0; i < N; ++i)
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

// Steps 2-4 from a point near the orbit on Sigma with a known number of returns per period.
template <template <int> class Method = dop853, tangent_model Model>
floquet_result<Model::dim> floquet_from_point(const Model& model, const vec<Model::dim>& x_guess,
                                              int returns, const floquet_options& opt = {})
{
    constexpr int N = Model::dim;
    floquet_result<N> res;
    res.jump = opt.jump;
    res.section_returns = returns;
    const periodic_orbit<N> orb = find_periodic_orbit<Method>(model, x_guess, returns, opt.shooting);
    res.initial_closure = orb.initial_closure;
    res.closure = orb.closure;
    res.newton_iterations = orb.iterations;
    res.orbit_point = orb.x;
    res.map_evaluations = orb.map_evaluations;
    res.tangent_stats = orb.map.stats;
    if (orb.status == shooting_status::sticking) {
        res.status = floquet_status::sticking;
        return res;
    }
    if (orb.status == shooting_status::flow_failed) {
        res.status = floquet_status::flow_failed;
        res.flow_outcome = std::string(to_string(orb.map.status));
        return res;
    }
    section_return<N> map = orb.map;
    if (opt.jump != impact_tangent::saltation || opt.sample_dt > 0.0) {
        section_map_options mo = opt.shooting.map;
        mo.jump = opt.jump;
        mo.sample_dt = opt.sample_dt;
        map = section_map<Method>(model, orb.x, returns, mo);
        ++res.map_evaluations;
        res.tangent_stats = map.stats;
        if (!map.valid()) {
            res.status = map.sticking_phases > 0 ? floquet_status::sticking : floquet_status::flow_failed;
            res.flow_outcome = std::string(to_string(map.status));
            return res;
        }
    }
    res.period = map.time;
    res.impacts_per_period = map.impacts;
    res.monodromy = map.monodromy;
    res.divergence_integral = map.divergence_integral;
    res.log_det_jumps = map.log_det_jumps;
    res.det_monodromy = map.monodromy.determinant();
    res.liouville_det = std::exp(map.divergence_integral + map.log_det_jumps);
    res.impacts = map.impact_list;
    res.orbit = map.samples;
    fill_multipliers(res, vec<N>(model.rhs(orb.x)));
    res.status = orb.status == shooting_status::converged ? floquet_status::ok : floquet_status::not_converged;
    return res;
}

// The whole analysis from an initial state.
template <template <int> class Method = dop853, tangent_model Model>
floquet_result<Model::dim> floquet_analysis(const Model& model, const vec<Model::dim>& x0,
                                            const floquet_options& opt = {})
{
    constexpr int N = Model::dim;
    if (!(opt.period_tolerance > 0.0)) throw input_error("period tolerance must be > 0");
    if (opt.protocol.section != section_choice::maxima)
        throw input_error("Floquet analysis uses the section maxima (v = 0, v decreasing)");
    if (opt.protocol.record_points < 2)
        throw input_error("Floquet analysis needs at least 2 recorded section points");
    const protocol_result<N> pr = run_protocol<Method>(model, x0, opt.protocol);
    const period_label lab = classify_period(model, pr, opt.period_tolerance);
    floquet_result<N> res;
    res.label = lab.label;
    res.protocol_stats = pr.stats;
    res.section_points = pr.points;
    if (pr.status != outcome::ok || pr.points.empty()) {
        res.status = floquet_status::flow_failed;
        res.flow_outcome = std::string(to_string(pr.status));
        return res;
    }
    int returns = lab.period;
    if (lab.period == 0) {  // P0: the barrier-free orbit, periodic on its own maxima or not
        using coords = decltype(model.section_coordinates(pr.points.front().x));
        std::vector<coords> c;
        for (const auto& p : pr.points) c.push_back(model.section_coordinates(p.x));
        returns = smallest_period(c, opt.period_tolerance);
    }
    if (returns <= 0) {
        res.status = floquet_status::aperiodic;
        return res;
    }
    floquet_result<N> fr = floquet_from_point<Method>(model, pr.points.front().x, returns, opt);
    fr.label = lab.label;
    fr.protocol_stats = pr.stats;
    fr.section_points = pr.points;
    return fr;
}

}  // namespace vimpact
