#pragma once
// The Lyapunov spectrum (analysis/lyapunov.hpp) on an engine model.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include <Eigen/QR>

#include "vimpact/analysis/lyapunov.hpp"
#include "vimpact/engine/stepping.hpp"
#include "vimpact/hybrid/flow.hpp"
#include "vimpact/tangent/variational.hpp"

namespace vimpact::engine {

// Q R of the deviations with R_ii > 0; returns ln(R_ii / scale) and overwrites D by scale Q.
// (In long double: a few more digits for the contracting directions.)
template <int N>
vec<N> reorthonormalise(mat<N>& D, double scale)
{
    using extended = Eigen::Matrix<long double, N, N>;
    Eigen::HouseholderQR<extended> qr(D.template cast<long double>());
    extended Q = qr.householderQ();
    const extended& QR = qr.matrixQR();
    vec<N> growth = sized<vec<N>>(D.rows());
    for (int i = 0; i < D.rows(); ++i) {
        if (QR(i, i) < 0.0L) Q.col(i) = -Q.col(i);
        growth[i] = static_cast<double>(std::log(std::abs(QR(i, i)))) - std::log(scale);
    }
    D = scale * Q.template cast<double>();
    return growth;
}

// Benettin's first deviations: the orthonormal frame of QR(I + 1 1^T), scaled by `scale`. Each
// of its vectors has a part along every direction of the flow, which the identity's need not:
// in a forced oscillator the axes of y and y' lie in the contracting subspace (a deviation of
// the phase alone reaches the neutral one), so from the identity the first deviation gained
// its neutral part from rounding only, and turned towards it over a few hundred intervals,
// which biased the flow's exponent by about ln(rounding) / time (-0.0016 +- 0.0019 over
// 10 000 time units, the other exponents compensating; -1.2e-5 +- 2.2e-4 from this frame).
// The tangent mappings are linear and keep those spaces exactly, so each of their columns
// grows by one exponent whatever the frame: they start from the identity.
template <int N>
mat<N> generic_frame(int n, double scale)
{
    // One dimension: the frame is the axis (and GCC 12 warns of Eigen's QR of a 1 x 1 matrix).
    if constexpr (N == 1) {
        return mat<N>::Constant(1, 1, scale);
    } else {
        mat<N> M = mat<N>::Identity(n, n) + mat<N>::Ones(n, n);
        Eigen::HouseholderQR<mat<N>> qr(M);
        mat<N> Q = qr.householderQ();
        for (int i = 0; i < n; ++i)
            if (qr.matrixQR()(i, i) < 0.0) Q.col(i) = -Q.col(i);
        return scale * Q;
    }
}

// Records section points of the reference orbit (state part) while `recording`, up to `limit`.
struct section_recorder {
    state_series* points = nullptr;
    long limit = 0;
    bool recording = false;
    template <class X>
    void add(double t, const X& x) const
    {
        if (recording && static_cast<long>(points->size()) < limit) points->push_back(t, x);
    }
};

// What one interval of the tangent flow met: its impacts (with the saltation determinants and,
// for the second-order mapping, the deviations that miss the surface) and the section points,
// read from the record of its stepping flow.
template <class VModel, class Record>
struct tangent_tally {
    static constexpr int N = VModel::base_dim;
    long impacts = 0;
    std::vector<long> by_surface;
    double log_det_jumps = 0.0;
    long misses = 0;
    long crossings = 0;  // of switches

