// Crossings inside long steps, and resets that go wrong (hybrid/flow.hpp, integrate/
// event_resolution.hpp), on systems whose motion is known in closed form:
//  - a ball bouncing on a vibrating table (z'' = -1, table G sin(phi), phi' = 1, restitution
//    e): the flight is a parabola, so the integrator's error estimate is zero and nothing but
//    the events limits its steps; the gap z - G sin(phi) and the strobe section sin(phi) are
//    not affine in the state. Every flight is compared with its exact landing, the strobe
//    crossings with t = 2 pi k, and the Floquet multipliers of the period-1 bounce with those
//    of the exact impact map;
//  - a ball on a fixed floor and an oscillator against a wall, with resets that put the state
//    beyond the surface, drop it from a height, or gain energy at every impact.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <numbers>
#include <span>
#include <string_view>
#include <vector>

#include "vimpact/analysis/floquet.hpp"
#include "vimpact/hybrid/flow.hpp"
#include "vimpact/model/export.hpp"
#include "vimpact/model/model.hpp"
#include "vimpact/model/native_model.hpp"
#include "example_models.hpp"

namespace {

using vimpact::crossing;
using vimpact::flow_control;
using vimpact::flow_event;
using vimpact::flow_mode;
using vimpact::flow_options;
using vimpact::outcome;
using vimpact::vec;
using vimpact::vec_t;
using X3 = vec<3>;
constexpr double pi = std::numbers::pi;

// The ball on a vibrating table, in the table's phase phi (time scaled by the forcing
// frequency, gravity 1). The ball rests on the table (moves with it) while the table's
// acceleration -G sin(phi) exceeds -1: the contact phase, released when G sin(phi) - 1 > 0.
struct vibrating_table {
    static constexpr std::string_view name = "vibrating_table";
    static constexpr std::string_view description = "a ball bouncing on a sinusoidally vibrating table";
    static constexpr std::array<vimpact::state_variable, 3> state{{{"z"}, {"v"}, {"phi", "", "", 2.0 * pi}}};
    static constexpr std::array<vimpact::parameter, 2> parameters{{{"G", 1.2}, {"e", 0.5}}};
    static constexpr std::array<vimpact::impact_surface, 1> surfaces{{{"table", "", true}}};
    static constexpr std::array<vimpact::poincare_section, 1> sections{{{"strobe", crossing::up}}};

    explicit vibrating_table(std::span<const double> p) : G(p[0]), e(p[1]) {}

    template <class T>
    vec_t<T, 3> derivatives(const vec_t<T, 3>& X) const
    {
        return {X[1], T(-1.0), T(1.0)};
    }
    template <class T>
    T gap(int, const vec_t<T, 3>& X) const
    {
        using std::sin;
        return X[0] - G * sin(X[2]);
    }
    template <class T>
    vec_t<T, 3> reset(int, const vec_t<T, 3>& X) const
    {
        using std::cos;
        const T u = G * cos(X[2]);  // the table's velocity
        return {X[0], u - e * (X[1] - u), X[2]};
    }
    template <class T>
    T section(int, const vec_t<T, 3>& X) const
    {
        using std::sin;
        return sin(X[2]);
    }
    template <class T>
    vec_t<T, 3> sticking_derivatives(int, const vec_t<T, 3>& X) const
    {
        using std::sin;
        return {X[1], T(-G * sin(X[2])), T(1.0)};
    }
    template <class T>
    T release(int, const vec_t<T, 3>& X) const
    {
        using std::sin;
        return G * sin(X[2]) - 1.0;
    }
    [[nodiscard]] X3 rest(int, const X3& X) const { return {G * std::sin(X[2]), G * std::cos(X[2]), X[2]}; }

