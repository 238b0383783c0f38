// Tests of the hybrid flow (hybrid/flow.hpp) on the forced linear impact oscillator
//   y' = v, v' = -y - 2 zeta v + F cos(theta), theta' = omega,  impact at y = sigma, v -> -r v,
// whose flight between impacts is known in closed form. With F = 0 it is the free damped
// oscillator y'' + 2 zeta y' + y = 0. The flow runs directly on the native model (the
// engine's templates), with the contact phase the model declares for its barrier.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <tuple>
#include <thread>
#include <vector>

#include "test_support.hpp"
#include "vimpact/hybrid/flow.hpp"
#include "vimpact/model/builtin/forced_impact_oscillator.hpp"
#include "vimpact/model/native_model.hpp"

namespace {

using vimpact::crossing;
using vimpact::flow_control;
using vimpact::flow_event;
using vimpact::flow_options;
using vimpact::hybrid_flow;
using vimpact::outcome;
using vimpact::test::flow_tolerances;
using oscillator_model = vimpact::native_model<vimpact::forced_impact_oscillator>;
using X3 = vimpact::vec<3>;
constexpr double pi = std::numbers::pi;

struct impact_record {
    int surface;
    double t;
    X3 pre, post;
};

// Records everything the flow reports. Events 0 and 1 are the maxima and minima of y (the
// model's sections 0 and 1) when the options watch them (see sections()).
struct recorder : vimpact::flow_observer {
    std::vector<impact_record> impacts;
    std::vector<double> max_t, min_t;
    std::vector<X3> max_x, min_x;
    std::vector<double> step_ends;
    std::vector<double> stick_t, release_t;
    std::vector<X3> stick_x, release_x;
    std::vector<int> stick_surface, release_surface;
    // Admissibility monitor: lowest y seen along the interpolants of all segments (only when
    // `segments` is set, since it makes DOP853 build every interpolant).
    bool segments = false;
    double min_y = std::numeric_limits<double>::infinity();
    double t_min_y = 0.0;

    [[nodiscard]] bool wants_segments() const { return segments; }
    template <class D>
    void on_segment(const D& d, double ta, double tb, vimpact::flow_mode)
    {
        for (int i = 0; i <= 16; ++i) {
            const double t = ta + (tb - ta) * i / 16.0;
            const double y = d.value(t)[0];
            if (y < min_y) {
                min_y = y;
                t_min_y = t;
            }
        }
    }

    flow_control on_impact(int surface, double t, const X3& pre, const X3& post)
    {
        impacts.push_back({surface, t, pre, post});
        return flow_control::proceed;
    }
    flow_control on_section(int event, crossing direction, double t, const X3& x)
    {
        // The maxima are watched downwards, the minima upwards: the direction must say so.
        EXPECT_EQ(direction, event == 0 ? crossing::down : crossing::up);
        if (event == 0) {
            max_t.push_back(t);
            max_x.push_back(x);
        } else {
            min_t.push_back(t);
            min_x.push_back(x);
        }
        return flow_control::proceed;
    }
    void on_stick(int surface, double t, const X3& x)
    {
        stick_surface.push_back(surface);
        stick_t.push_back(t);
        stick_x.push_back(x);
    }
    void on_release(int surface, double t, const X3& x)
    {
        release_surface.push_back(surface);
        release_t.push_back(t);
        release_x.push_back(x);
    }
    flow_control on_step_end(double t)
    {
        step_ends.push_back(t);
        return flow_control::proceed;
    }
};

// Parameters in the model's declared order: zeta, omega, F, sigma, r.
oscillator_model oscillator(double zeta, double F, double omega, double sigma, double r)
{
    const std::array<double, 5> p{zeta, omega, F, sigma, r};
    return oscillator_model(p);
}

// Watch the maxima (section 0, downwards) and minima (section 1, upwards) of y.
flow_options with_extrema(flow_options o)
{
    o.events = {flow_event::section(0, crossing::down), flow_event::section(1, crossing::up)};
    return o;
}

template <template <int> class Method = vimpact::dop853>
recorder run_flow(const oscillator_model& m, const flow_options& o, const X3& x0, outcome* status = nullptr,
                  vimpact::run_stats* stats = nullptr, bool monitor_segments = false)
{
    hybrid_flow<oscillator_model, Method> flow(m, o);
    flow.start(0.0, x0);
    recorder rec;
    rec.segments = monitor_segments;
    const outcome st = flow.run(rec);
    if (status) *status = st;
    if (stats) *stats = flow.stats();
    return rec;
}

// Free damped oscillator y'' + 2 zeta y' + y = 0 in closed form, in long double.
struct damped_closed_form {
    long double zeta;
    long double wd() const { return std::sqrt(1.0L - zeta * zeta); }
    void at(long double s, long double y0, long double v0, long double& y, long double& v) const
    {
        const long double w = wd(), e = std::exp(-zeta * s), c = std::cos(w * s), sn = std::sin(w * s);
        y = e * (y0 * c + (v0 + zeta * y0) / w * sn);
        v = e * (v0 * c - (y0 + zeta * v0) / w * sn);
    }
    // First s > 0 with y(s) = sigma reached from above (scan, then bisection to long double
    // precision). Returns a negative value if there is none before s_max.
    long double next_impact(long double y0, long double v0, long double sigma, long double s_max) const
    {
        const long double ds = 1e-3L;
        long double a = 0.0L;
        for (long double b = ds; b <= s_max; b += ds) {
            long double y, v;
            at(b, y0, v0, y, v);
            if (y - sigma <= 0.0L) {
                long double lo = a, hi = b;
                for (int i = 0; i < 200; ++i) {
                    const long double mid = 0.5L * (lo + hi);
                    at(mid, y0, v0, y, v);
                    if (y - sigma > 0.0L) lo = mid;
                    else hi = mid;
                }
                return 0.5L * (lo + hi);
            }
            a = b;
        }
        return -1.0L;
    }
};

}  // namespace

