// The hybrid flow with several surfaces and event kinds (hybrid/flow.hpp), on small C++
// definitions whose motion is known in closed form:
//  - a particle in free flight between walls (x' = v, v' = 0): impacts at exact times, ties
//    between surfaces that are crossed at the same instant, several surfaces inside one step;
//  - a damped linear oscillator between two stops: impacts and sections placed exactly on a
//    step end (counted once, as heyoka's tests require of its event detection), and the
//    extrema of a gap and of state variables (flow_event::gap_extrema, state_extrema).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <span>
#include <string_view>
#include <vector>

#include "test_support.hpp"
#include "vimpact/hybrid/flow.hpp"
#include "vimpact/model/model.hpp"
#include "vimpact/model/native_model.hpp"
#include "vimpact/system/hybrid_system.hpp"

namespace {

using vimpact::crossing;
using vimpact::flow_control;
using vimpact::flow_event;
using vimpact::flow_options;
using vimpact::outcome;
using vimpact::vec;
using vimpact::vec_t;
using vimpact::test::flow_tolerances;
using X2 = vec<2>;
constexpr double pi = std::numbers::pi;

// Free flight x' = v, v' = 0. Surfaces 0 and 1 are walls on the right, gaps k_i (c_i - x)
// (the scale k_i changes nothing about where the gap vanishes), with resets v -> -v/2 and
// v -> -v/4 so that the surface hit can be told from the state after it; surface 2 is a wall
// on the left at x = c2 with v -> -v. Section j is x = s_j.
struct walls {
    static constexpr std::string_view name = "walls";
    static constexpr std::string_view description = "a particle in free flight between walls";
    static constexpr std::array<vimpact::state_variable, 2> state{{{"x"}, {"v"}}};
    static constexpr std::array<vimpact::parameter, 7> parameters{{
        {"c0", 1.0},
        {"c1", 1.0},
        {"c2", -1.0},
        {"k0", 1.0},
        {"k1", 1.0},
        {"s0", 0.5},
        {"s1", 10.0},
    }};
    static constexpr std::array<vimpact::impact_surface, 3> surfaces{{{"first"}, {"second"}, {"left"}}};
    static constexpr std::array<vimpact::poincare_section, 2> sections{{{"s0", crossing::both}, {"s1", crossing::both}}};
    static constexpr std::array<double, 3> restitution{0.5, 0.25, 1.0};

    explicit walls(std::span<const double> p) : c{p[0], p[1], p[2]}, k{p[3], p[4]}, s{p[5], p[6]} {}

    template <class T>
    vec_t<T, 2> derivatives(const vec_t<T, 2>& X) const
    {
        return {X[1], T(0.0)};
    }
    template <class T>
    T gap(int i, const vec_t<T, 2>& X) const
    {
        if (i == 2) return T(X[0] - c[2]);
        return T(k[i] * (c[i] - X[0]));
    }
    template <class T>
    vec_t<T, 2> reset(int i, const vec_t<T, 2>& X) const
    {
        return {X[0], T(-restitution[static_cast<std::size_t>(i)] * X[1])};
    }
    template <class T>
    T section(int j, const vec_t<T, 2>& X) const
    {
        return T(X[0] - s[j]);
    }

    double c[3], k[2], s[2];
};

// y'' + 2 zeta y' + y = 0 between a right stop (gap c_r - x - beta v: tilted in the phase
// plane when beta != 0) and a left stop (gap x - c_l), both with v -> -r v; section x = s.
struct damped_between {
    static constexpr std::string_view name = "damped_between";
    static constexpr std::string_view description = "a damped linear oscillator between two stops";
    static constexpr std::array<vimpact::state_variable, 2> state{{{"x"}, {"v"}}};
    static constexpr std::array<vimpact::parameter, 6> parameters{{
        {"zeta", 0.0},
        {"right", 10.0},
        {"beta", 0.0},
        {"left", -10.0},
        {"s", 10.0},
        {"r", 0.8},
    }};
    static constexpr std::array<vimpact::impact_surface, 2> surfaces{{{"right"}, {"left"}}};
    static constexpr std::array<vimpact::poincare_section, 1> sections{{{"level", crossing::both}}};