    double G, e;
};
using table_model = vimpact::native_model<vibrating_table>;

table_model make_table(double G, double e)
{
    const std::array<double, 2> p{G, e};
    return table_model(std::span<const double>(p));
}

struct impact_record {
    double t;
    X3 pre, post;
};

struct recorder : vimpact::flow_observer {
    std::vector<impact_record> impacts;
    std::vector<double> sections;
    flow_control on_impact(int, double t, const X3& pre, const X3& post)
    {
        impacts.push_back({t, pre, post});
        return flow_control::proceed;
    }
    flow_control on_section(int, crossing, double t, const X3&)
    {
        sections.push_back(t);
        return flow_control::proceed;
    }
    void on_stick(int, double, const X3&) { stuck = true; }
    bool stuck = false;
    bool single_steps = false;
    flow_control on_step_end(double) { return single_steps ? flow_control::stop : flow_control::proceed; }
};

// The exact landing after leaving the table at (t0, z0, v0, phi0): the first tau > 0 where
// z0 + v0 tau - tau^2 / 2 = G sin(phi0 + tau), found by a scan of the exact flight in steps of
// 1e-3 and bisection to rounding.
double exact_landing(double G, double z0, double v0, double phi0)
{
    const auto gap = [&](double tau) { return z0 + v0 * tau - 0.5 * tau * tau - G * std::sin(phi0 + tau); };
    double a = 1e-9;
    while (!(gap(a) > 0.0)) a += 1e-9;  // just after the impact: off the table
    for (double b = a + 1e-3;; a = b, b += 1e-3) {
        if (gap(b) <= 0.0) {
            for (int i = 0; i < 200 && b - a > 1e-15; ++i) {
                const double m = 0.5 * (a + b);
                (gap(m) > 0.0 ? a : b) = m;
            }
            return b;
        }
    }
}

template <template <int> class Method>
void never_passes_through_the_table()
{
    // From just above the table, moving up at speed 1: with the flight inside one step of the
    // integrator (its error estimate is zero on a parabola) the landing was missed and the ball
    // fell 0.126 through the table.
    const table_model m = make_table(1.2, 0.5);
    flow_options o;
    o.t_max = 600 * 2.0 * pi;
    vimpact::hybrid_flow<table_model, Method> flow(m, o);
    flow.start(0.0, X3{1e-3, 1.0, 0.0});
    recorder rec;
    rec.single_steps = true;
    double worst = 0.0;
    outcome status = outcome::ok;
    while ((status = flow.run(rec)) == outcome::ok && flow.t() < o.t_max)
        if (flow.mode() == flow_mode::free) worst = std::min(worst, m.gap(0, flow.x()));
    EXPECT_EQ(status, outcome::ok);
    EXPECT_GE(flow.t(), o.t_max);
    EXPECT_GE(worst, -1e-9);
    EXPECT_GT(rec.impacts.size(), 1000u);
    for (const auto& i : rec.impacts) EXPECT_GE(m.gap(0, i.post), -1e-9);
}

}  // namespace

TEST(VibratingTable, NeverPassesThroughTheTableDop853) { never_passes_through_the_table<vimpact::dop853>(); }
TEST(VibratingTable, NeverPassesThroughTheTableDopri5) { never_passes_through_the_table<vimpact::dopri5>(); }

// Each flight ends where the exact parabola meets the exact table first: from every departure
// of a run (the state after an impact, or at a release from the table), the next impact's time
// against the exact landing's.
TEST(VibratingTable, EveryLandingIsTheExactFirstOne)
{
    const double G = 1.2;
    const table_model m = make_table(G, 0.5);
    flow_options o;
    o.t_max = 300.0;
    vimpact::hybrid_flow<table_model> flow(m, o);
    flow.start(0.0, X3{1e-3, 1.0, 0.0});
    struct departures : recorder {
        std::vector<std::pair<double, X3>> from;  // departures, in order, before each impact
        std::vector<double> landing;
        flow_control on_impact(int, double t, const X3&, const X3& post)
        {
            if (!from.empty() && landing.size() < from.size()) landing.push_back(t);
            from.emplace_back(t, post);
            return flow_control::proceed;
        }
        void on_release(int, double t, const X3& x)
        {
            if (!from.empty() && landing.size() < from.size()) from.pop_back();  // it stuck instead
            from.emplace_back(t, x);
        }
    } obs;
    EXPECT_EQ(flow.run(obs), outcome::time_limit);
    int compared = 0;
    for (std::size_t k = 0; k < obs.landing.size(); ++k) {
        const auto& [t0, x] = obs.from[k];
        // Flights long enough for the scan's 1e-3 steps (a chatter sequence's are not).
        if (obs.landing[k] - t0 < 0.05) continue;
        EXPECT_NEAR(obs.landing[k] - t0, exact_landing(G, x[0], x[1], x[2]), 1e-9) << "flight " << k;
        ++compared;
    }
    EXPECT_GE(compared, 20);
}