// Undamped free oscillator from (1, 0): y = cos t. With the barrier at -1/2 the first impact
// is at t = arccos(-1/2) = 2 pi/3 with v- = -sin(2 pi/3). After the reset (y, v) =
// (sigma, r u) the orbit is A cos(s - phi) with A cos phi = sigma, A sin phi = r u, so
// phi = atan2(r u, sigma) in (pi/2, pi); it returns to sigma after s = 2 phi with the same
// speed (time reversal). So impact k has speed u_k = (sqrt 3 / 2) r^k and the next one
// follows after 2 atan2(r u_k, sigma).
template <template <int> class Method>
void check_undamped_impact_sequence()
{
    const double sigma = -0.5, r = 0.8;
    const auto m = oscillator(0.0, 0.0, 0.8, sigma, r);
    std::vector<double> t_exact, u_exact;
    double t = 2.0 * pi / 3.0, u = std::sqrt(3.0) / 2.0;
    for (int k = 0; k < 6; ++k) {
        t_exact.push_back(t);
        u_exact.push_back(u);
        t += 2.0 * std::atan2(r * u, sigma);
        u *= r;
    }
    const double t_max = 0.5 * (t_exact[5] + t);  // between the 6th and the 7th impact
    outcome st;
    vimpact::run_stats stats;
    const recorder rec = run_flow<Method>(m, flow_tolerances(1e-12, t_max), X3(1.0, 0.0, 0.0), &st, &stats);
    EXPECT_EQ(st, outcome::time_limit);
    ASSERT_EQ(rec.impacts.size(), 6u);
    EXPECT_EQ(stats.impacts, 6);
    EXPECT_EQ(stats.impacts_by_surface, std::vector<long>{6});
    for (std::size_t k = 0; k < 6; ++k) {
        const auto& e = rec.impacts[k];
        EXPECT_EQ(e.surface, 0);
        EXPECT_NEAR(e.t, t_exact[k], 1e-9) << "impact " << k;
        EXPECT_NEAR(e.pre[1], -u_exact[k], 1e-9) << "impact " << k;
        EXPECT_EQ(e.pre[0], sigma);
        EXPECT_EQ(e.post[0], sigma);
        EXPECT_EQ(e.post[1], -r * e.pre[1]);  // Newton's law, exactly the model's reset
        EXPECT_EQ(e.post[2], e.pre[2]);
        EXPECT_NEAR(e.pre[2], 0.8 * e.t, 1e-9);  // theta' = omega
    }
    EXPECT_TRUE(rec.stick_t.empty());
}

TEST(HybridFlow, UndampedImpactTimesMatchClosedFormDop853)
{
    check_undamped_impact_sequence<vimpact::dop853>();
}
TEST(HybridFlow, UndampedImpactTimesMatchClosedFormDopri5)
{
    check_undamped_impact_sequence<vimpact::dopri5>();
}