    explicit damped_between(std::span<const double> p)
        : zeta(p[0]), right(p[1]), beta(p[2]), left(p[3]), level(p[4]), r(p[5])
    {
    }

    template <class T>
    vec_t<T, 2> derivatives(const vec_t<T, 2>& X) const
    {
        return {X[1], T(-X[0] - 2.0 * zeta * X[1])};
    }
    template <class T>
    T gap(int i, const vec_t<T, 2>& X) const
    {
        return i == 0 ? T(right - X[0] - beta * X[1]) : T(X[0] - left);
    }
    template <class T>
    vec_t<T, 2> reset(int, const vec_t<T, 2>& X) const
    {
        return {X[0], T(-r * X[1])};
    }
    template <class T>
    T section(int, const vec_t<T, 2>& X) const
    {
        return T(X[0] - level);
    }

    double zeta, right, beta, left, level, r;
};

using walls_model = vimpact::native_model<walls>;
using oscillator_model = vimpact::native_model<damped_between>;

struct impact_record {
    int surface;
    double t;
    X2 pre, post;
};
struct event_record {
    int event;
    crossing direction;
    double t;
    X2 x;
};

// Records impacts and events in the order the flow reports them; with `single_steps` every
// run() returns after one step, so that the caller sees every step end.
struct recorder : vimpact::flow_observer {
    bool single_steps = false;
    std::vector<impact_record> impacts;
    std::vector<event_record> events;
    std::vector<double> order;  // times of impacts and events, in reporting order

    flow_control on_impact(int surface, double t, const X2& pre, const X2& post)
    {
        impacts.push_back({surface, t, pre, post});
        order.push_back(t);
        return flow_control::proceed;
    }
    flow_control on_section(int event, crossing direction, double t, const X2& x)
    {
        events.push_back({event, direction, t, x});
        order.push_back(t);
        return flow_control::proceed;
    }
    flow_control on_step_end(double) { return single_steps ? flow_control::stop : flow_control::proceed; }
};

template <class D>
vimpact::native_model<D> make(std::vector<double> p)
{
    return vimpact::native_model<D>(std::span<const double>(p));
}

template <class Model>
recorder run(const Model& m, const flow_options& o, const X2& x0, vimpact::run_stats* stats = nullptr,
             outcome* status = nullptr)
{
    vimpact::hybrid_flow<Model> flow(m, o);
    flow.start(0.0, x0);
    recorder rec;
    const outcome st = flow.run(rec);
    if (stats) *stats = flow.stats();
    if (status) *status = st;
    return rec;
}

// Every step end (t, x) of a run up to t_end, one step per run() call.
template <class Model>
std::vector<std::pair<double, X2>> step_ends(const Model& m, const flow_options& o, const X2& x0, double t_end)
{
    vimpact::hybrid_flow<Model> flow(m, o);
    flow.start(0.0, x0);
    recorder rec;
    rec.single_steps = true;
    std::vector<std::pair<double, X2>> out;
    while (flow.t() < t_end && flow.run(rec) == outcome::ok) out.emplace_back(flow.t(), flow.x());
    return out;
}

}  // namespace

// ---- several surfaces ---------------------------------------------------------------------