// The strobe section sin(phi) = 0 upwards is crossed once per period, at t = 2 pi k - 0.1
// from phi = 0.1 at t = 0: 600 of them in 600 periods, each at its time, whatever the integrator's steps. With G = 1.5 the
// ball settles on a bounce whose flights the integrator crossed in one step each, and 3 of the
// 600 crossings were found.
TEST(VibratingTable, StrobeSectionOncePerPeriod)
{
    for (const double G : {1.5, 1.2, 3.0}) {
        const table_model m = make_table(G, 0.5);
        flow_options o;
        o.t_max = 600 * 2.0 * pi + 1.0;
        o.events = {flow_event::section(0, crossing::up)};
        recorder rec;
        vimpact::hybrid_flow<table_model> flow(m, o);
        flow.start(0.0, X3{1.0, 0.0, 0.1});
        EXPECT_EQ(flow.run(rec), outcome::time_limit) << "G = " << G;
        ASSERT_EQ(rec.sections.size(), 600u) << "G = " << G;
        for (std::size_t k = 0; k < rec.sections.size(); ++k)
            ASSERT_NEAR(rec.sections[k], 2.0 * pi * static_cast<double>(k + 1) - 0.1, 1e-9 * (1.0 + static_cast<double>(k)))
                << "G = " << G;
    }
}

// The Floquet multipliers of the period-1 bounce at the strobe section against those of the
// exact impact map. The bounce leaves the table at phase p with speed pi (a flight of one
// period lands at the same table height), which needs G cos p (1 + e) = pi (1 - e). The impact
// map (p, v) -> (p', v') is defined by the landing tau, F = G sin p + v tau - tau^2 / 2 -
// G sin(p + tau) = 0, and v' = (1 + e) G cos p' - e (v - tau); by the implicit function
// theorem, with k = dtau/dv = 2 pi / (pi + G cos p) and dtau/dp = 0 at the orbit,
//   J = [[1, k], [-(1 + e) G sin p, -(1 + e) G sin p k - e + e k]].
// The strobe map is conjugate to it, so its non-trivial multipliers are J's eigenvalues.
TEST(VibratingTable, FloquetMultipliersOfTheBounceAreTheExactOnes)
{
    const double G = 1.2, e = 0.5;
    const double p = std::acos(pi * (1.0 - e) / (G * (1.0 + e)));
    const double k = 2.0 * pi / (pi + G * std::cos(p)), a = -(1.0 + e) * G * std::sin(p);
    const double tr = 1.0 + a * k - e + e * k, det = a * k - e + e * k - k * a;
    const std::complex<double> disc = std::sqrt(std::complex<double>(tr * tr - 4.0 * det));
    const std::complex<double> mu1 = 0.5 * (tr + disc), mu2 = 0.5 * (tr - disc);

    vimpact::model m = vimpact::model::from_definition<vibrating_table>();
    m = m.with_parameter(m.info().parameter_index("G"), G).with_parameter(m.info().parameter_index("e"), e);
    vimpact::floquet_options o;
    o.protocol.transient_impacts = 200;
    o.protocol.record_points = 20;
    o.protocol.section = vimpact::section_choice::crossings(0);
    // Just after the bounce's impact, a little off it.
    Eigen::VectorXd x0(3);
    x0 << G * std::sin(p) + 1e-3, pi + 0.01, p;
    const vimpact::floquet_result r = vimpact::floquet(m, x0, o);
    ASSERT_EQ(r.status, outcome::ok) << vimpact::to_string(r.status);
    EXPECT_EQ(r.label, "P1");
    EXPECT_EQ(r.impacts_per_period, 1);
    ASSERT_EQ(r.multipliers.size(), 3u);
    EXPECT_NEAR(std::abs(r.multipliers[0] - 1.0), 0.0, 1e-8);  // the trivial one, along the flow
    const std::complex<double> a1 = r.multipliers[1], a2 = r.multipliers[2];
    const bool same_order = std::abs(a1 - mu1) < std::abs(a1 - mu2);
    EXPECT_NEAR(std::abs(a1 - (same_order ? mu1 : mu2)), 0.0, 1e-7);
    EXPECT_NEAR(std::abs(a2 - (same_order ? mu2 : mu1)), 0.0, 1e-7);
    EXPECT_NEAR(det, e * e, 1e-12);  // the closed form's own sum rule: det J = e^2
}

namespace {

// A ball above a fixed floor (z'' = -1, gap z) with one of several resets:
//   0: restitution r, v -> -r v;
//   1: to a depth below the floor (z -> -1: beyond the surface);
//   2: a drop from the height H at rest (z -> H, v -> 0: away from the surface).
struct floor_ball {
    static constexpr std::string_view name = "floor_ball";
    static constexpr std::string_view description = "a ball above a fixed floor";
    static constexpr std::array<vimpact::state_variable, 2> state{{{"z"}, {"v"}}};
    static constexpr std::array<vimpact::parameter, 3> parameters{{{"mode", 0.0}, {"r", 0.5}, {"H", 2.0}}};
    static constexpr std::array<vimpact::impact_surface, 1> surfaces{{{"floor", "", false, true}}};
    static constexpr std::array<vimpact::poincare_section, 1> sections{{{"apex", crossing::down, "", true}}};