// Damped free oscillator (zeta = 0.05): impact times from the closed-form flight
// e^{-zeta s}(y0 cos wd s + (v0 + zeta y0)/wd sin wd s), roots found by bisection in long
// double, chained through the reset v -> -r v with the closed-form pre-impact velocity.
TEST(HybridFlow, DampedImpactTimesMatchClosedForm)
{
    const double zeta = 0.05, sigma = -0.2, r = 0.9, T = 60.0;
    const auto m = oscillator(zeta, 0.0, 0.8, sigma, r);
    const damped_closed_form cf{zeta};
    std::vector<long double> t_exact, v_exact;
    long double t = 0.0L, y0 = 1.0L, v0 = 0.0L;
    for (;;) {
        const long double s = cf.next_impact(y0, v0, sigma, T - t);
        if (s < 0.0L) break;
        long double y, v;
        cf.at(s, y0, v0, y, v);
        t += s;
        t_exact.push_back(t);
        v_exact.push_back(v);
        y0 = sigma;
        v0 = -static_cast<long double>(r) * v;
    }
    ASSERT_GE(t_exact.size(), 3u);  // the set-up must actually impact several times

    const recorder rec = run_flow(m, flow_tolerances(1e-12, T), X3(1.0, 0.0, 0.0));
    ASSERT_EQ(rec.impacts.size(), t_exact.size());
    for (std::size_t k = 0; k < t_exact.size(); ++k) {
        EXPECT_NEAR(rec.impacts[k].t, static_cast<double>(t_exact[k]), 1e-9) << "impact " << k;
        EXPECT_NEAR(rec.impacts[k].pre[1], static_cast<double>(v_exact[k]), 1e-9) << "impact " << k;
    }
}

// Sections (v = 0 going down = maxima of y, going up = minima) of the barrier-free undamped
// oscillator y = cos t: maxima at t = 2 pi k with y = 1, minima at pi + 2 pi k with y = -1.
// The start (1, 0) is itself on the section; by the left-open convention of event location
// it belongs to the (non-existent) previous step and is not reported.
TEST(HybridFlow, SectionMaximaOfFreeOscillator)
{
    const auto m = oscillator(0.0, 0.0, 0.8, -5.0, 0.8);
    auto o = with_extrema(flow_tolerances(1e-12, 20.0 * pi + 1.0));
    o.surfaces = false;
    vimpact::run_stats stats;
    const recorder rec = run_flow(m, o, X3(1.0, 0.0, 0.0), nullptr, &stats);
    ASSERT_EQ(rec.max_t.size(), 10u);
    ASSERT_EQ(rec.min_t.size(), 10u);
    EXPECT_EQ(stats.sections, 20);
    for (std::size_t k = 0; k < 10; ++k) {
        const double kk = static_cast<double>(k);
        EXPECT_NEAR(rec.max_t[k], 2.0 * pi * (kk + 1), 1e-10);
        EXPECT_NEAR(rec.max_x[k][0], 1.0, 1e-11);
        EXPECT_EQ(rec.max_x[k][1], 0.0);
        EXPECT_NEAR(rec.min_t[k], pi + 2.0 * pi * kk, 1e-10);
        EXPECT_NEAR(rec.min_x[k][0], -1.0, 1e-11);
    }
    EXPECT_TRUE(rec.impacts.empty());
}

// Events near step boundaries. Fixed steps h = 2 pi / 32 (h_init = h_max, no rejection) put
// every maximum and minimum of y = cos t within round-off of a step end, on one side or the
// other. Each must be counted exactly once, at the right time. (Events exactly on a step end
// are tested on hand-made functions in event_location_test.cpp and, for the flow, with a
// surface and a section placed on a step end in flow_surfaces_test.cpp.)
TEST(HybridFlow, SectionsAtStepBoundariesCountedOnce)
{
    const auto m = oscillator(0.0, 0.0, 0.8, -5.0, 0.8);
    const int periods = 40;
    auto o = with_extrema(flow_tolerances(1e-10, periods * 2.0 * pi + 0.5));
    o.integration.h_init = 2.0 * pi / 32.0;
    o.integration.h_max = 2.0 * pi / 32.0;
    o.surfaces = false;
    vimpact::run_stats stats;
    const recorder rec = run_flow(m, o, X3(1.0, 0.0, 0.0), nullptr, &stats);
    // Precondition: every step but the clipped last one has the fixed size.
    ASSERT_EQ(stats.rejected, 0);
    ASSERT_EQ(stats.h_max, 2.0 * pi / 32.0);
    ASSERT_EQ(stats.steps, periods * 32 + 3);
    ASSERT_EQ(rec.max_t.size(), static_cast<std::size_t>(periods));
    ASSERT_EQ(rec.min_t.size(), static_cast<std::size_t>(periods));
    for (std::size_t k = 0; k < static_cast<std::size_t>(periods); ++k) {
        const double kk = static_cast<double>(k);
        EXPECT_NEAR(rec.max_t[k], 2.0 * pi * (kk + 1), 1e-9);
        EXPECT_NEAR(rec.min_t[k], pi + 2.0 * pi * kk, 1e-9);
    }
}