// Two right walls at the same place (gaps 1 - x and 2 (1 - x)) are crossed at the same
// instant: the tie goes to the lower index, whichever gap is scaled, and the other wall does
// not fire at the same instant after the reset (its gap is 0 and opening). From (0, 1): right
// walls at t = 1 (v -> -1/2), left wall at t = 5 (v -> 1/2), right walls at t = 9.
TEST(FlowSurfaces, TieAtTheSameInstantGoesToTheLowerIndex)
{
    for (const auto& scales : {std::array<double, 2>{1.0, 2.0}, std::array<double, 2>{2.0, 1.0}}) {
        const auto m = make<walls>({1.0, 1.0, -1.0, scales[0], scales[1], 0.5, 10.0});
        vimpact::run_stats stats;
        const recorder rec = run(m, flow_tolerances(1e-12, 10.0), X2(0.0, 1.0), &stats);
        ASSERT_EQ(rec.impacts.size(), 3u) << "scales " << scales[0] << ", " << scales[1];
        const std::array<int, 3> surface{0, 2, 0};
        const std::array<double, 3> t{1.0, 5.0, 9.0};
        const std::array<double, 3> v_after{-0.5, 0.5, -0.25};
        for (std::size_t k = 0; k < 3; ++k) {
            EXPECT_EQ(rec.impacts[k].surface, surface[k]) << "impact " << k;
            EXPECT_NEAR(rec.impacts[k].t, t[k], 1e-13) << "impact " << k;
            EXPECT_EQ(rec.impacts[k].post[1], v_after[k]) << "impact " << k;
        }
        EXPECT_EQ(stats.impacts_by_surface, (std::vector<long>{2, 0, 1}));
    }
}

// Two right walls 0.001 apart inside one step (fixed steps of 4): the first crossed in time
// wins whatever its index, the rest of the step after it is discarded with the trajectory
// it belonged to, so the far wall is never hit; a section crossing before the impact in the
// same step is reported before it, and one beyond the near wall (x = 1.0005) never.
TEST(FlowSurfaces, FirstSurfaceInTimeWinsInsideOneStep)
{
    for (const bool near_first : {true, false}) {
        const double c0 = near_first ? 1.0 : 1.001, c1 = near_first ? 1.001 : 1.0;
        const auto m = make<walls>({c0, c1, -1.0, 1.0, 1.0, 0.5, 1.0005});
        flow_options o = flow_tolerances(1e-12, 10.0);
        o.integration.h_init = 4.0;
        o.integration.h_max = 4.0;
        o.events = {flow_event::section(0, crossing::both), flow_event::section(1, crossing::both)};
        vimpact::run_stats stats;
        const recorder rec = run(m, o, X2(0.0, 1.0), &stats);
        ASSERT_EQ(stats.rejected, 0);  // the first step is [0, 4]: both walls inside it
        ASSERT_GE(rec.impacts.size(), 1u);
        const int near = near_first ? 0 : 1;
        const double v1 = near_first ? 0.5 : 0.25;  // speed after the near wall
        EXPECT_EQ(rec.impacts[0].surface, near);
        EXPECT_NEAR(rec.impacts[0].t, 1.0, 1e-14);
        EXPECT_EQ(rec.impacts[0].pre[0], 1.0);  // put exactly on the near wall
        EXPECT_EQ(rec.impacts[0].post[1], -v1);
        // Then the left wall at 1 + 2 / v1, and nothing else before t = 10.
        ASSERT_EQ(rec.impacts.size(), near_first ? 3u : 2u);
        EXPECT_EQ(rec.impacts[1].surface, 2);
        EXPECT_NEAR(rec.impacts[1].t, 1.0 + 2.0 / v1, 1e-13);
        if (near_first) {
            EXPECT_EQ(rec.impacts[2].surface, near);
            EXPECT_NEAR(rec.impacts[2].t, 9.0, 1e-13);
        }
        std::vector<long> by_surface{0, 0, 1};
        by_surface[static_cast<std::size_t>(near)] = near_first ? 2 : 1;
        EXPECT_EQ(stats.impacts_by_surface, by_surface);

        // Section x = 0.5: up at 0.5, down at 1 + 0.5 / v1, up again at 1 + 2 / v1 + 1.5 / v1
        // (t = 8 when v1 = 1/2; 13 > 10 when v1 = 1/4). Section x = 1.0005: never.
        std::vector<double> expected{0.5, 1.0 + 0.5 / v1};
        if (near_first) expected.push_back(8.0);
        ASSERT_EQ(rec.events.size(), expected.size());
        for (std::size_t k = 0; k < expected.size(); ++k) {
            EXPECT_EQ(rec.events[k].event, 0);
            EXPECT_EQ(rec.events[k].direction, k % 2 == 0 ? crossing::up : crossing::down);
            EXPECT_NEAR(rec.events[k].t, expected[k], 1e-13);
            EXPECT_EQ(rec.events[k].x[0], 0.5);
        }
        for (std::size_t k = 1; k < rec.order.size(); ++k) EXPECT_LE(rec.order[k - 1], rec.order[k]);
    }
}

