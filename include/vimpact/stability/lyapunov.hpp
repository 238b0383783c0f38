#pragma once
// The Lyapunov spectrum of an orbit with impacts (the paper's Algorithm 2, Eq. 13).
//
// After a transient of impacts (state only), N deviation vectors of size r0 are carried along
// the reference orbit. Every t0 they are re-orthonormalised by a QR decomposition, rescaled
// to r0, and ln(R_ii / r0) is accumulated; after `warmup_intervals` intervals (not counted,
// so the vectors align with the Lyapunov directions) the averages over the following impacts
// (or time) are the exponents, sorted in descending order.
//
// How deviations cross an impact (`tdm`):
//  - saltation:    the tangent (variational) flow with Y -> S Y at each impact (first order,
//                  exact for infinitesimal deviations: the textbook Lyapunov spectrum);
//  - second_order: the tangent flow between impacts, the second-order mapping of SPEC §4
//                  applied to each finite deviation (size about r0) at each impact;
//  - trajectory:   Benettin's two-trajectory method: each x + y_i is integrated as a real
//                  orbit with its own impacts, y_i = x_i - x at the end of each interval.
// The sum of the exponents satisfies  sum = <div F> + (1/T) sum_impacts ln|det S|, i.e.
// <div F> + (impact rate) ln(r^2) for the paper's model: reported as `sum_rule` (tangent
// modes only: the trajectory mode does not integrate div F).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/QR>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/stability/variational.hpp"

namespace vimpact {

enum class lyapunov_tdm { saltation, second_order, trajectory };

constexpr const char* to_string(lyapunov_tdm t)
{
    switch (t) {
        case lyapunov_tdm::saltation: return "saltation";
        case lyapunov_tdm::second_order: return "second-order";
        case lyapunov_tdm::trajectory: return "trajectory";
    }
    return "unknown";
}

// Throws input_error naming the valid choices.
inline lyapunov_tdm parse_lyapunov_tdm(std::string_view s)
{
    if (s == "saltation") return lyapunov_tdm::saltation;
    if (s == "second-order") return lyapunov_tdm::second_order;
    if (s == "trajectory") return lyapunov_tdm::trajectory;
    throw input_error("--tdm '" + std::string(s) + "' is not one of saltation, second-order, trajectory");
}

struct lyapunov_options {
    long transient_impacts = 500;
    double quiet_time = 2000.0;       // the protocol's P0 rule during the transient
    flow_options flow{.t_max = 1e6};  // integration; t_max bounds the transient
    lyapunov_tdm tdm = lyapunov_tdm::saltation;
    double r0 = 1e-4;                 // size of the deviation vectors
    double t0 = std::numbers::pi;     // re-orthonormalisation interval
    long warmup_intervals = 16;       // intervals not counted
    long impacts = 800;               // average over this many impacts of the reference ...
    double time = 0.0;                // ... or, if > 0, over this much time
    double p0_time = 1e4;             // averaging time of an orbit without impacts (P0)
    double max_time = 1e6;            // averaging time limit (status time_limit)
    // Integrate div F with the tangent (sum_rule); without it the tangent flow is about a
    // third cheaper (28 -> 20 integrated components for the paper's model).
    bool divergence = true;
    // > 0: also record this many section maxima (v = 0, v decreasing) of the reference orbit
    // in the averaging window: the bifurcation diagram under an exponent sweep.
    long record_points = 0;
};

enum class lyapunov_status { ok, time_limit, sticking, flow_failed };

constexpr const char* to_string(lyapunov_status s)
{
    switch (s) {
        case lyapunov_status::ok: return "ok";
        case lyapunov_status::time_limit: return "time_limit";
        case lyapunov_status::sticking: return "sticking";
        case lyapunov_status::flow_failed: return "flow_failed";
    }
    return "unknown";
}

template <int N>
struct lyapunov_sample {
    double t;           // end of the interval
    vec<N> growth;      // ln(R_ii / r0) of this interval (QR order)
};

template <int N>
struct lyapunov_result {
    lyapunov_status status = lyapunov_status::flow_failed;
    std::string flow_outcome = "ok";
    lyapunov_tdm tdm = lyapunov_tdm::saltation;
    bool impacting = true;            // false: no impact during the transient's quiet time
    vec<N> exponents = vec<N>::Constant(std::numeric_limits<double>::quiet_NaN());  // descending
    double lle_standard_error = std::numeric_limits<double>::quiet_NaN();  // from 8 block means
    double t_start = 0.0;             // start of the averaging window
    double time = 0.0;                // length of the averaging window
    long impacts = 0;                 // impacts of the reference in the window
    long intervals = 0;               // counted intervals
    double divergence_average = std::numeric_limits<double>::quiet_NaN();
    double jump_log_det_rate = std::numeric_limits<double>::quiet_NaN();  // sum ln|det S| / time
    double sum_rule = std::numeric_limits<double>::quiet_NaN();           // the two added
    // second_order: deviations whose flight-time quadratic has no real root (they miss the
    // barrier to second order); trajectory: perturbed orbits whose impact count in an interval
    // differs from the reference's.
    long misses = 0;
    std::vector<lyapunov_sample<N>> history;   // counted intervals
    std::vector<timed_state<N>> section_points; // record_points maxima of the window
    run_stats transient_stats;
    run_stats stats;                           // summed over the interval runs (all orbits)
};

namespace detail {

inline void accumulate(run_stats& into, const run_stats& s)
{
    into.steps += s.steps;
    into.rejected += s.rejected;
    into.rhs_calls += s.rhs_calls;
    into.sections += s.sections;
    into.sticking_phases += s.sticking_phases;
    into.sticking_time += s.sticking_time;
    into.h_min = std::min(into.h_min, s.h_min);
    into.h_max = std::max(into.h_max, s.h_max);
    into.t_final = s.t_final;
}

// Q R of the deviations with R_ii > 0; returns ln(R_ii / scale) and overwrites D by scale Q.
// (In long double: no vectorised kernels, whose AVX-512 code for double trips false
// -Wmaybe-uninitialized errors in GCC 12.)
template <int N>
vec<N> reorthonormalise(mat<N>& D, double scale)
{
    using extended = Eigen::Matrix<long double, N, N>;
    Eigen::HouseholderQR<extended> qr(D.template cast<long double>());
    extended Q = qr.householderQ();
    const extended& QR = qr.matrixQR();
    vec<N> growth;
    for (int i = 0; i < N; ++i) {
        if (QR(i, i) < 0.0L) Q.col(i) = -Q.col(i);
        growth[i] = static_cast<double>(std::log(std::abs(QR(i, i)))) - std::log(scale);
    }
    D = scale * Q.template cast<double>();
    return growth;
}

// Records section maxima of the reference orbit (state part) while `recording`, up to `limit`.
template <int N>
struct section_recorder {
    std::vector<timed_state<N>>* points = nullptr;
    long limit = 0;
    bool recording = false;
    void add(section_kind k, double t, const vec<N>& x) const
    {
        if (recording && k == section_kind::maximum && static_cast<long>(points->size()) < limit)
            points->push_back({t, x});
    }
};

template <class VModel>
struct lyapunov_tangent_observer : flow_observer {
    static constexpr int N = VModel::base_dim;
    const VModel& vm;
    section_recorder<N> sections;
    long impacts = 0;
    double log_det_jumps = 0.0;
    long misses = 0;
    explicit lyapunov_tangent_observer(const VModel& v, section_recorder<N> rec = {}) : vm(v), sections(rec) {}