// Grazing inside one step: y = cos t has its minimum -1 at t = pi. A barrier 1e-9 above it is
// hit (the gap is negative for only 2 sqrt(2e-9) ~ 9e-5 time units, inside one step whose
// ends are both above the barrier): exactly one impact before t = 4, at
// t = pi - arccos(1 - 1e-9) with speed sin of that. The impact time of a grazing orbit is
// ill-conditioned, dt = dy / |v| with |v| = 4.5e-5, so a global error of a few 1e-12 in y
// allows ~1e-7 in t. A barrier 1e-9 below the minimum is never hit.
TEST(HybridFlow, GrazingDipInsideOneStepIsCaught)
{
    const double t_max = 4.0;
    // Precondition: the step sequence (the same in both runs up to the first impact) has a
    // step that contains pi well inside it.
    {
        const auto m = oscillator(0.0, 0.0, 0.8, -1.0 - 1e-9, 0.8);
        const recorder rec = run_flow(m, flow_tolerances(1e-12, 20.0), X3(1.0, 0.0, 0.0));
        EXPECT_TRUE(rec.impacts.empty());  // below the minimum: no impact, ever
        bool spans = false;
        for (std::size_t i = 0; i + 1 < rec.step_ends.size(); ++i)
            spans = spans || (rec.step_ends[i] < pi - 1e-3 && rec.step_ends[i + 1] > pi + 1e-3);
        ASSERT_TRUE(spans);
    }
    const auto m = oscillator(0.0, 0.0, 0.8, -1.0 + 1e-9, 0.8);
    const recorder rec = run_flow(m, flow_tolerances(1e-12, t_max), X3(1.0, 0.0, 0.0));
    ASSERT_EQ(rec.impacts.size(), 1u);
    const double d = std::acos(1.0 - 1e-9);
    EXPECT_NEAR(rec.impacts[0].t, pi, 1e-4);
    EXPECT_NEAR(rec.impacts[0].t, pi - d, 3e-7);
    EXPECT_NEAR(rec.impacts[0].pre[1], -std::sin(d), 3e-7);
}

// The same with a loose tolerance (rtol = atol = 1e-6, steps of order 1) and a dip 1e-5 deep
// (well above the integration error): the dip, 9e-3 time units wide, lies inside one step and
// is still caught, at t = pi - arccos(1 - 1e-5) up to dy/|v| ~ 1e-6 / 4.5e-3.
TEST(HybridFlow, GrazingDipCaughtWithLooseTolerance)
{
    {
        const auto m = oscillator(0.0, 0.0, 0.8, -1.0 - 1e-3, 0.8);
        const recorder rec = run_flow(m, flow_tolerances(1e-6, 4.0), X3(1.0, 0.0, 0.0));
        bool spans = false;
        for (std::size_t i = 0; i + 1 < rec.step_ends.size(); ++i)
            spans = spans || (rec.step_ends[i] < pi - 1e-2 && rec.step_ends[i + 1] > pi + 1e-2);
        ASSERT_TRUE(spans);
    }
    const auto m = oscillator(0.0, 0.0, 0.8, -1.0 + 1e-5, 0.8);
    const recorder rec = run_flow(m, flow_tolerances(1e-6, 4.0), X3(1.0, 0.0, 0.0));
    ASSERT_EQ(rec.impacts.size(), 1u);
    EXPECT_NEAR(rec.impacts[0].t, pi - std::acos(1.0 - 1e-5), 1e-3);
}