// ---- events exactly on a step end ----------------------------------------------------------

// The undamped oscillator x = sin t from (0, 1). A first run with the stops far away gives
// the step ends (t_k, x_k). Placing the right stop exactly at x_k (rising there) makes its gap
// exactly 0.0 at the end of step k in a second run (the steps up to t_k are the same: the
// surfaces do not enter the vector field). The impact belongs to the step that ends there:
// reported once, at t_k exactly, with the step end as the pre-impact state; the next step
// starts on the stop with the gap opening and reports nothing. The same for the left stop
// at a step end x_m of the second run after the rebound (falling there), in a third run.
TEST(FlowSurfaces, ImpactsExactlyAtAStepEndAreCountedOnce)
{
    const flow_options o = flow_tolerances(1e-10, 20.0);
    const X2 x0(0.0, 1.0);
    const auto ends = step_ends(make<damped_between>({0.0, 10.0, 0.0, -10.0, 10.0, 0.8}), o, x0, 3.0);
    std::size_t k = 0;
    while (k < ends.size() && !(ends[k].second[0] > 0.2 && ends[k].second[1] > 0.0)) ++k;
    ASSERT_LT(k, ends.size());
    ASSERT_GT(k, 0u);
    const double t_k = ends[k].first, c_r = ends[k].second[0];
    // Precondition: x_k is the end of a step, not a grid point the method would reach anyway.
    ASSERT_GT(t_k - ends[k - 1].first, 1e-3);

    const auto second = make<damped_between>({0.0, c_r, 0.0, -10.0, 10.0, 0.8});
    const auto ends2 = step_ends(second, o, x0, t_k + 4.0);
    std::size_t m = 0;
    while (m < ends2.size() && !(ends2[m].first > t_k && ends2[m].second[0] < -0.1 && ends2[m].second[1] < 0.0)) ++m;
    ASSERT_LT(m, ends2.size());
    const double t_m = ends2[m].first, c_l = ends2[m].second[0];
    EXPECT_EQ(ends2[k].first, t_k);  // the same steps up to the impact

    const auto third = make<damped_between>({0.0, c_r, 0.0, c_l, 10.0, 0.8});
    vimpact::run_stats stats;
    const recorder rec = run(third, flow_tolerances(1e-10, t_m + 0.05), x0, &stats);
    ASSERT_EQ(rec.impacts.size(), 2u);
    EXPECT_EQ(rec.impacts[0].surface, 0);
    EXPECT_EQ(rec.impacts[0].t, t_k);
    EXPECT_EQ(rec.impacts[0].pre, ends[k].second);
    EXPECT_EQ(rec.impacts[0].post[1], -0.8 * ends[k].second[1]);
    EXPECT_EQ(rec.impacts[1].surface, 1);
    EXPECT_EQ(rec.impacts[1].t, t_m);
    EXPECT_EQ(rec.impacts[1].pre, ends2[m].second);
    EXPECT_EQ(stats.impacts_by_surface, (std::vector<long>{1, 1}));
    // The first impact against the closed form: sin t = c_r.
    EXPECT_NEAR(t_k, std::asin(c_r), 1e-8);
}

