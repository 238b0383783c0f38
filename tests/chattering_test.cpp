// The chattering rule of the hybrid flow (hybrid/flow.hpp) on a bouncing ball, x'' = -g over
// a floor x >= 0 with v -> -r v, where every impact is known in closed form: from rest at
// height h0 the first impact is at t1 = sqrt(2 h0 / g) with speed v1 = g t1, the rebound
// speeds are u_k = r^k v1, each hop lasts 2 u_k / g, and the impacts accumulate at
//   t_inf = t1 + 2 v1 r / (g (1 - r)).
// The rule ends a chatter sequence at the first impact whose rebound is negligible: u_k below
// u_stop = max(sticking_velocity, sqrt(2 g h)), h the resolution of the gap at rest (by
// default 256 ulps of max(1, |x|), x = 0 on the floor). A floor without a contact phase then
// ends the run with the outcome `chattering`; a floor with one puts the ball at rest until
// its release function turns positive.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <string_view>
#include <vector>

#include "test_support.hpp"
#include "vimpact/hybrid/flow.hpp"
#include "vimpact/model/native_model.hpp"

namespace {

using vimpact::crossing;
using vimpact::flow_control;
using vimpact::flow_event;
using vimpact::flow_options;
using vimpact::outcome;
using vimpact::vec;
using vimpact::vec_t;
constexpr double pi = std::numbers::pi;

// The ball with g = 1 and no contact phase; section "apex": v = 0 going down.
struct ball {
    static constexpr std::string_view name = "ball";
    static constexpr std::string_view description = "a ball bouncing on a floor, no contact phase";
    static constexpr std::array<vimpact::state_variable, 2> state{{{"x"}, {"v"}}};
    static constexpr std::array<vimpact::parameter, 1> parameters{{{"r", 0.5}}};
    static constexpr std::array<vimpact::impact_surface, 1> surfaces{{{"floor"}}};
    static constexpr std::array<vimpact::poincare_section, 1> sections{{{"apex", crossing::down}}};

    explicit ball(std::span<const double> p) : r(p[0]) {}

    template <class T>
    vec_t<T, 2> derivatives(const vec_t<T, 2>& X) const
    {
        return {X[1], T(-1.0)};
    }
    template <class T>
    T gap(int, const vec_t<T, 2>& X) const
    {
        return X[0];
    }
    template <class T>
    vec_t<T, 2> reset(int, const vec_t<T, 2>& X) const
    {
        return {X[0], T(-r * X[1])};
    }
    template <class T>
    T section(int, const vec_t<T, 2>& X) const
    {
        return X[1];
    }

    double r;
};

// The ball with a contact phase, in a gravity that weakens and reverses slowly:
// x'' = -cos(omega s), s' = 1 (s the time). At rest on the floor the ball waits until the
// free acceleration -cos(omega s) turns positive, at s = pi / (2 omega); with omega = 0 it
// never does.
struct resting_ball {
    static constexpr std::string_view name = "resting_ball";
    static constexpr std::string_view description = "a ball on a floor with a contact phase";
    static constexpr std::array<vimpact::state_variable, 3> state{{{"x"}, {"v"}, {"s"}}};
    static constexpr std::array<vimpact::parameter, 2> parameters{{{"r", 0.5}, {"omega", 0.0}}};
    static constexpr std::array<vimpact::impact_surface, 1> surfaces{{{"floor", "", true}}};
    static constexpr std::array<vimpact::poincare_section, 1> sections{{{"apex", crossing::down}}};

    explicit resting_ball(std::span<const double> p) : r(p[0]), omega(p[1]) {}

    template <class T>
    T acceleration(const vec_t<T, 3>& X) const
    {
        using std::cos;
        return T(-cos(omega * X[2]));
    }
    template <class T>
    vec_t<T, 3> derivatives(const vec_t<T, 3>& X) const
    {
        return {X[1], acceleration(X), T(1.0)};
    }
    template <class T>
    T gap(int, const vec_t<T, 3>& X) const
    {
        return X[0];
    }
    template <class T>
    vec_t<T, 3> reset(int, const vec_t<T, 3>& X) const
    {
        return {X[0], T(-r * X[1]), X[2]};
    }
    template <class T>
    T section(int, const vec_t<T, 3>& X) const
    {
        return X[1];
    }
    template <class T>
    vec_t<T, 3> sticking_derivatives(int, const vec_t<T, 3>&) const
    {
        return {T(0.0), T(0.0), T(1.0)};
    }
    template <class T>
    T release(int, const vec_t<T, 3>& X) const
    {
        return acceleration(X);
    }
    vec<3> rest(int, const vec<3>& X) const { return {0.0, 0.0, X[2]}; }