namespace {

// Flight from the barrier (sigma > 0, the equilibrium 0 below it) with F = 0, zeta = 0:
// y = sigma cos s + u sin s returns to sigma after s = 2 atan(u / sigma) with speed u.
struct compression_chatter {
    double t_first;  // time of the first impact
    double v0;       // its speed
    int impacts;     // impacts until the rebound speed r^k v0 falls below v_stick
    double t_stick;  // time of the last impact (the structure sticks there)
};

// The rebound speed below which the flow puts the state at rest on the barrier, pulled into
// it with acceleration |a| (the rule of hybrid/flow.hpp): max(sticking_velocity,
// sqrt(2 |a| h)), h the default resolution of the gap y - sigma at rest, 256 ulps of
// max(1, |sigma|).
double stop_speed(const flow_options& o, double sigma, double pull)
{
    const double h = 256.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(sigma));
    return std::max(o.sticking_velocity, std::sqrt(2.0 * pull * h));
}

compression_chatter compression_closed_form(double y0, double sigma, double r, double v_stick)
{
    compression_chatter c{};
    const long double s = sigma, y = y0;
    const long double t0 = std::acos(s / y);
    const long double v0 = std::sqrt(y * y - s * s);
    c.t_first = static_cast<double>(t0);
    c.v0 = static_cast<double>(v0);
    long double t = t0, u = v0;
    int n = 1;
    for (;;) {
        u *= r;  // rebound speed of impact n
        if (u < v_stick) break;
        t += 2.0L * std::atan(u / s);
        ++n;
    }
    c.impacts = n;
    c.t_stick = static_cast<double>(t);
    return c;
}

// The free oscillator (F = 0, zeta = 0) dropped from (y0, 0, 0) onto a barrier above its
// equilibrium, run until 5 time units after the closed-form sticking time.
struct chatter_run {
    compression_chatter cf;
    double stop_speed;
    recorder rec;
    vimpact::run_stats stats;
    outcome status = outcome::ok;
};

chatter_run run_compression_chatter(double sigma, double y0, double r)
{
    const auto m = oscillator(0.0, 0.0, 0.8, sigma, r);
    auto o = flow_tolerances(1e-12, 0.0);
    chatter_run c;
    c.stop_speed = stop_speed(o, sigma, sigma);
    c.cf = compression_closed_form(y0, sigma, r, c.stop_speed);
    o.t_max = c.cf.t_stick + 5.0;
    c.rec = run_flow(m, o, X3(y0, 0.0, 0.0), &c.status, &c.stats, true);
    return c;
}

}  // namespace

// Complete chatter: above its equilibrium (sigma > 0, F = 0) the structure falls back onto the
// barrier with geometrically shrinking rebound speeds u_k = r^k v0, in flight times
// 2 atan(u_k / sigma) that sum to a finite accumulation time. The flow must turn it into
// sticking after exactly the number of impacts with r^k v0 >= v_stick, at the closed-form time,
// never let the structure below the barrier, and then stay on the barrier (the free
// acceleration -sigma < 0 never turns positive). sigma = 1/64 keeps the last hops (height
// u^2 / (2 sigma) ~ 3e-15) far above the resolution of y near sigma (ulp 3.5e-18); a hop of
// speed u is then timed to ~ulp(sigma)/u ~ 4e-10.
TEST(HybridFlow, CompressionChatterEndsInSticking)
{
    const double sigma = 1.0 / 64.0, r = 0.8, y0 = 2.0 * sigma;
    const auto [cf, u_stop, rec, stats, st] = run_compression_chatter(sigma, y0, r);
    const double t_max = cf.t_stick + 5.0;
    // The count must not sit on a rounding knife edge.
    const double k_real = std::log(u_stop / cf.v0) / std::log(r);
    ASSERT_GT(std::abs(k_real - std::round(k_real)), 0.05);
    EXPECT_EQ(cf.impacts, static_cast<int>(std::floor(k_real)) + 1);

    EXPECT_EQ(st, outcome::time_limit);
    EXPECT_EQ(stats.sticking_phases, 1);
    ASSERT_EQ(rec.stick_t.size(), 1u);
    EXPECT_EQ(rec.stick_surface, std::vector<int>{0});
    EXPECT_TRUE(rec.release_t.empty());
    EXPECT_EQ(static_cast<int>(rec.impacts.size()), cf.impacts);
    ASSERT_GE(rec.impacts.size(), 3u);
    EXPECT_NEAR(rec.impacts[0].t, pi / 3.0, 1e-10);  // y0 cos t = y0 / 2
    EXPECT_NEAR(rec.impacts[1].t, pi / 3.0 + 2.0 * std::atan(r * cf.v0 / sigma), 1e-9);
    EXPECT_NEAR(rec.stick_t[0], cf.t_stick, 1e-8);
    EXPECT_EQ(rec.stick_x[0][0], sigma);
    EXPECT_EQ(rec.stick_x[0][1], 0.0);
    EXPECT_NEAR(stats.sticking_time, t_max - cf.t_stick, 1e-8);
    EXPECT_GE(rec.min_y, sigma - 1e-12) << "below the barrier at t = " << rec.t_min_y;
    EXPECT_LT(stats.steps, 20000);  // bounded work
}

