#pragma once
// Many runs of one C++ model definition integrated in lock-step across SIMD lanes: each lane
// is another job (its own parameters, initial state, step size, events, impacts and contact
// phases). The free steps of all lanes are tried at once: the vector field, the Runge-Kutta
// stages, the error norm and the step-size controller run on `lanes` (core/lanes.hpp), the
// same arithmetic the scalar integrator does, so every lane gets the bits it would get alone.
// Whatever follows an accepted step (events, impacts, resets, the chattering rule, the
// observer) is the scalar hybrid flow of that lane, unchanged: the lane hands the step to its
// flow's integrator (accept_external) and the flow goes on from there; a step with nothing to
// follow it (keeps_quiet below) waits in the lane until the flow next needs it. A lane in a contact
// phase steps on its own until it is released. A lane whose job ends takes the next job from
// its source (in the job loop, the queue all the threads share), so lanes stay busy when jobs
// differ in length.
//
// What a definition needs: D::lanes_definition, the same definition with its parameters held
// as lanes and constructible from them; its vector field must compile for T = lanes
// (core/lanes.hpp says how). The built-in models have it. A model file's table brings its own
// lanes (model/table_lanes.hpp: its stages, gaps, sections and switches compiled in its
// binary), given to run_in_lanes_of as a lanes definition with an attempt() of its own; with
// switches, each lane's field is that of its own sides, read from its flow's pinned context.
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "vimpact/core/lanes.hpp"
#include "vimpact/hybrid/flow.hpp"
#include "vimpact/integrate/event_resolution.hpp"
#include "vimpact/hybrid/lanes_counts.hpp"
#include "vimpact/model/native_model.hpp"