    explicit floor_ball(std::span<const double> p) : mode(static_cast<int>(p[0])), r(p[1]), H(p[2]) {}

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
        if (mode == 1) return {T(-1.0), X[1]};
        if (mode == 2) return {T(H), T(0.0)};
        return {X[0], -r * X[1]};
    }
    template <class T>
    T section(int, const vec_t<T, 2>& X) const
    {
        return X[1];
    }
    int mode;
    double r, H;
};

// x'' = -x against a wall at x = 0 (gap x), with v -> -g v: g > 1 gains energy at every impact.
struct gaining_wall {
    static constexpr std::string_view name = "gaining_wall";
    static constexpr std::string_view description = "an oscillator whose impacts gain energy";
    static constexpr std::array<vimpact::state_variable, 2> state{{{"x"}, {"v"}}};
    static constexpr std::array<vimpact::parameter, 1> parameters{{{"g", 2.0}}};
    static constexpr std::array<vimpact::impact_surface, 1> surfaces{{{"wall", "", false, true}}};
    static constexpr std::array<vimpact::poincare_section, 0> sections{};

    explicit gaining_wall(std::span<const double> p) : g(p[0]) {}
    template <class T>
    vec_t<T, 2> derivatives(const vec_t<T, 2>& X) const
    {
        return {X[1], -X[0]};
    }
    template <class T>
    T gap(int, const vec_t<T, 2>& X) const
    {
        return X[0];
    }
    template <class T>
    vec_t<T, 2> reset(int, const vec_t<T, 2>& X) const
    {
        return {X[0], -g * X[1]};
    }
    template <class T>
    T section(int, const vec_t<T, 2>&) const
    {
        return T(0.0);
    }
    double g;
};

template <class D>
struct run_result {
    outcome status;
    vimpact::run_stats stats;
    vec<2> x;
    double t;
};

template <class D>
run_result<D> run_model(std::vector<double> p, const vec<2>& x0, double t_max)
{
    const vimpact::native_model<D> m{std::span<const double>(p)};
    flow_options o;
    o.t_max = t_max;
    vimpact::hybrid_flow<vimpact::native_model<D>> flow(m, o);
    flow.start(0.0, x0);
    vimpact::flow_observer obs;
    const outcome st = flow.run(obs);
    return {st, flow.stats(), flow.x(), flow.t()};
}

}  // namespace

// A reset that puts the state beyond the floor ends the run at the first impact, at the
// landing of the fall from z = 2 (t = 2), with the state before it: not a run that goes on
// below the floor with the outcome ok.
TEST(Resets, BeyondTheSurfaceIsInadmissibleAtTheFirstImpact)
{
    const auto r = run_model<floor_ball>({1.0, 0.5, 2.0}, vec<2>{2.0, 0.0}, 50.0);
    EXPECT_EQ(r.status, outcome::inadmissible);
    EXPECT_NEAR(r.t, 2.0, 1e-12);
    EXPECT_GE(r.x[0], -1e-12);
    EXPECT_EQ(r.stats.impacts, 0);
}

// A reset that drops the ball from a height at rest moves it away from the floor: a new fall
// of 2 time units each time (z = 2 - t^2 / 2), so 25 impacts in 50 time units; chattering
// (impacts accumulating) it is not.
TEST(Resets, ADropToAHeightIsANewFlightNotChattering)
{
    const auto r = run_model<floor_ball>({2.0, 0.5, 2.0}, vec<2>{2.0, 0.0}, 50.0 + 1.0);
    EXPECT_EQ(r.status, outcome::time_limit);
    EXPECT_EQ(r.stats.impacts, 25);
}

// Restitution 1/2 on the fixed floor stays what it was: impacts accumulate (a chatter
// sequence) and the run ends with the outcome chattering.
TEST(Resets, RestitutionStillChattersOnAFixedFloor)
{
    const auto r = run_model<floor_ball>({0.0, 0.5, 2.0}, vec<2>{2.0, 0.0}, 50.0);
    EXPECT_EQ(r.status, outcome::chattering);
    EXPECT_GT(r.stats.impacts, 20);
}