    tangent_tally(const VModel& vm, const Record& rec, const section_recorder& sections)
        : by_surface(static_cast<std::size_t>(vm.surface_count()), 0), crossings(static_cast<long>(rec.switchings.size()))
    {
        // A switching surface's jump S (tangent/variational.hpp): det S = det Y+ / det Y-.
        for (const auto& c : rec.switchings)
            log_det_jumps += std::log(std::abs(VModel::matrix(c.post).determinant())) -
                             std::log(std::abs(VModel::matrix(c.pre).determinant()));
        for (const auto& p : rec.points) sections.add(p.t, VModel::point(p.x));
        for (const auto& i : rec.impacts) {
            ++impacts;
            ++by_surface[static_cast<std::size_t>(i.surface)];
            const vec<N> x = VModel::point(i.pre);
            log_det_jumps += std::log(std::abs(saltation_matrix(vm.base(), i.surface, x).determinant()));
            if (vm.jump() == impact_tangent::second_order) {
                const auto d = prepare_impact(vm.base(), i.surface, x);
                const mat<N> Y = VModel::matrix(i.pre);
                for (int j = 0; j < Y.cols(); ++j)
                    if (second_order_map(vm.base(), d, vec<N>(vm.deviation_scale() * Y.col(j))).misses) ++misses;
            }
        }
    }
};

struct impact_counter : flow_observer {
    section_recorder sections;
    long impacts = 0;
    long crossings = 0;  // of switches
    template <class X>
    flow_control on_switch(int, double, const X&, const X&)
    {
        ++crossings;
        return flow_control::proceed;
    }
    std::vector<long> by_surface;
    template <class X>
    flow_control on_section(int, crossing, double t, const X& x)
    {
        sections.add(t, x);
        return flow_control::proceed;
    }
    template <class X>
    flow_control on_impact(int surface, double, const X&, const X&)
    {
        ++impacts;
        if (by_surface.size() <= static_cast<std::size_t>(surface)) by_surface.resize(static_cast<std::size_t>(surface) + 1, 0);
        ++by_surface[static_cast<std::size_t>(surface)];
        return flow_control::proceed;
    }
};

// Decides when the averaging is over. `impacts` counts the crossings of switches too: an
// orbit of a switching system averages over its events as an impacting one does.
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
void finish_exponents(lyapunov_result& res, const vec<N>& sum)
{
    vec<N> e = sum / res.time;
    std::sort(e.data(), e.data() + e.size(), [](double a, double b) { return a > b; });
    res.exponents = to_dynamic(e);
    // Standard error of the largest exponent from 8 consecutive blocks of intervals.
    constexpr int blocks = 8;
    const auto n = static_cast<long>(res.history.size());
    if (n >= 2 * blocks) {
        std::array<double, blocks> means{};
        for (int b = 0; b < blocks; ++b) {
            const long i0 = n * b / blocks, i1 = n * (b + 1) / blocks;
            double s = 0.0;
            for (long i = i0; i < i1; ++i) s += res.history[static_cast<std::size_t>(i)].maxCoeff();
            const double dt = res.history_t[static_cast<std::size_t>(i1 - 1)] -
                              (i0 > 0 ? res.history_t[static_cast<std::size_t>(i0 - 1)] : res.t_start);
            means[static_cast<std::size_t>(b)] = s / dt;
        }
        double mean = 0.0, var = 0.0;
        for (double m : means) mean += m / blocks;
        for (double m : means) var += (m - mean) * (m - mean) / (blocks - 1);
        res.lle_standard_error = std::sqrt(var / blocks);
        // The two halves of the window (4 blocks each) against each other, a two-sample test:
        // with the block variance pooled within the halves (a drift between them must not
        // inflate it), their difference has the standard error sqrt(pooled / 2). A drift
        // (the transient not over, a slow attractor change) shows as a difference of more
        // than 4 of those, and more than 1e-3 of the spectrum's spread, the floor for orbits
        // whose blocks agree to rounding.
        constexpr int half = blocks / 2;
        double first = 0.0, second = 0.0;
        for (int b = 0; b < half; ++b) first += means[static_cast<std::size_t>(b)] / half;
        for (int b = half; b < blocks; ++b) second += means[static_cast<std::size_t>(b)] / half;
        double pooled = 0.0;
        for (int b = 0; b < blocks; ++b) {
            const double d = means[static_cast<std::size_t>(b)] - (b < half ? first : second);
            pooled += d * d / (blocks - 2);
        }
        const double spread = e[0] - e[e.size() - 1];
        res.settled = std::abs(first - second) <= std::max(4.0 * std::sqrt(pooled / 2.0), 1e-3 * spread);
    }
}

inline void add_counts(std::vector<long>& into, const std::vector<long>& more)
{
    if (into.size() < more.size()) into.resize(more.size(), 0);
    for (std::size_t i = 0; i < more.size(); ++i) into[i] += more[i];
}

// Runs one interval of the averaging to its end (t_max); false, with res.status set, when the
// flow ended otherwise or met a contact phase (whose tangent map is not implemented).
template <class Flow, class Observer>
bool run_interval(Flow& flow, Observer& obs, lyapunov_result& res)
{
    const outcome o = flow.run(obs);
    res.stats.add(flow.stats());
    if (o != outcome::time_limit) {
        res.status = o;
        return false;
    }
    if (flow.sticking_phases() > 0) {
        res.status = outcome::sticking;
        return false;
    }
    return true;
}

inline flow_options interval_flow(const lyapunov_options& opt, crossing section_direction)
{
    flow_options fo = opt.flow;
    fo.surfaces = true;
    fo.events.clear();
    if (opt.record_points > 0) fo.events.push_back(flow_event::section(opt.section, section_direction));
    return fo;
}

// Algorithm 2 with the tangent flow (saltation or second-order mapping at impacts), from
// x_start at t_begin; fills res (status, window, exponent sums in `sum`).
template <class VM, engine_model Model>
void tangent_intervals(const Model& model, const lyapunov_options& opt, const vec<Model::dim>& x_start, double t_begin,
                       lyapunov_result& res, vec<Model::dim>& sum)
{
    constexpr int N = Model::dim;
    const averaging_window window{opt, res.impacting};
    flow_options fo = interval_flow(opt, opt.record_points > 0 ? model.section_direction(opt.section) : crossing::down);
    fo.integration = VM::integration_options(opt.flow.integration);
    // Unit tangent columns standing for deviations of size r0 (see variational_model).
    const VM vm(model, opt.tdm == lyapunov_tdm::second_order ? impact_tangent::second_order : impact_tangent::saltation,
                opt.r0);
    typename VM::state X = VM::pack(x_start, mat<N>::Identity(x_start.size(), x_start.size()), 0.0);
    double q_start = 0.0, log_det_sum = 0.0;
    long crossings = 0;  // of switches by the reference in the window
    double t = t_begin;
    // Each interval lands on its end (the steppable tangent's way, system/tangent_system.hpp),
    // where the deviations are re-orthonormalised and the tangent flow starts again.
    fo.t_max = std::numeric_limits<double>::infinity();
    for (long k = 0;; ++k) {
        stepping_flow<VM, dop853> run(vm, fo, t, X);
        run.record().keep_switchings = true;
        const outcome o = run.advance_to(t_begin + static_cast<double>(k + 1) * opt.t0);
        res.stats.add(run.stats());
        if (o != outcome::ok || run.flow().sticking_phases() > 0) {
            res.status = o != outcome::ok ? o : outcome::sticking;
            return;
        }
        const tangent_tally<VM, step_record<typename VM::state>> obs(
            vm, run.record(), {&res.section_points, opt.record_points, k >= opt.warmup_intervals});
        X = run.x();
        t = run.t();
        mat<N> Y = VM::matrix(X);
        const vec<N> growth = reorthonormalise<N>(Y, 1.0);
        X = VM::pack(VM::point(X), Y, VM::divergence_integral(X));
        if (k + 1 == opt.warmup_intervals) q_start = VM::divergence_integral(X);
        if (k < opt.warmup_intervals) continue;
        sum += growth;
        res.history_t.push_back(t);
        res.history.push_back(to_dynamic(growth));
        res.impacts += obs.impacts;
        crossings += obs.crossings;
        add_counts(res.impacts_by_surface, obs.by_surface);
        res.misses += obs.misses;
        log_det_sum += obs.log_det_jumps;
        res.intervals = k + 1 - opt.warmup_intervals;
        res.time = t - res.t_start;
        res.stats.switchings = crossings;  // as stats.impacts: the reference's in the window
        if (window.done(res.time, res.impacts + crossings) || window.over_limit(res.time)) {
            res.status = window.done(res.time, res.impacts + crossings) ? outcome::ok : outcome::time_limit;
            res.jump_log_det_rate = log_det_sum / res.time;
            if constexpr (VM::has_divergence_integral) {
                res.divergence_average = (VM::divergence_integral(X) - q_start) / res.time;
                res.sum_rule = res.divergence_average + res.jump_log_det_rate;
            }
            return;
        }
    }
}

// Benettin's two-trajectory method: N + 1 real orbits per interval.
template <template <int> class Method, engine_model Model>
void trajectory_intervals(const Model& model, const lyapunov_options& opt, const vec<Model::dim>& x_start,
                          double t_begin, lyapunov_result& res, vec<Model::dim>& sum)
{
    constexpr int N = Model::dim;
    const averaging_window window{opt, res.impacting};
    flow_options fo = interval_flow(opt, opt.record_points > 0 ? model.section_direction(opt.section) : crossing::down);
    const int n = state_dim(model);
    vec<N> xr = x_start;
    mat<N> D = generic_frame<N>(n, opt.r0);
    double t = t_begin;
    // The n + 1 orbits' starts, ends and impact counts: on the stack where n is known at
    // compile time.
    using states = std::conditional_t<N == Eigen::Dynamic, std::vector<vec<N>>, std::array<vec<N>, std::max(N, 0) + 1>>;
    using counts = std::conditional_t<N == Eigen::Dynamic, std::vector<long>, std::array<long, std::max(N, 0) + 1>>;
    states starts{}, ends{};
    counts impacts{};
    long crossings = 0;  // of switches by the reference in the window
    if constexpr (N == Eigen::Dynamic) {
        starts.resize(static_cast<std::size_t>(n) + 1);
        ends.resize(static_cast<std::size_t>(n) + 1);
        impacts.resize(static_cast<std::size_t>(n) + 1);
    }
    for (long k = 0;; ++k) {
        fo.t_max = t_begin + static_cast<double>(k + 1) * opt.t0;
        starts[0] = xr;
        for (int j = 0; j < n; ++j) {
            // The sign of a deviation vector is free: take the one that starts admissible.
            vec<N> xp = xr + D.col(j);
            if (!admissible(model, xp)) xp = xr - D.col(j);
            starts[static_cast<std::size_t>(j) + 1] = xp;
        }
        std::fill(impacts.begin(), impacts.end(), 0L);
        for (int j = 0; j <= n; ++j) {
            hybrid_flow<Model, Method> flow(model, fo);
            flow.start(t, starts[static_cast<std::size_t>(j)]);
            impact_counter obs;
            if (j == 0) obs.sections = {&res.section_points, opt.record_points, k >= opt.warmup_intervals};
            if (!run_interval(flow, obs, res)) return;
            ends[static_cast<std::size_t>(j)] = flow.x();
            impacts[static_cast<std::size_t>(j)] = obs.impacts;
            if (j == 0 && k >= opt.warmup_intervals) {
                add_counts(res.impacts_by_surface, obs.by_surface);
                crossings += obs.crossings;
            }
        }
        t = fo.t_max;
        xr = ends[0];
        for (int j = 0; j < n; ++j) D.col(j) = model.state_difference(ends[static_cast<std::size_t>(j) + 1], xr);
        const vec<N> growth = reorthonormalise<N>(D, opt.r0);
        if (k < opt.warmup_intervals) continue;
        sum += growth;
        res.history_t.push_back(t);
        res.history.push_back(to_dynamic(growth));
        res.impacts += impacts[0];
        for (int j = 1; j <= n; ++j)
            if (impacts[static_cast<std::size_t>(j)] != impacts[0]) ++res.misses;
        res.intervals = k + 1 - opt.warmup_intervals;
        res.time = t - res.t_start;
        res.stats.switchings = crossings;  // as stats.impacts: the reference's in the window
        if (window.done(res.time, res.impacts + crossings) || window.over_limit(res.time)) {
            res.status = window.done(res.time, res.impacts + crossings) ? outcome::ok : outcome::time_limit;
            return;
        }
    }
}

// After the transient `pr` (its last recorded point is where the averaging starts).
template <template <int> class Method, engine_model Model>
lyapunov_result lyapunov_after_transient(const Model& model, const simulation& pr, const lyapunov_options& opt)
{
    constexpr int N = Model::dim;
    lyapunov_result res;
    res.tdm = opt.tdm;
    const int n = state_dim(model);
    res.exponents = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
    res.section_points = state_series(n);
    res.transient_stats = pr.stats;
    res.impacting = pr.impacting;
    res.impacts_by_surface.assign(static_cast<std::size_t>(model.surface_count()), 0);
    if (pr.status != outcome::ok || pr.points.empty()) {
        res.status = pr.status;
        return res;
    }
    const vec<N> x_start = pr.points.x(pr.points.size() - 1);
    const double t_begin = pr.points.t(pr.points.size() - 1);
    vec<N> sum = vec<N>::Zero(n);
    res.t_start = t_begin + static_cast<double>(opt.warmup_intervals) * opt.t0;
    res.stats.h_min = std::numeric_limits<double>::infinity();
    if (opt.tdm != lyapunov_tdm::trajectory) {
        if (opt.divergence) tangent_intervals<variational_model<Model, true>>(model, opt, x_start, t_begin, res, sum);
        else tangent_intervals<variational_model<Model, false>>(model, opt, x_start, t_begin, res, sum);
    } else {
        trajectory_intervals<Method>(model, opt, x_start, t_begin, res, sum);
    }
    if (!res.has_exponents()) return res;
    res.stats.impacts = res.impacts;
    finish_exponents<N>(res, sum);
    return res;
}

// The transient of the spectrum: the protocol with one recorded point, the start: the first
// point of the section after the transient (the first post-impact state for a model without
// sections).
inline protocol_options lyapunov_transient(const lyapunov_options& opt, bool has_sections)
{
    protocol_options po;
    po.transient_impacts = opt.transient_impacts;
    po.record_points = 1;
    po.quiet_time = opt.quiet_time;
    po.flow = opt.flow;
    po.method = opt.method;
    po.section = has_sections ? section_choice::crossings(opt.section) : section_choice::impacts();
    return po;
}

}  // namespace vimpact::engine