// The same at unit scale (sigma = 1/2, y0 = 1): here the last hops before the threshold
// (u ~ 1e-8, height u^2 / (2 sigma) ~ 1e-16) are about one ulp of sigma high, so their speeds
// carry round-off of order ulp(sigma) sigma / u^2 ~ 10 %, and the impact count may differ from
// the exact one by one. The chatter must still end in sticking, at the accumulation time up to
// the timing resolution of those hops (~ulp/u per hop, summed geometrically: < 3e-7).
TEST(HybridFlow, UnitScaleCompressionChatterEndsInSticking)
{
    const double sigma = 0.5;
    const auto [cf, u_stop, rec, stats, st] = run_compression_chatter(sigma, 1.0, 0.8);
    EXPECT_EQ(stats.sticking_phases, 1);
    ASSERT_EQ(rec.stick_t.size(), 1u);
    EXPECT_LE(std::abs(static_cast<int>(rec.impacts.size()) - cf.impacts), 1);
    EXPECT_NEAR(rec.impacts[0].t, pi / 3.0, 1e-10);
    EXPECT_NEAR(rec.stick_t[0], cf.t_stick, 3e-7);
    EXPECT_GE(rec.min_y, sigma - 1e-12) << "below the barrier at t = " << rec.t_min_y;
}

// Small initial speed: the chatter is ballistic (gravity g = sigma near the barrier), and its
// accumulation time is t_inf = t0 + 2 v0 r / (g (1 - r)), up to a relative O((v0/sigma)^2)
// = 2e-6. The flow sticks at the last impact with rebound speed >= v_stick, i.e. before
// t_inf by the rest of the geometric series, at most 2 v_stick / (g (1 - r)) = 6.4e-6.
TEST(HybridFlow, ChatterAccumulationTimeMatchesBallisticLimit)
{
    const double sigma = 1.0 / 64.0, r = 0.8, y0 = sigma * (1.0 + 1e-6);
    const auto m = oscillator(0.0, 0.0, 0.8, sigma, r);
    auto o = flow_tolerances(1e-12, 1.0);
    const auto cf = compression_closed_form(y0, sigma, r, stop_speed(o, sigma, sigma));
    const double t_inf = cf.t_first + 2.0 * cf.v0 * r / (sigma * (1.0 - r));
    const double tail = 2.0 * stop_speed(o, sigma, sigma) / (sigma * (1.0 - r));
    const double k_real = std::log(stop_speed(o, sigma, sigma) / cf.v0) / std::log(r);
    ASSERT_GT(std::abs(k_real - std::round(k_real)), 0.05);

    vimpact::run_stats stats;
    const recorder rec = run_flow(m, o, X3(y0, 0.0, 0.0), nullptr, &stats, true);
    ASSERT_EQ(rec.stick_t.size(), 1u);
    EXPECT_EQ(static_cast<int>(rec.impacts.size()), cf.impacts);
    EXPECT_NEAR(rec.impacts[0].t, cf.t_first, 1e-9);
    EXPECT_NEAR(rec.stick_t[0], cf.t_stick, 1e-8);
    EXPECT_LE(rec.stick_t[0], t_inf + 1e-8);
    EXPECT_GE(rec.stick_t[0], t_inf - tail - 1e-8);
    EXPECT_GE(rec.min_y, sigma - 1e-12) << "below the barrier at t = " << rec.t_min_y;
}