// A section x = x_j placed on a step end is crossed there: one crossing, at t_j exactly, on
// the section exactly; the next step starts on it and does not report it again.
TEST(FlowSurfaces, SectionExactlyAtAStepEndIsCountedOnce)
{
    const flow_options o = flow_tolerances(1e-10, 20.0);
    const X2 x0(-1.0, 0.0);
    const auto ends = step_ends(make<damped_between>({0.0, 10.0, 0.0, -10.0, 10.0, 0.8}), o, x0, 3.0);
    std::size_t j = 0;
    while (j < ends.size() && !(ends[j].second[0] > -0.5 && ends[j].second[1] > 0.0)) ++j;
    ASSERT_LT(j, ends.size());
    const double t_j = ends[j].first, level = ends[j].second[0];
    ASSERT_LT(t_j + 0.5, pi);  // x = -cos t rises through the level once before t_j + 0.5

    const auto m = make<damped_between>({0.0, 10.0, 0.0, -10.0, level, 0.8});
    flow_options oe = flow_tolerances(1e-10, t_j + 0.5);
    oe.events = {flow_event::section(0, crossing::both)};
    vimpact::run_stats stats;
    const recorder rec = run(m, oe, x0, &stats);
    ASSERT_EQ(rec.events.size(), 1u);
    EXPECT_EQ(stats.sections, 1);
    EXPECT_EQ(rec.events[0].direction, crossing::up);
    EXPECT_EQ(rec.events[0].t, t_j);
    EXPECT_EQ(rec.events[0].x[0], level);
    EXPECT_NEAR(rec.events[0].x[1], ends[j].second[1], 1e-15);
}

// ---- extrema of gaps and state variables ---------------------------------------------------

// The damped oscillator (zeta = 0.05) from (1, 0), surfaces off: with w = sqrt(1 - zeta^2),
//   x = e^{-zeta t} (cos wt + zeta/w sin wt),  v = -e^{-zeta t} sin(wt) / w,
//   x'' = e^{-zeta t} (zeta sin wt - w cos wt) / w.
// Extrema of x (v = 0): t = k pi / w, minima for odd k. Extrema of v (x'' = 0):
// tan(wt) = w / zeta, the first a minimum. Extrema of u = x + beta v, i.e. of the tilted gap
// g = c - u (its minima are the maxima of u): u' = e^{-zeta t}/w ((beta zeta - 1) sin wt -
// beta w cos wt) = 0, u decreasing at t = 0, so the first is a minimum of u (a maximum of g).
TEST(FlowSurfaces, GapAndStateExtremaMatchClosedForms)
{
    const double zeta = 0.05, beta = 0.5, T = 40.0;
    const double w = std::sqrt(1.0 - zeta * zeta);
    const auto m = make<damped_between>({zeta, 5.0, beta, -5.0, 10.0, 0.8});
    flow_options o = flow_tolerances(1e-12, T);
    o.surfaces = false;
    o.events = {flow_event::gap_extrema(0, crossing::up), flow_event::gap_extrema(0, crossing::down),
                flow_event::gap_extrema(1, crossing::both), flow_event::state_extrema(0, crossing::up),
                flow_event::state_extrema(1, crossing::both)};
    const recorder rec = run(m, o, X2(1.0, 0.0));
    auto exact = [&](double t) {
        const double e = std::exp(-zeta * t), c = std::cos(w * t), s = std::sin(w * t);
        return X2(e * (c + zeta / w * s), -e * s / w);
    };
    // The roots t = (theta0 + k pi) / w < T, theta0 in (0, pi], with the direction of the
    // first one; the following ones alternate.
    struct expected_event {
        double t;
        crossing direction;
    };
    auto roots = [&](double theta0, crossing first) {
        std::vector<expected_event> out;
        for (int k = 0; (theta0 + k * pi) / w < T; ++k) {
            const bool same = k % 2 == 0;
            const crossing other = first == crossing::up ? crossing::down : crossing::up;
            out.push_back({(theta0 + k * pi) / w, same ? first : other});
        }
        return out;
    };
    const double theta_u = std::atan2(beta * w, beta * zeta - 1.0);  // in (pi/2, pi) here
    std::vector<std::vector<expected_event>> want(5);
    for (const auto& r : roots(theta_u, crossing::down)) {  // gap maxima first (u minima)
        if (r.direction == crossing::up) want[0].push_back(r);
        else want[1].push_back(r);
    }
    want[2] = roots(pi, crossing::up);  // minima of x (x - left) at t = pi / w first
    for (const auto& r : want[2])
        if (r.direction == crossing::up) want[3].push_back(r);
    want[4] = roots(std::atan(w / zeta), crossing::up);
    ASSERT_GE(want[0].size(), 5u);

    std::vector<std::vector<event_record>> got(5);
    for (const auto& e : rec.events) got[static_cast<std::size_t>(e.event)].push_back(e);
    for (std::size_t ev = 0; ev < 5; ++ev) {
        ASSERT_EQ(got[ev].size(), want[ev].size()) << "event " << ev;
        for (std::size_t k = 0; k < want[ev].size(); ++k) {
            EXPECT_NEAR(got[ev][k].t, want[ev][k].t, 1e-10) << "event " << ev << " #" << k;
            EXPECT_EQ(got[ev][k].direction, want[ev][k].direction) << "event " << ev << " #" << k;
            EXPECT_LT(vimpact::test::max_abs_diff(got[ev][k].x, exact(got[ev][k].t)), 1e-10) << "event " << ev;
        }
    }
    // Extrema of x are put exactly on v = 0 (the rate of x is a coordinate).
    for (std::size_t ev : {2u, 3u})
        for (const auto& e : got[ev]) EXPECT_EQ(e.x[1], 0.0);
}