    double r, omega;
};

// The closed-form chatter of the ball (g = 1) dropped from h0, ended by u_stop.
struct chatter_prediction {
    double t1, v1;
    int impacts;      // N: the first k with r^k v1 < u_stop
    double t_last;    // the time of impact N
    double u_last;    // its rebound r^N v1
    double t_inf;     // the accumulation time
    double k_real;    // log(u_stop / v1) / log(r): N = floor(k_real) + 1
};

chatter_prediction predict(double h0, double r, double u_stop)
{
    chatter_prediction p{};
    p.t1 = std::sqrt(2.0 * h0);
    p.v1 = p.t1;
    p.t_inf = p.t1 + 2.0 * p.v1 * r / (1.0 - r);
    p.k_real = std::log(u_stop / p.v1) / std::log(r);
    long double t = p.t1, u = p.v1;
    int n = 1;
    for (;;) {
        u *= r;
        if (u < u_stop) break;
        t += 2.0L * u;
        ++n;
    }
    p.impacts = n;
    p.t_last = static_cast<double>(t);
    p.u_last = static_cast<double>(u);
    return p;
}

// The documented default stop speed on the floor (x = 0, |a| = 1).
double default_stop_speed(const flow_options& o)
{
    return std::max(o.sticking_velocity, std::sqrt(2.0 * 256.0 * std::numeric_limits<double>::epsilon()));
}

template <int N>
struct recorder : vimpact::flow_observer {
    std::vector<double> impact_t, apex_t, apex_x, stick_t, release_t;
    std::vector<vec<N>> post, stick_x, release_x;
    flow_control on_impact(int surface, double t, const vec<N>&, const vec<N>& after)
    {
        EXPECT_EQ(surface, 0);
        impact_t.push_back(t);
        post.push_back(after);
        return flow_control::proceed;
    }
    flow_control on_section(int, crossing, double t, const vec<N>& x)
    {
        apex_t.push_back(t);
        apex_x.push_back(x[0]);
        return flow_control::proceed;
    }
    void on_stick(int surface, double t, const vec<N>& x)
    {
        EXPECT_EQ(surface, 0);
        stick_t.push_back(t);
        stick_x.push_back(x);
    }
    void on_release(int surface, double t, const vec<N>& x)
    {
        EXPECT_EQ(surface, 0);
        release_t.push_back(t);
        release_x.push_back(x);
    }
};

template <class D, int N = vimpact::definition_dim<D>>
struct ball_run {
    recorder<N> rec;
    outcome status = outcome::ok;
    vimpact::run_stats stats;
    vec<N> x_end;
};

template <class D, int N = vimpact::definition_dim<D>>
ball_run<D> run_ball(std::vector<double> parameters, const vec<N>& x0, const flow_options& o)
{
    const vimpact::native_model<D> m{std::span<const double>(parameters)};
    vimpact::hybrid_flow<vimpact::native_model<D>> flow(m, o);
    flow.start(0.0, x0);
    ball_run<D> out;
    out.status = flow.run(out.rec);
    out.stats = flow.stats();
    out.x_end = flow.x();
    return out;
}

flow_options ball_options(double t_max)
{
    flow_options o = vimpact::test::flow_tolerances(1e-12, t_max);
    o.events = {flow_event::section(0, crossing::down)};
    return o;
}

}  // namespace

// No contact phase: the run ends with `chattering` at impact N of the closed form, at its
// time, with its rebound as the final state, just before the accumulation time (by the rest
// of the geometric series, 2 u_N / (1 - r) < 2 u_stop / (1 - r)). Every hop in between is
// resolved: one apex per hop at height u_k^2 / 2.
TEST(Chattering, SurfaceWithoutContactPhaseEndsWithChatteringAtTheAccumulationTime)
{
    const double h0 = 0.7, r = 0.5;
    const flow_options o = ball_options(100.0);
    const double u_stop = default_stop_speed(o);
    const auto p = predict(h0, r, u_stop);
    // The count must not sit on a rounding knife edge.
    ASSERT_GT(std::abs(p.k_real - std::round(p.k_real)), 0.1);
    ASSERT_EQ(p.impacts, static_cast<int>(std::floor(p.k_real)) + 1);

    const auto run = run_ball<ball>({r}, vec<2>(h0, 0.0), o);
    EXPECT_EQ(run.status, outcome::chattering);
    EXPECT_EQ(run.stats.impacts, p.impacts);
    ASSERT_EQ(static_cast<int>(run.rec.impact_t.size()), p.impacts);
    EXPECT_NEAR(run.rec.impact_t.front(), p.t1, 1e-12);
    EXPECT_NEAR(run.stats.t_final, p.t_last, 1e-12);
    EXPECT_EQ(run.x_end[0], 0.0);
    EXPECT_NEAR(run.x_end[1], p.u_last, 1e-12);
    EXPECT_LT(run.stats.t_final, p.t_inf);
    EXPECT_LE(p.t_inf - run.stats.t_final, 2.0 * u_stop / (1.0 - r));
    EXPECT_EQ(run.stats.sticking_phases, 0);
    ASSERT_EQ(static_cast<int>(run.rec.apex_t.size()), p.impacts - 1);
    double u = p.v1;
    for (std::size_t k = 0; k < run.rec.apex_t.size(); ++k) {
        u *= r;
        EXPECT_NEAR(run.rec.apex_x[k], 0.5 * u * u, 1e-12 * (1.0 + 0.5 * u * u)) << "apex " << k;
    }
    std::printf("[ measured ] ball h0 = %g, r = %g: outcome %s after %ld impacts (predicted %d), t_final %.15f, "
                "t_N %.15f, t_inf %.15f\n",
                h0, r, std::string(to_string(run.status)).c_str(), run.stats.impacts, p.impacts, run.stats.t_final,
                p.t_last, p.t_inf);
}