namespace {

// Checks a forced chatter-stick-release cycle: pull -sigma + F cos(theta) < 0 at the start
// (theta = pi), release when F cos(theta) = sigma with cos increasing. With sigma / F = 1/2
// that is theta = 2 pi - arccos(1/2) = 5 pi / 3, i.e. t = (5 pi/3 - pi) / omega.
void check_forced_stick_release(double sigma, double F, double y0)
{
    const double omega = 0.05, r = 0.8;
    ASSERT_EQ(sigma / F, 0.5);
    const auto m = oscillator(0.0, F, omega, sigma, r);
    const double t_release = (5.0 * pi / 3.0 - pi) / omega;
    auto o = flow_tolerances(1e-12, t_release + 1.0);
    outcome st;
    vimpact::run_stats stats;
    const recorder rec = run_flow(m, o, X3(y0, 0.0, pi), &st, &stats, true);
    EXPECT_EQ(st, outcome::time_limit);

    // Admissibility: the structure never goes below the barrier.
    EXPECT_GE(rec.min_y, sigma - 1e-9) << "the orbit went below the barrier sigma = " << sigma
                                       << ": y = " << rec.min_y << " at t = " << rec.t_min_y;

    ASSERT_FALSE(rec.stick_t.empty());
    std::size_t n_chatter = 0;
    while (n_chatter < rec.impacts.size() && rec.impacts[n_chatter].t <= rec.stick_t[0]) ++n_chatter;
    ASSERT_GE(n_chatter, 30u);
    // One chatter sequence: the impact speeds fall monotonically until the structure sticks,
    // in ratio r once the hops are short (ballistic flight under a slowly varying pull; checked
    // for speeds 1e-6..1e-3, short hops that are still far above round-off).
    std::size_t first_rise = 0;
    for (std::size_t k = 0; k + 1 < n_chatter && first_rise == 0; ++k)
        if (-rec.impacts[k + 1].pre[1] >= -rec.impacts[k].pre[1]) first_rise = k + 1;
    EXPECT_EQ(first_rise, 0u) << "impact " << first_rise << " at t = " << rec.impacts[first_rise].t
                              << " is faster (" << -rec.impacts[first_rise].pre[1]
                              << ") than the one before (" << -rec.impacts[first_rise - 1].pre[1] << ")";
    int ratios = 0;
    for (std::size_t k = 0; k + 1 < n_chatter; ++k) {
        const double u = -rec.impacts[k].pre[1];
        if (u < 1e-6 || u > 1e-3) continue;
        ++ratios;
        EXPECT_NEAR(rec.impacts[k + 1].pre[1] / rec.impacts[k].pre[1], r, 1e-3) << "impact " << k + 1;
    }
    EXPECT_GE(ratios, 20);
    // Impacts to reach the threshold: log(v_stick / v_first) / log(r) plus a few for the
    // first, longer and not yet ballistic flights.
    const double v_first = -rec.impacts[0].pre[1];
    const double pull = -m.definition().free_acceleration(rec.stick_x[0]);
    const double predicted = std::log(stop_speed(o, sigma, pull) / v_first) / std::log(r);
    EXPECT_NEAR(static_cast<double>(n_chatter), predicted, 4.0);

    EXPECT_EQ(stats.sticking_phases, 1);
    ASSERT_EQ(rec.stick_t.size(), 1u);
    ASSERT_EQ(rec.release_t.size(), 1u);
    EXPECT_EQ(rec.release_surface, std::vector<int>{0});
    EXPECT_LT(rec.stick_t[0], t_release);
    EXPECT_NEAR(rec.release_t[0], t_release, 1e-8);
    EXPECT_EQ(rec.release_x[0][0], sigma);
    EXPECT_EQ(rec.release_x[0][1], 0.0);
    EXPECT_NEAR(rec.release_x[0][2], 5.0 * pi / 3.0, 1e-9);
    EXPECT_NEAR(stats.sticking_time, rec.release_t[0] - rec.stick_t[0], 1e-9);
    // After the release the structure lifts off: no further impact in the last time unit.
    EXPECT_EQ(rec.impacts.size(), n_chatter);
    EXPECT_LT(stats.steps, 20000);
}

}  // namespace

// Forced chatter, sticking and release at small scale (sigma = 1/64, F = 1/32, slow forcing
// omega = 0.05, start (1/32, 0, pi)): the forcing pulls the structure onto the barrier, it
// chatters, sticks, and is released at theta = 5 pi / 3 exactly as the closed form says.
TEST(HybridFlow, ForcedChatterSticksAndReleasesOnTime)
{
    check_forced_stick_release(1.0 / 64.0, 1.0 / 32.0, 1.0 / 32.0);
}