// A block at rest on a floor (a contact phase that never releases) slides at unit speed
// between walls at x = 0 and x = 1 (restitution 1/2 on vx). The walls act during the contact
// phase as in flight: the block hits them at t_k = 0.5 + 2^k - 2 from x = 0.5, stays on the
// floor and between the walls. (The contact step ignored other surfaces: the block slid
// through the wall to x = 1e6, outcome time_limit, no impact.)
TEST(FlowSurfaces, SurfacesActDuringAContactPhase)
{
    const auto m = vimpact::model::from_toml(R"(
name = "sliding_block"
state = ["x", "vx", "y", "vy"]
[parameters]
r = { default = 0.5 }
[derivatives]
x = "vx"
vx = "0"
y = "vy"
vy = "-1"
[[surfaces]]
name = "floor"
gap = "y"
reset = { vy = "-r*vy" }
sticking = { release = "-1", rest = { y = "0", vy = "0" }, derivatives = { y = "0", vy = "0" } }
[[surfaces]]
name = "right"
gap = "1 - x"
reset = { vx = "-r*vx" }
[[surfaces]]
name = "left"
gap = "x"
reset = { vx = "-r*vx" }
)");
    vimpact::hybrid_system_options o;
    o.flow = flow_tolerances(1e-12, 100.0);
    vimpact::hybrid_system s(m, Eigen::Vector4d(0.5, 1.0, 0.0, 0.0), 0.0, o);
    ASSERT_TRUE(s.in_contact());
    std::vector<double> times;
    std::vector<int> surfaces;
    for (int steps = 0; times.size() < 4 && steps < 10000; ++steps) {
        ASSERT_EQ(s.step(), outcome::ok);
        const auto& imp = s.impacts();
        for (std::size_t k = 0; k < imp.size(); ++k) {
            times.push_back(imp.pre.t(k));
            surfaces.push_back(imp.surface[k]);
        }
        EXPECT_TRUE(s.in_contact()) << "t = " << s.time();
        EXPECT_GE(s.state()[0], -1e-12) << "t = " << s.time();
        EXPECT_LE(s.state()[0], 1.0 + 1e-12) << "t = " << s.time();
    }
    ASSERT_EQ(times.size(), 4U);
    for (int k = 1; k <= 4; ++k) {
        EXPECT_NEAR(times[static_cast<std::size_t>(k - 1)], 0.5 + std::ldexp(1.0, k) - 2.0, 1e-12) << k;
        EXPECT_EQ(surfaces[static_cast<std::size_t>(k - 1)], k % 2 == 1 ? 1 : 2) << k;
    }
    EXPECT_EQ(s.stats().impacts_by_surface, (std::vector<long>{0, 2, 2}));
}