// The threshold is the caller's: with sticking_velocity = 1e-3 the sequence ends at the
// first rebound below 1e-3 (impact 11 from h0 = 0.7, r = 1/2).
TEST(Chattering, StickingVelocitySetsWhereTheSequenceEnds)
{
    const double h0 = 0.7, r = 0.5;
    flow_options o = ball_options(100.0);
    o.sticking_velocity = 1e-3;
    const auto p = predict(h0, r, 1e-3);
    ASSERT_EQ(p.impacts, 11);
    const auto run = run_ball<ball>({r}, vec<2>(h0, 0.0), o);
    EXPECT_EQ(run.status, outcome::chattering);
    EXPECT_EQ(run.stats.impacts, 11);
    EXPECT_NEAR(run.stats.t_final, p.t_last, 1e-12);
}

// With a contact phase and a release function that never turns positive (omega = 0) the ball
// rests on the floor from impact N on, at the same time as the chatter above ends, and stays.
TEST(Chattering, ContactPhaseStartsAtTheLastResolvedImpactAndLasts)
{
    const double h0 = 0.7, r = 0.5, t_max = 5.0;
    const flow_options o = ball_options(t_max);
    const auto p = predict(h0, r, default_stop_speed(o));
    const auto run = run_ball<resting_ball>({r, 0.0}, vec<3>(h0, 0.0, 0.0), o);
    EXPECT_EQ(run.status, outcome::time_limit);
    EXPECT_EQ(run.stats.impacts, p.impacts);
    EXPECT_EQ(run.stats.sticking_phases, 1);
    ASSERT_EQ(run.rec.stick_t.size(), 1u);
    EXPECT_NEAR(run.rec.stick_t[0], p.t_last, 1e-12);
    EXPECT_EQ(run.rec.stick_x[0], vec<3>(0.0, 0.0, run.rec.stick_x[0][2]));
    EXPECT_NEAR(run.rec.stick_x[0][2], p.t_last, 1e-12);
    EXPECT_TRUE(run.rec.release_t.empty());
    EXPECT_NEAR(run.stats.sticking_time, t_max - p.t_last, 1e-12);
    EXPECT_EQ(run.x_end[0], 0.0);
    EXPECT_EQ(run.x_end[1], 0.0);
    EXPECT_NEAR(run.x_end[2], t_max, 1e-12);
}

// A time-dependent release: gravity -cos(omega s), omega = 0.05. The ball chatters to rest
// within a few time units (gravity still about 1: near the constant-gravity accumulation
// time), waits, and is released when the gravity reverses, at t_r = pi / (2 omega). Then it
// lifts off: v = (1 - sin(omega t)) / omega, x = (t - t_r) / omega + cos(omega t) / omega^2.
TEST(Chattering, ContactPhaseIsReleasedAtTheClosedFormTime)
{
    const double h0 = 0.7, r = 0.5, omega = 0.05;
    const double t_release = pi / (2.0 * omega), t_max = t_release + 2.0;
    const flow_options o = ball_options(t_max);
    const auto p = predict(h0, r, default_stop_speed(o));
    const auto run = run_ball<resting_ball>({r, omega}, vec<3>(h0, 0.0, 0.0), o);
    EXPECT_EQ(run.status, outcome::time_limit);
    EXPECT_EQ(run.stats.sticking_phases, 1);
    ASSERT_EQ(run.rec.stick_t.size(), 1u);
    ASSERT_EQ(run.rec.release_t.size(), 1u);
    EXPECT_NEAR(run.rec.stick_t[0], p.t_inf, 0.05);
    EXPECT_LT(run.rec.stick_t[0], 4.0);
    EXPECT_NEAR(run.rec.release_t[0], t_release, 1e-9);
    EXPECT_EQ(run.rec.release_x[0][0], 0.0);
    EXPECT_EQ(run.rec.release_x[0][1], 0.0);
    EXPECT_NEAR(run.rec.release_x[0][2], t_release, 1e-9);
    EXPECT_NEAR(run.stats.sticking_time, run.rec.release_t[0] - run.rec.stick_t[0], 1e-12);
    // No impact after the release; the lift-off follows the closed form.
    EXPECT_LT(run.rec.impact_t.back(), run.rec.stick_t[0] + 1e-12);
    const double x_exact = (t_max - t_release) / omega + std::cos(omega * t_max) / (omega * omega);
    const double v_exact = (1.0 - std::sin(omega * t_max)) / omega;
    EXPECT_NEAR(run.x_end[0], x_exact, 1e-9);
    EXPECT_NEAR(run.x_end[1], v_exact, 1e-9);
    EXPECT_GT(run.x_end[0], 0.05);
}