    flow_control on_section(section_kind k, double t, const typename VModel::state& X)
    {
        sections.add(k, t, VModel::point(X));
        return flow_control::proceed;
    }

    flow_control on_impact(double, const typename VModel::state& pre, const typename VModel::state&)
    {
        ++impacts;
        const vec<N> x = VModel::point(pre);
        log_det_jumps += std::log(std::abs(saltation_matrix(vm.base(), x).determinant()));
        if constexpr (second_order_model<typename VModel::base_model>) {
            if (vm.jump() == impact_tangent::second_order) {
                const auto d = prepare_impact(vm.base(), x);
                const mat<N> Y = VModel::matrix(pre);
                for (int j = 0; j < N; ++j)
                    if (second_order_map(vm.base(), d, vec<N>(vm.deviation_scale() * Y.col(j))).misses)
                        ++misses;
            }
        }
        return flow_control::proceed;
    }
};

template <int N>
struct impact_counter : flow_observer {
    section_recorder<N> sections;
    long impacts = 0;
    flow_control on_section(section_kind k, double t, const vec<N>& x)
    {
        sections.add(k, t, x);
        return flow_control::proceed;
    }
    template <class X>
    flow_control on_impact(double, const X&, const X&)
    {
        ++impacts;
        return flow_control::proceed;
    }
};

template <class Model>
bool admissible(const Model& m, const vec<Model::dim>& x)
{
    const double g = m.guard(x);
    return g > 0.0 || (g == 0.0 && m.guard_gradient(x).dot(m.rhs(x)) >= 0.0);
}

// Decides when the averaging is over.
struct averaging_window {
    const lyapunov_options& opt;
    bool impacting;
    [[nodiscard]] bool done(double time, long impacts) const
    {
        if (opt.time > 0.0) return time >= opt.time * (1.0 - 1e-12);
        if (!impacting) return time >= opt.p0_time * (1.0 - 1e-12);
        return impacts >= opt.impacts;
    }
    [[nodiscard]] bool over_limit(double time) const { return time >= opt.max_time; }
};

template <int N>
void finish_exponents(lyapunov_result<N>& res, const vec<N>& sum)
{
    vec<N> e = sum / res.time;
    std::sort(e.data(), e.data() + N, [](double a, double b) { return a > b; });
    res.exponents = e;
    // Standard error of the largest exponent from 8 consecutive blocks of intervals.
    constexpr int blocks = 8;
    const auto n = static_cast<long>(res.history.size());
    if (n >= 2 * blocks) {
        std::array<double, blocks> means{};
        for (int b = 0; b < blocks; ++b) {
            const long i0 = n * b / blocks, i1 = n * (b + 1) / blocks;
            double s = 0.0;
            for (long i = i0; i < i1; ++i) s += res.history[i].growth.maxCoeff();
            const double dt = res.history[i1 - 1].t - (i0 > 0 ? res.history[i0 - 1].t : res.t_start);
            means[b] = s / dt;
        }
        double mean = 0.0, var = 0.0;
        for (double m : means) mean += m / blocks;
        for (double m : means) var += (m - mean) * (m - mean) / (blocks - 1);
        res.lle_standard_error = std::sqrt(var / blocks);
    }
}

// Algorithm 2 with the tangent flow (saltation or second-order mapping at impacts), from
// x_start at t_begin; fills res (status, window, exponent sums in `sum`).
template <class VM, template <int> class Method, class Model>
void tangent_intervals(const Model& model, const lyapunov_options& opt, const vec<Model::dim>& x_start,
                       double t_begin, lyapunov_result<Model::dim>& res, vec<Model::dim>& sum)
{
    constexpr int N = Model::dim;
    const averaging_window window{opt, res.impacting};
    flow_options fo = opt.flow;
    fo.integration = VM::integration_options(opt.flow.integration);
    fo.track_maxima = opt.record_points > 0;
    fo.track_minima = false;
    // Unit tangent columns standing for deviations of size r0 (see variational_model).
    const VM vm(model,
                opt.tdm == lyapunov_tdm::second_order ? impact_tangent::second_order : impact_tangent::saltation,
                opt.r0);
    typename VM::state X = VM::pack(x_start, mat<N>::Identity(), 0.0);
    double q_start = 0.0, log_det_sum = 0.0;
    double t = t_begin;
    for (long k = 0;; ++k) {
        fo.t_max = t_begin + static_cast<double>(k + 1) * opt.t0;
        hybrid_flow<VM, Method> flow(vm, fo);
        flow.start(t, X);
        lyapunov_tangent_observer<VM> obs(vm, {&res.section_points, opt.record_points, k >= opt.warmup_intervals});
        const outcome o = flow.run(obs);
        accumulate(res.stats, flow.stats());
        if (o != outcome::time_limit) {
            res.flow_outcome = std::string(to_string(o));
            res.status = lyapunov_status::flow_failed;
            return;
        }
        if (flow.stats().sticking_phases > 0) {
            res.status = lyapunov_status::sticking;
            return;
        }
        X = flow.x();
        t = flow.t();
        mat<N> Y = VM::matrix(X);
        const vec<N> growth = reorthonormalise(Y, 1.0);
        X = VM::pack(VM::point(X), Y, VM::divergence_integral(X));
        if (k + 1 == opt.warmup_intervals) q_start = VM::divergence_integral(X);
        if (k < opt.warmup_intervals) continue;
        sum += growth;
        res.history.push_back({t, growth});
        res.impacts += obs.impacts;
        res.misses += obs.misses;
        log_det_sum += obs.log_det_jumps;
        res.intervals = k + 1 - opt.warmup_intervals;
        res.time = t - res.t_start;
        if (window.done(res.time, res.impacts) || window.over_limit(res.time)) {
            res.status = window.done(res.time, res.impacts) ? lyapunov_status::ok : lyapunov_status::time_limit;
            res.jump_log_det_rate = log_det_sum / res.time;
            if constexpr (VM::has_divergence_integral) {
                res.divergence_average = (VM::divergence_integral(X) - q_start) / res.time;
                res.sum_rule = res.divergence_average + res.jump_log_det_rate;
            }
            return;
        }
    }
}

}  // namespace detail

// The spectrum from an initial state: transient, then Algorithm 2 with the chosen mapping.
template <template <int> class Method = dop853, tangent_model Model>
lyapunov_result<Model::dim> lyapunov_spectrum(const Model& model, const vec<Model::dim>& x0,
                                              const lyapunov_options& opt = {})
{
    constexpr int N = Model::dim;
    if (!(opt.r0 > 0.0) || !std::isfinite(opt.r0) || opt.r0 >= 1.0)
        throw input_error("r0 = " + format_double(opt.r0) + " is outside its valid range (0, 1)");
    if (!(opt.t0 > 0.0) || !std::isfinite(opt.t0))
        throw input_error("t0 = " + format_double(opt.t0) + " is outside its valid range (0, inf)");
    if (opt.warmup_intervals < 0) throw input_error("warmup must be >= 0 intervals");
    if (opt.impacts < 1) throw input_error("impacts must be >= 1");
    if (!(opt.time >= 0.0) || !std::isfinite(opt.time)) throw input_error("time must be >= 0 and finite");
    if (!(opt.max_time > 0.0) || !(opt.p0_time > 0.0)) throw input_error("averaging time limits must be > 0");
    if (opt.record_points < 0) throw input_error("record must be >= 0 section points");
    if (opt.tdm == lyapunov_tdm::second_order && !second_order_model<Model>)
        throw input_error("the second-order mapping needs the model's Jacobian and the guard's and reset's second derivatives");

    lyapunov_result<N> res;
    res.tdm = opt.tdm;
    protocol_options po;
    po.transient_impacts = opt.transient_impacts;
    po.record_points = 1;
    po.quiet_time = opt.quiet_time;
    po.flow = opt.flow;
    const protocol_result<N> pr = run_protocol<Method>(model, x0, po);
    res.transient_stats = pr.stats;
    res.impacting = pr.impacting;
    if (pr.status != outcome::ok || pr.points.empty()) {
        res.flow_outcome = std::string(to_string(pr.status));
        return res;
    }
    const vec<N> x_start = pr.points.back().x;
    const double t_begin = pr.points.back().t;
    vec<N> sum = vec<N>::Zero();
    res.t_start = t_begin + static_cast<double>(opt.warmup_intervals) * opt.t0;
    res.stats.h_min = std::numeric_limits<double>::infinity();

    if (opt.tdm != lyapunov_tdm::trajectory) {
        if (opt.divergence)
            detail::tangent_intervals<variational_model<Model, true>, Method>(model, opt, x_start, t_begin, res, sum);
        else
            detail::tangent_intervals<variational_model<Model, false>, Method>(model, opt, x_start, t_begin, res, sum);
        if (res.status == lyapunov_status::flow_failed || res.status == lyapunov_status::sticking) return res;
    } else {
        const detail::averaging_window window{opt, pr.impacting};
        flow_options fo = opt.flow;
        fo.track_maxima = opt.record_points > 0;
        fo.track_minima = false;
        auto end_of_interval = [&](long k) { return t_begin + static_cast<double>(k + 1) * opt.t0; };
        vec<N> xr = x_start;
        mat<N> D = opt.r0 * mat<N>::Identity();
        double t = t_begin;
        for (long k = 0;; ++k) {
            fo.t_max = end_of_interval(k);
            std::array<vec<N>, N + 1> starts;
            starts[0] = xr;
            for (int j = 0; j < N; ++j) {
                // The sign of a deviation vector is free: take the one that starts admissible.
                vec<N> xp = xr + D.col(j);
                if (!detail::admissible(model, xp)) xp = xr - D.col(j);
                starts[j + 1] = xp;
            }
            std::array<vec<N>, N + 1> ends;
            std::array<long, N + 1> impacts{};
            for (int j = 0; j <= N; ++j) {
                hybrid_flow<Model, Method> flow(model, fo);
                flow.start(t, starts[j]);
                detail::impact_counter<N> obs;
                if (j == 0) obs.sections = {&res.section_points, opt.record_points, k >= opt.warmup_intervals};
                const outcome o = flow.run(obs);
                detail::accumulate(res.stats, flow.stats());
                if (o != outcome::time_limit) {
                    res.flow_outcome = std::string(to_string(o));
                    return res;
                }
                if (flow.stats().sticking_phases > 0) {
                    res.status = lyapunov_status::sticking;
                    return res;
                }
                ends[j] = flow.x();
                impacts[j] = obs.impacts;
            }
            t = fo.t_max;
            xr = ends[0];
            for (int j = 0; j < N; ++j) D.col(j) = state_difference(model, ends[j + 1], xr);
            const vec<N> growth = detail::reorthonormalise(D, opt.r0);
            if (k < opt.warmup_intervals) continue;
            sum += growth;
            res.history.push_back({t, growth});
            res.impacts += impacts[0];
            for (int j = 1; j <= N; ++j)
                if (impacts[j] != impacts[0]) ++res.misses;
            res.intervals = k + 1 - opt.warmup_intervals;
            res.time = t - res.t_start;
            if (window.done(res.time, res.impacts) || window.over_limit(res.time)) {
                res.status = window.done(res.time, res.impacts) ? lyapunov_status::ok : lyapunov_status::time_limit;
                break;
            }
        }
    }
    res.stats.impacts = res.impacts;
    detail::finish_exponents(res, sum);
    return res;
}

}  // namespace vimpact