namespace vimpact {

template <class D>
concept lanes_capable = model_definition<D> && switch_count_of<D>() == 0 && requires(std::span<const lanes> p, const vec_t<lanes, definition_dim<D>>& x) {
    { typename D::lanes_definition(p).derivatives(x) } -> std::convertible_to<vec_t<lanes, definition_dim<D>>>;
};

// A lanes definition whose gaps and sections, with their gradients, also run in lanes: the
// driver then screens every lane's step for crossings itself, and only the lanes where one is
// possible go through their flow's event handling.
template <class L, int N>
concept lanes_screenable = requires(const L& d, const vec_t<lanes, N>& x) {
    { d.gap(0, x) } -> std::convertible_to<lanes>;
    { d.gap_gradient(0, x) } -> std::convertible_to<vec_t<lanes, N>>;
    { d.section(0, x) } -> std::convertible_to<lanes>;
    { d.section_gradient(0, x) } -> std::convertible_to<vec_t<lanes, N>>;
};

namespace detail {

// grad . f, and whether its sign is beyond doubt: the flow computes the same rate with
// another order of the sum, so a rate within rounding of zero is not trusted.
template <int N>
lanes rate(const vec_t<lanes, N>& grad, const vec_t<lanes, N>& f, lane_mask& sure)
{
    lanes r(0.0), a(0.0);
    for (int i = 0; i < N; ++i) {
        const lanes t = grad[i] * f[i];
        r += t;
        a += abs(t);
    }
    sure = sure && abs(r) > 1e-10 * a;
    return r;
}

// two_interior_extrema (integrate/event_location.hpp) with a margin: also true where the flow's
// own test, on rates summed in another order, could be true. Such a step goes through the flow.
inline lane_mask maybe_two_interior_extrema(const lanes& v0, const lanes& v1, const lanes& r0, const lanes& r1)
{
    const lanes zero(0.0), d = v1 - v0;
    const lanes b = 3.0 * d - 2.0 * r0 - r1, c = r0 + r1 - 2.0 * d;
    const lanes u = -b / (3.0 * c), turn = r0 - b * b / (3.0 * c);
    const lanes margin = 1e-9 * (abs(r0) + abs(turn - r0));
    const lane_mask near_turn = (r0 > zero && r1 > zero && turn < margin) || (r0 < zero && r1 < zero && turn > -margin);
    // c = 0 (no turn at all) gives no NaN here: b^2 / 0 is infinite, and so is u unless b = 0.
    return near_turn && !(u <= lanes(-1e-9)) && !(u >= lanes(1.0 + 1e-9));
}

// Whether gap i (section k) of a lanes definition is affine in the state: declared in its
// spec (model/spec.hpp), or said by the definition at run time (a model file's table).
template <class L>
bool lanes_gap_affine(const L& def, int i)
{
    if constexpr (requires { def.gap_affine(i); }) return def.gap_affine(i);
    else return L::surfaces[static_cast<std::size_t>(i)].affine;
}
template <class L>
bool lanes_section_affine(const L& def, int k)
{
    if constexpr (requires { def.section_affine(k); }) return def.section_affine(k);
    else return L::sections[static_cast<std::size_t>(k)].affine;
}

// The gaps and sections of a lanes definition at one state, with their gradients: as the
// definition computes them one at a time (inlined), or all in one call where it has one
// (point(x, slot): a model file's table, model/table_lanes.hpp, whose slot 0 and 1 hold two
// states at once).
template <class L, int N>
struct lanes_point {
    const L* def;
    const vec_t<lanes, N>* x;
    [[nodiscard]] lanes gap(int i) const { return def->gap(i, *x); }
    [[nodiscard]] vec_t<lanes, N> gap_gradient(int i) const { return def->gap_gradient(i, *x); }
    [[nodiscard]] lanes section(int k) const { return def->section(k, *x); }
    [[nodiscard]] vec_t<lanes, N> section_gradient(int k) const { return def->section_gradient(k, *x); }
};
template <int N, class L>
auto lanes_point_at(const L& def, const vec_t<lanes, N>& x, int slot)
{
    if constexpr (requires { def.point(x, slot); }) return def.point(x, slot);
    else return lanes_point<L, N>{&def, &x};
}

// Where the step of size h from (x0, f0) to (x1, f1) is quiet: every gap positive at one end
// at least and not crossed, every watched section not crossed in its directions, by the
// flow's own rule (hybrid_flow::after_free_step) with rates of certain sign; and every gap or
// section the flow checks for resolution (not declared affine: model/spec.hpp) resolved on the
// step, by the flow's own check (integrate/event_resolution.hpp), which takes the other steps
// back.
template <int N, class L>
lane_mask quiet_steps(const L& def, const flow_options& opt, int surfaces, const vec_t<lanes, N>& x0,
                      const vec_t<lanes, N>& f0, const vec_t<lanes, N>& x1, const vec_t<lanes, N>& f1, const lanes& h)
{
    const lanes zero(0.0);
    lane_mask quiet = zero == zero;
    std::array<std::optional<vec_t<lanes, N>>, 2> xc;
    const auto hermite = [&](int point) -> const vec_t<lanes, N>& {
        auto& p = xc[static_cast<std::size_t>(point)];
        if (!p) {
            p.emplace();
            event_resolution::hermite_state<N>(point, x0, f0, x1, f1, h, *p);
        }
        return *p;
    };
    // With half the tolerance: the flow's own check, on rates summed in another order, then
    // finds the step resolved too; a lane nearer the limit goes through the flow, which decides.
    const auto resolved = [&](const lanes& v0, const lanes& r0, const lanes& v1, const lanes& r1, auto&& value) {
        lane_mask ok = v0 == v0 || v0 != v0;
        for (int point = 0; point < 2; ++point) {
            const auto d = event_resolution::deviation_at(point, v0, r0 * h, v1, r1 * h, value(hermite(point)));
            ok = ok && d.error <= 0.5 * d.allowed;
        }
        return ok;
    };
    const auto no_crossing = [&](const lanes& v0, const lanes& v1, const lanes& r0, const lanes& r1) {
        return !down_crossing_possible(v0, v1, r0, r1) && !maybe_two_interior_extrema(v0, v1, r0 * h, r1 * h);
    };
    const auto p0 = lanes_point_at<N>(def, x0, 0), p1 = lanes_point_at<N>(def, x1, 1);
    if (opt.surfaces)
        for (int i = 0; i < surfaces; ++i) {
            const lanes v0 = p0.gap(i), v1 = p1.gap(i);
            const lanes r0 = rate<N>(p0.gap_gradient(i), f0, quiet), r1 = rate<N>(p1.gap_gradient(i), f1, quiet);
            quiet = quiet && (v0 > zero || v1 > zero) && no_crossing(v0, v1, r0, r1);
            // The flow's rule for a gap maximum inside the step (report_gap_maxima).
            if (opt.gap_maxima) quiet = quiet && !(r0 > zero && r1 <= zero);
            if (!lanes_gap_affine(def, i))
                quiet = quiet && resolved(v0, r0, v1, r1, [&](const vec_t<lanes, N>& y) { return def.gap(i, y); });
        }
    // Switches (a model file's table: side * h_k, the lane's sides): the flow's rule
    // (hybrid_flow::quiet_step), positive at one end at least, not negative at the end, no
    // crossing possible; and resolved on the step where h_k is not affine.
    if constexpr (requires { def.switch_count(); def.switching(0, x0); p0.switching(0); p0.switching_gradient(0); })
        if (opt.switches)
            for (int k = 0; k < def.switch_count(); ++k) {
                const lanes v0 = p0.switching(k), v1 = p1.switching(k);
                const lanes r0 = rate<N>(p0.switching_gradient(k), f0, quiet), r1 = rate<N>(p1.switching_gradient(k), f1, quiet);
                quiet = quiet && (v0 > zero || v1 > zero) && !(v1 < zero) && no_crossing(v0, v1, r0, r1);
                if (!def.switching_affine(k))
                    quiet = quiet && resolved(v0, r0, v1, r1, [&](const vec_t<lanes, N>& y) { return def.switching(k, y); });
            }
    for (const flow_event& e : opt.events) {
        const lanes v0 = p0.section(e.index), v1 = p1.section(e.index);
        const lanes r0 = rate<N>(p0.section_gradient(e.index), f0, quiet), r1 = rate<N>(p1.section_gradient(e.index), f1, quiet);
        if (e.direction != crossing::up) quiet = quiet && no_crossing(v0, v1, r0, r1);
        if (e.direction != crossing::down) quiet = quiet && no_crossing(-v0, -v1, -r0, -r1);
        if (!lanes_section_affine(def, e.index))
            quiet = quiet && resolved(v0, r0, v1, r1, [&](const vec_t<lanes, N>& y) { return def.section(e.index, y); });
    }
    return quiet;
}

}  // namespace detail

// Runs the jobs `next` gives, up to `width` of them at once (at most lane_width), in lanes.
//   next() -> std::optional<long>: the next job, or none for now. A lane whose job ends asks
//     again, and so do the empty lanes then, so a source that had none may still give more
//     (jobs handed out while these run); the call returns when every lane is empty after a
//     none;
//   start(job) -> std::unique_ptr<Run>: a run set up at its initial state; Run has members
//     `flow` (hybrid_flow<native_model<D>, Method>), `obs` (its observer) and
//     finish(outcome) -> Result;
//   parameters(job) -> the job's parameter values (std::span<const double> or a vector);
//   done(job, Result&&): called as jobs end, in the order they end.
// run_in_lanes_of does the same for a lanes definition L of dimension N made by
// make_definition(std::span<const lanes>) from the lanes of what parameters(job) gives.
template <class L, int N, template <int, class = double> class Method, class Make, class Next, class Start,
          class Parameters, class Done>
lanes_counts run_in_lanes_of(int width, Make&& make_definition, Next&& next, Start&& start, Parameters&& parameters,
                             Done&& done)
{
    constexpr int W = lane_width;
    using run_ptr = std::decay_t<decltype(start(0L))>;
    using flow_type = std::decay_t<decltype(start(0L)->flow)>;
    using integrator_type = typename flow_type::integrator_type;
    using method_type = typename integrator_type::method_type;
    using observer_type = std::decay_t<decltype(start(0L)->obs)>;
    using lane_method = Method<N, lanes>;
    using lvec = vec_t<lanes, N>;
    // A quiet step (no crossing possible, see detail::quiet_steps) after which the lane's run
    // would only move its state on, count it, note its gaps and ask its observer whether to go
    // on, is left in the lane's arrays: the run takes over all such steps at once when the lane
    // next needs it (integrator's accept_external_steps, flow's quiet_free_steps). The observer
    // says from what time its step-end call can act (step_end_acts_from); before that, and below
    // the step limit, the steps need nothing from the run. About 95 % of the steps of the
    // paper's protocol are quiet.
    constexpr bool keeps_quiet = lanes_screenable<L, N> &&
                                 requires(const observer_type& o) { { o.step_end_acts_from() } -> std::convertible_to<double>; };
    constexpr double inf = std::numeric_limits<double>::infinity();

    struct slot {
        long job = -1;
        run_ptr run;
        long starts = -1;
        bool rejected_before = false;
        const std::atomic<bool>* cancel = nullptr;
    };
    std::array<slot, W> slots;
    alignas(64) double X[N][W] = {}, F[N][W] = {}, XN[N][W], FN[N][W];
    alignas(64) double Tt[W] = {}, H[W] = {}, LE[W] = {}, RB[W] = {};
    // The steps a lane keeps (keeps_quiet): how many (PEND), the state after the last one (DT,
    // DX, DF, DH, DLE), the last one's start and size (PT, XP, FP, PHT), the extremes of their
    // sizes (HMN, HMX) and each surface's largest gap at their ends (GB); what lets a step be
    // kept: the time from which the observer acts (QT, -infinity: keep none), the run's step
    // count and limit (ST, MS), and whether the lane took part in the trial (FR).
    alignas(64) double PEND[W] = {}, DT[W] = {}, DX[N][W] = {}, DF[N][W] = {}, DH[W] = {}, DLE[W] = {};
    alignas(64) double PT[W] = {}, XP[N][W] = {}, FP[N][W] = {}, PHT[W] = {}, HMN[W], HMX[W];
    alignas(64) double QT[W], ST[W] = {}, MS[W] = {}, FR[W] = {};
    std::fill(std::begin(HMN), std::end(HMN), inf);
    std::fill(std::begin(HMX), std::end(HMX), -inf);
    std::fill(std::begin(QT), std::end(QT), -inf);
    std::vector<std::array<double, W>> GB;
    std::vector<std::array<double, W>> par;
    std::optional<L> def;
    bool params_changed = true;
    lane_method method;
    const int used = std::clamp(width, 1, W);
    int active = 0;
    lanes_counts counts;

    // The stages of lane j, for its interpolant (adaptive_integrator::stage_source).
    struct stage_context {
        const lane_method* method;
        int lane;
    };
    std::array<stage_context, W> stage_contexts;
    for (int j = 0; j < W; ++j) stage_contexts[static_cast<std::size_t>(j)] = {&method, j};
    auto fill_stages = [](const void* c, method_type& m) {
        const auto* sc = static_cast<const stage_context*>(c);
        const auto& src = sc->method->stages();
        auto& dst = m.stages();
        for (std::size_t k = 0; k < src.size(); ++k)
            for (int i = 0; i < N; ++i) dst[k][i] = src[k][i].lane(sc->lane);
        // A stepper that keeps stages of its own between a step and its interpolant (a model
        // file's fused steps) learns that these are the step's.
        if constexpr (requires { m.stages_set_outside(); }) m.stages_set_outside();
    };

    // Lane j's run takes over the steps the lane kept; before any other call on the run.
    auto sync = [&](int j) {
        if constexpr (keeps_quiet) {
            if (PEND[j] == 0.0) return;
            auto& r = *slots[static_cast<std::size_t>(j)].run;
            typename integrator_type::external_steps e{static_cast<long>(PEND[j]), PT[j], PHT[j], DT[j], HMN[j], HMX[j],
                                                       DH[j], DLE[j], {}, {}, {}, {}};
            for (int i = 0; i < N; ++i) {
                e.x_prev[i] = XP[i][j];
                e.f_prev[i] = FP[i][j];
                e.x[i] = DX[i][j];
                e.f[i] = DF[i][j];
            }
            r.flow.integrator().accept_external_steps(e);
            r.flow.quiet_free_steps(r.obs, HMX[j], [&](int i) { return GB[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]; });
            PEND[j] = 0.0;
            HMN[j] = inf;
            HMX[j] = -inf;
            for (auto& g : GB) g[static_cast<std::size_t>(j)] = std::numeric_limits<double>::quiet_NaN();
        }
    };
    // What lets lane j keep its next steps, read from its run (after any call on it).
    auto refresh = [&](int j) {
        if constexpr (keeps_quiet) {
            const auto& r = *slots[static_cast<std::size_t>(j)].run;
            QT[j] = r.flow.mode() == flow_mode::free && !r.obs.wants_segments() ? r.obs.step_end_acts_from() : -inf;
            ST[j] = static_cast<double>(r.flow.integrator().counters().steps);
            MS[j] = static_cast<double>(r.flow.options().max_steps);
        }
    };
    // A model file with switches: its lanes read each lane's sides from the lane's context, which
    // is therefore its flow's pinned context (table_model::pin_sides), read again whenever the
    // run has stepped itself (a crossing changes it).
    auto repin = [&](int j) {
        const auto& m = slots[static_cast<std::size_t>(j)].run->flow.model();
        if constexpr (requires { m.switch_count(); m.context(); m.table(); }) {
            if (m.switch_count() == 0) return;
            const auto* c = static_cast<const double*>(m.context());
            bool changed = false;
            for (std::size_t k = 0; k < par.size(); ++k)
                if (std::bit_cast<std::uint64_t>(par[k][static_cast<std::size_t>(j)]) != std::bit_cast<std::uint64_t>(c[k])) {
                    par[k][static_cast<std::size_t>(j)] = c[k];
                    changed = true;
                }
            // The definition made already takes the lane's new context in place (no
            // allocation at each crossing); one still to be made reads it from par.
            if (changed) {
                if constexpr (requires { def->set_lane_context(j, c); }) {
                    if (def && !params_changed) def->set_lane_context(j, c);
                    else params_changed = true;
                } else {
                    params_changed = true;
                }
            }
        }
    };
    auto load = [&](int j) {
        sync(j);
        refresh(j);
        repin(j);
        const auto& in = slots[static_cast<std::size_t>(j)].run->flow.integrator();
        Tt[j] = in.t();
        H[j] = in.step_size();
        LE[j] = in.log2_err_old();
        for (int i = 0; i < N; ++i) {
            X[i][j] = in.x()[i];
            F[i][j] = in.f()[i];
        }
        RB[j] = 0.0;
        slots[static_cast<std::size_t>(j)].starts = in.starts();
    };
    auto set_parameters = [&](int j, long job) {
        const auto p = parameters(job);
        if (par.empty()) {
            par.resize(p.size());
            // Lanes without a job compute with the first job's values (finite, never read).
            for (std::size_t k = 0; k < p.size(); ++k) par[k].fill(p[k]);
        }
        for (std::size_t k = 0; k < p.size(); ++k) par[k][static_cast<std::size_t>(j)] = p[k];
        params_changed = true;
    };
    // Ends lane j's job with outcome o and takes the next job, if any.
    auto finish = [&](int j, outcome o) {
        auto& s = slots[static_cast<std::size_t>(j)];
        sync(j);
        QT[j] = -inf;
        done(s.job, s.run->finish(o));
        s.run.reset();
        s.job = -1;
        --active;
    };
    // Gives lane j the next job that does not end at once; false when the source has none.
    auto fill = [&](int j) {
        auto& s = slots[static_cast<std::size_t>(j)];
        for (;;) {
            const std::optional<long> taken = next();
            if (!taken) return false;
            const long job = *taken;
            s.run = start(job);
            s.job = job;
            s.rejected_before = false;
            s.cancel = s.run->flow.options().cancel;
            ++active;
            if constexpr (keeps_quiet)
                if (GB.empty())
                    GB.assign(static_cast<std::size_t>(s.run->flow.model().surface_count()),
                              [] {
                                  std::array<double, W> a;
                                  a.fill(std::numeric_limits<double>::quiet_NaN());
                                  return a;
                              }());
            s.run->flow.begin_run();
            if (const auto o = s.run->flow.limit_reached()) {
                finish(j, *o);
                continue;
            }
            set_parameters(j, job);
            load(j);
            return true;
        }
    };
    // After a job ends: its lane, and any lane a source without jobs left empty before.
    bool dry = false;  // the source had no job for an empty lane
    auto refill = [&] {
        dry = false;
        for (int j = 0; j < used; ++j)
            if (!slots[static_cast<std::size_t>(j)].run && !fill(j)) {
                dry = true;
                return;
            }
    };
    // One step of lane j by its own flow; the outcome when the run ends.
    auto step_alone = [&](int j) {
        sync(j);
        auto& r = *slots[static_cast<std::size_t>(j)].run;
        const step_status st = r.flow.step(r.obs);
        std::optional<outcome> o = r.flow.step_taken(st, r.obs);
        if (!o) o = r.flow.limit_reached();
        if (!o) refresh(j);
        return o;
    };
    refill();

    while (active > 0) {
        // Fewer than half the lanes busy and no job for the others: a trial of all the lanes
        // then costs more than the busy ones' trials alone (a trial of 8 lanes of 512 bits costs
        // about 3.1 scalar trials on an AVX-512 machine, of 4 lanes of 256 bits 2.0, of 4 AVX2
        // lanes 2.0: the lane count over bench/output/lanes_isa.jsonl's speed-ups), so each
        // lane between two steps (not after a rejected trial, whose step the
        // lanes' controller finishes) steps on its own, with the bits it has in lanes, for a
        // slice of steps; then the source is asked again, and the lanes go on together from
        // where their flows are, with the jobs that came meanwhile if any.
        if (dry && 2 * active < W) {
            constexpr int slice = 256;
            std::array<bool, W> alone{};
            for (int j = 0; j < W; ++j) {
                if (!slots[static_cast<std::size_t>(j)].run || RB[j] != 0.0) continue;
                for (int k = 0; k < slice; ++k) {
                    ++counts.steps_alone;
                    if (const std::optional<outcome> o = step_alone(j)) {
                        finish(j, *o);
                        break;
                    }
                }
                alone[static_cast<std::size_t>(j)] = slots[static_cast<std::size_t>(j)].run != nullptr;
            }
            refill();
            for (int j = 0; j < W; ++j)
                if (alone[static_cast<std::size_t>(j)] && slots[static_cast<std::size_t>(j)].run) load(j);
            if (active == 0) break;
        }
        // Lanes in a contact phase step on their own; the others take a free step together.
        unsigned free_lanes = 0;
        for (int j = 0; j < W; ++j) {
            auto& s = slots[static_cast<std::size_t>(j)];
            if (!s.run) continue;
            auto& flow = s.run->flow;
            if (flow.mode() != flow_mode::free) {
                if (const std::optional<outcome> o = step_alone(j)) {
                    finish(j, *o);
                    refill();
                }
                continue;
            }
            if (flow.integrator().starts() != s.starts) load(j);
            // A cancelled run's next step goes through its flow, which ends it.
            if (s.cancel && s.cancel->load(std::memory_order_relaxed)) QT[j] = -inf;
            free_lanes |= 1U << static_cast<unsigned>(j);
        }
        for (int j = 0; j < W; ++j) FR[j] = ((free_lanes >> static_cast<unsigned>(j)) & 1U) ? 1.0 : 0.0;
        if (!free_lanes) continue;
        if (params_changed) {
            std::vector<lanes> p(par.size());
            for (std::size_t k = 0; k < par.size(); ++k) p[k] = lanes::load(par[k].data());
            def.emplace(make_definition(std::span<const lanes>(p)));
            params_changed = false;
        }

        const auto& first = *slots[static_cast<std::size_t>(std::countr_zero(free_lanes))].run;
        const auto& opt = first.flow.options();
        const integrator_options& io = opt.integration;
        const controller_constants c = first.flow.integrator().constants();
        // opt and io belong to the first free lane's run, which the loop over the lanes below
        // may end and free: what that loop needs of them is copied here.
        const double t_max = opt.t_max;
        const lanes t = lanes::load(Tt), h = lanes::load(H), le = lanes::load(LE);
        const lane_mask rb = lanes::load(RB) != lanes(0.0);
        const auto plan = plan_trial(t, h, io.h_max, opt.t_max);
        lvec x, f, xn, fn;
        for (int i = 0; i < N; ++i) {
            x[i] = lanes::load(X[i]);
            f[i] = lanes::load(F[i]);
        }
        const auto& field = *def;
        ++counts.lane_trials;
        lanes err2;
        if constexpr (requires { field.attempt(method, x, f, plan.h, io.rtol, io.atol, xn, fn); })
            err2 = field.attempt(method, x, f, plan.h, io.rtol, io.atol, xn, fn);
        else
            err2 = method.attempt([&field](const lvec& y) { return lvec(field.derivatives(y)); }, x, f, plan.h, io.rtol,
                                  io.atol, xn, fn);
        lane_mask finite = is_finite(err2);
        for (int i = 0; i < N; ++i) finite = finite && is_finite(xn[i]) && is_finite(fn[i]);
        const auto out = control_step(c, err2, finite, plan.h, h, plan.clipped, rb, le);
        // Every free lane's state moves on in the arrays; a lane whose flow handles events
        // is read back from its integrator afterwards (a reset, a contact phase).
        const lane_mask accepted_mask = out.accepted;
        const lanes t_new = select(plan.clipped, lanes(opt.t_max), t + plan.h);
        for (int i = 0; i < N; ++i) {
            xn[i].store(XN[i]);
            fn[i].store(FN[i]);
            select(accepted_mask, xn[i], x[i]).store(X[i]);
            select(accepted_mask, fn[i], f[i]).store(F[i]);
        }
        select(accepted_mask, t_new, t).store(Tt);
        out.h_next.store(H);
        out.log2_err_old.store(LE);
        select(accepted_mask, lanes(0.0), lanes(1.0)).store(RB);
        alignas(64) double PH[W], PF[W];
        plan.h.store(PH);
        plan.h_floor.store(PF);
        const unsigned clipped = lane_bits(plan.clipped), underflow = lane_bits(plan.underflow),
                       accepted = lane_bits(accepted_mask), finite_bits = lane_bits(finite);
        unsigned quiet = 0, kept = 0;
        if constexpr (lanes_screenable<L, N>) {
            const bool sections_only = std::all_of(opt.events.begin(), opt.events.end(), [](const flow_event& e) {
                return e.kind == flow_event::source::section;
            });
            if (sections_only) {
                const int surfaces = first.flow.model().surface_count();
                const lane_mask quiet_mask = detail::quiet_steps<N>(field, opt, surfaces, x, f, xn, fn, plan.h);
                quiet = lane_bits(quiet_mask);
                if constexpr (keeps_quiet) {
                    const lanes one(1.0);
                    lane_mask keep = quiet_mask && accepted_mask && !plan.clipped && !plan.underflow &&
                                     lanes::load(FR) == one && t_new < lanes::load(QT) &&
                                     lanes::load(ST) + one < lanes::load(MS);
                    // A gap that is not a number would not merge as the observer's calls one by
                    // one do: such a step goes through the run.
                    if (opt.gap_maxima && opt.surfaces)
                        for (int i = 0; i < surfaces; ++i) keep = keep && is_finite(field.gap(i, xn));
                    kept = lane_bits(keep);
                    if (kept) {
                        const auto keep_new = [&keep](const lanes& v, double* a) { select(keep, v, lanes::load(a)).store(a); };
                        keep_new(lanes::load(PEND) + one, PEND);
                        keep_new(lanes::load(ST) + one, ST);
                        keep_new(t_new, DT);
                        keep_new(t, PT);
                        keep_new(plan.h, PHT);
                        keep_new(out.h_next, DH);
                        keep_new(out.log2_err_old, DLE);
                        keep_new(lane_min(lanes::load(HMN), plan.h), HMN);
                        keep_new(lane_max(lanes::load(HMX), plan.h), HMX);
                        for (int i = 0; i < N; ++i) {
                            keep_new(xn[i], DX[i]);
                            keep_new(fn[i], DF[i]);
                            keep_new(x[i], XP[i]);
                            keep_new(f[i], FP[i]);
                        }
                        if (opt.gap_maxima && opt.surfaces)
                            for (int i = 0; i < surfaces; ++i) {
                                const lanes g = field.gap(i, xn), b = lanes::load(GB[static_cast<std::size_t>(i)].data());
                                // on_gap_maximum's rule, which takes the first value over a NaN.
                                select(keep && !(g <= b), g, b).store(GB[static_cast<std::size_t>(i)].data());
                            }
                    }
                }
            }
        }

        for (unsigned todo = free_lanes & ~kept; todo; todo &= todo - 1) {
            const int j = std::countr_zero(todo);
            sync(j);
            auto& s = slots[static_cast<std::size_t>(j)];
            auto& flow = s.run->flow;
            auto& in = flow.integrator();
            const auto bit = [j](unsigned m) { return ((m >> static_cast<unsigned>(j)) & 1U) != 0; };
            const trial_plan<double, bool> pj{PH[j], bit(clipped), bit(underflow), PF[j]};
            std::optional<outcome> o;
            if (pj.underflow) {
                o = flow.step_taken(step_status::step_underflow, s.run->obs);
            } else if (bit(accepted)) {
                vec<N> xj, fj;
                for (int i = 0; i < N; ++i) {
                    xj[i] = XN[i][j];
                    fj[i] = FN[i][j];
                }
                in.accept_external(pj, t_max, xj, fj, H[j], LE[j],
                                   {fill_stages, &stage_contexts[static_cast<std::size_t>(j)]});
                if (bit(quiet) && !s.run->obs.wants_segments()) {
                    flow.quiet_free_step(s.run->obs);
                    o = flow.step_taken(step_status::ok, s.run->obs);
                    if (!o) o = flow.limit_reached();
                    if (!o) refresh(j);
                } else {
                    const step_status st = flow.free_step_taken(s.run->obs);
                    o = flow.step_taken(st, s.run->obs);
                    if (!o) o = flow.limit_reached();
                    if (!o) load(j);
                }
            } else {
                if (in.reject_external(pj, H[j], bit(finite_bits)))
                    o = flow.step_taken(step_status::non_finite, s.run->obs);
            }
            if (o) {
                finish(j, *o);
                RB[j] = 0.0;
                refill();
            }
        }
    }
    return counts;
}

// The jobs of a C++ definition D in lanes (its lanes_definition).
template <model_definition D, template <int, class = double> class Method, class Next, class Start, class Parameters,
          class Done>
lanes_counts run_in_lanes(int width, Next&& next, Start&& start, Parameters&& parameters, Done&& done)
{
    using L = typename D::lanes_definition;
    return run_in_lanes_of<L, definition_dim<D>, Method>(
        width, [](std::span<const lanes> p) { return L(p); }, std::forward<Next>(next), std::forward<Start>(start),
        std::forward<Parameters>(parameters), std::forward<Done>(done));
}

}  // namespace vimpact