// Formerly a library bug: the same cycle at unit scale (sigma = 1/2, F = 1, start (1, 0, pi)).
// A rebound speed of ~1.2e-8 (above sticking_velocity = 1e-8) gives a hop u^2 / (2 |a|) ~
// 5e-17, below the resolution of y near sigma (ulp(0.5) = 1.1e-16): the gap never becomes
// > 0 in floating point, so no downward crossing exists. With a velocity threshold alone the
// orbit fell through the barrier (y ~ -2 at t ~ 10); the hop-height rule must prevent it.
TEST(HybridFlow, UnitScaleForcedChatterStaysAboveBarrier)
{
    check_forced_stick_release(0.5, 1.0, 1.0);
}

// Formerly a library bug: compression chatter with the barrier at sigma = 4 (F = 0, start
// (5, 0, 0)). ulp(4) = 8.9e-16, so a hop of speed u (height u^2 / (2 sigma)) is invisible in
// y once u is below about sqrt(sigma ulp(sigma)) ~ 6e-8, yet the velocity rule alone sticks
// only below 1e-8: a hop (rebound speed 5.1e-8) was missed and the orbit passed through the
// barrier to y ~ -4. It must stick instead.
TEST(HybridFlow, LargeBarrierCompressionChatterSticks)
{
    const double sigma = 4.0;
    const auto [cf, u_stop, rec, stats, st] = run_compression_chatter(sigma, 5.0, 0.8);
    EXPECT_GE(rec.min_y, sigma - 1e-9) << "the orbit went below the barrier sigma = " << sigma
                                       << ": y = " << rec.min_y << " at t = " << rec.t_min_y;
    EXPECT_EQ(stats.sticking_phases, 1);
    EXPECT_LE(std::abs(static_cast<int>(rec.impacts.size()) - cf.impacts), 2);
}

// A state beyond the barrier is refused; one on it at rest, pushed into it, starts in contact.
TEST(HybridFlow, InadmissibleStartIsRefusedAndRestingStartSticks)
{
    const auto m = oscillator(0.0, 0.0, 0.8, 0.5, 0.8);  // free acceleration at rest: -0.5
    hybrid_flow<oscillator_model> flow(m, flow_tolerances(1e-10, 1.0));
    EXPECT_THROW(flow.start(0.0, X3(0.4, 0.0, 0.0)), vimpact::input_error);
    EXPECT_THROW(flow.start(0.0, X3(0.5, -0.1, 0.0)), vimpact::input_error);  // on it, moving in
    flow.start(0.0, X3(0.5, 0.0, 0.0));
    EXPECT_EQ(flow.mode(), vimpact::flow_mode::sticking);
    EXPECT_EQ(flow.contact_surface(), 0);
    recorder rec;
    EXPECT_EQ(flow.run(rec), outcome::time_limit);
    EXPECT_EQ(flow.x()[0], 0.5);  // still at rest on the barrier
    EXPECT_TRUE(rec.impacts.empty());
}

// Determinism: the same model, options and start give bit-identical event sequences.
// A run depends on nothing but its inputs: run in another thread while a run of other
// parameters goes on beside it (no state shared between flows, none left behind by an earlier
// run), it gives the bits of the same run made first and alone.
TEST(HybridFlow, ARunGivesTheSameBitsInAnyThreadBesideAnyOtherRun)
{
    const auto m = oscillator(0.05, 1.0, 0.8, -0.2, 0.8);
    const auto o = with_extrema(flow_tolerances(1e-10, 200.0));
    const recorder a = run_flow(m, o, X3(0.3, 0.1, 0.0));
    recorder b, other;
    std::thread beside([&] { other = run_flow(oscillator(0.02, 1.3, 0.6, -0.1, 0.9), o, X3(0.2, 0.4, 1.0)); });
    std::thread again([&] { b = run_flow(m, o, X3(0.3, 0.1, 0.0)); });
    beside.join();
    again.join();
    ASSERT_GT(other.impacts.size(), 0u);
    ASSERT_GT(a.impacts.size(), 10u);
    ASSERT_EQ(a.impacts.size(), b.impacts.size());
    for (std::size_t k = 0; k < a.impacts.size(); ++k) {
        EXPECT_EQ(a.impacts[k].t, b.impacts[k].t);
        EXPECT_EQ(a.impacts[k].pre, b.impacts[k].pre);
        EXPECT_EQ(a.impacts[k].post, b.impacts[k].post);
    }
    EXPECT_EQ(a.max_t, b.max_t);
    EXPECT_EQ(a.max_x, b.max_x);
    EXPECT_EQ(a.step_ends, b.step_ends);
}