// Each impact doubles the speed; the impacts come every pi (half a period of x'' = -x), so the
// speed, 2^n after n impacts, overflows after about 1024 of them. The run ends there, its state
// the last finite one, not with ok and a state of infinities: with non_finite where the reset's
// image overflows, or inadmissible where, a few impacts before, the impact point's position
// (located to a few ulps of a step crossed at 1e300 units of speed) already lies beyond the wall
// by more than its resolution.
TEST(Resets, EnergyGainedWithoutBoundEndsNonFinite)
{
    const auto r = run_model<gaining_wall>({2.0}, vec<2>{1.0, 0.0}, 1e9);
    EXPECT_TRUE(r.status == outcome::non_finite || r.status == outcome::inadmissible) << vimpact::to_string(r.status);
    EXPECT_TRUE(r.x.allFinite());
    EXPECT_GE(r.stats.impacts, 1000);
    EXPECT_LE(r.stats.impacts, 1030);
}

// A model file's gaps and sections are found affine in the state or not from their equations
// (the table's surface_affine and section_affine): the walls d - x and x + d are, the table
// z - G sin(phi) and the strobe sections sin(phi) are not, the paper's barrier y - sigma and
// velocity sections ydot are.
TEST(ModelFiles, AffineGapsAndSectionsAreFoundFromTheEquations)
{
    const auto flags = [](const vimpact::model& m) {
        const vimpact_model_table& t = m.table();
        std::vector<int> f;
        for (int i = 0; i < t.surface_count; ++i) f.push_back(t.surface_affine ? t.surface_affine[i] : -1);
        f.push_back(9);
        for (int k = 0; k < t.section_count; ++k) f.push_back(t.section_affine ? t.section_affine[k] : -1);
        return f;
    };
    using v = std::vector<int>;
    EXPECT_EQ(flags(vimpact::test::example_model("two_sided_impact_oscillator")), (v{1, 1, 9, 0}));
    EXPECT_EQ(flags(vimpact::test::example_model("vibrating_table")), (v{0, 9, 0}));
    EXPECT_EQ(flags(vimpact::test::example_model("wake_impact")), (v{1, 9, 1, 1}));
    // The C++ definitions say it themselves, through the same table.
    EXPECT_EQ(flags(vimpact::model::from_definition<vibrating_table>()), (v{0, 9, 0}));
    EXPECT_EQ(flags(vimpact::model::from_definition<floor_ball>()), (v{1, 9, 1}));
}

// The model file of the ball on the vibrating table (examples/models/vibrating_table.toml)
// runs as its C++ definition does: on the period-1 bounce (its Floquet test above), the same
// impacts and the same strobe points, to the integrator's tolerance.
TEST(ModelFiles, VibratingTableFileRunsAsItsDefinition)
{
    const vimpact::model file = vimpact::test::example_model("vibrating_table");
    const vimpact::model def = vimpact::model::from_definition<vibrating_table>();
    const double G = 1.2, e = 0.5, p = std::acos(pi * (1.0 - e) / (G * (1.0 + e)));
    Eigen::VectorXd x0(3);
    x0 << G * std::sin(p) + 1e-3, pi + 0.01, p;
    vimpact::protocol_options po;
    po.transient_impacts = 50;
    po.record_points = 20;
    po.section = vimpact::section_choice::crossings(0);
    const vimpact::simulation a = vimpact::simulate(file, x0, po);
    const vimpact::simulation b = vimpact::simulate(def, x0, po);
    ASSERT_EQ(a.status, outcome::ok);
    ASSERT_EQ(b.status, outcome::ok);
    ASSERT_EQ(a.points.size(), b.points.size());
    // The impacts of the recorded window, not stats.impacts: that counts every impact the
    // integration met, up to the end of its last step, which may or may not reach the impact
    // just after the last strobe point as the steps fall (a change of 1e-15 in the start moves it).
    EXPECT_EQ(a.transient_impacts, b.transient_impacts);
    ASSERT_EQ(a.impacts.size(), b.impacts.size());
    for (std::size_t k = 0; k < a.impacts.size(); ++k) {
        EXPECT_NEAR(a.impacts.pre.t(k), b.impacts.pre.t(k), 1e-9);
        EXPECT_NEAR((a.impacts.post.x(k) - b.impacts.post.x(k)).cwiseAbs().maxCoeff(), 0.0, 1e-8);
    }
    for (std::size_t k = 0; k < a.points.size(); ++k) {
        EXPECT_NEAR(a.points.t(k), b.points.t(k), 1e-9);
        EXPECT_NEAR((a.points.x(k) - b.points.x(k)).cwiseAbs().maxCoeff(), 0.0, 1e-8);
    }
}
