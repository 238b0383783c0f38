// Switching surfaces in the hybrid flow (hybrid/flow.hpp) and the tangent flow
// (tangent/variational.hpp): a vector field that changes where a switching function h(x)
// changes sign, with the side held between located crossings. Expected values come from
// closed forms (a bilinear oscillator, Housner's linearised rocking block, a relay) and from
// finite differences of the section map (a forced oscillator with a compliant stop).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <complex>
#include <cmath>
#include <numbers>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>

#include "example_models.hpp"
#include "map_differences.hpp"
#include "test_support.hpp"
#include "vimpact/analysis/continuation.hpp"
#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/lyapunov.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/hybrid/flow.hpp"
#include "vimpact/model/export.hpp"
#include "vimpact/model/native_model.hpp"
#include "vimpact/tangent/section_map.hpp"

namespace {

using vimpact::crossing;
using vimpact::flow_control;
using vimpact::flow_event;
using vimpact::outcome;
using vimpact::switch_sides;
using vimpact::vec;
using vimpact::vec_t;
using vimpact::test::flow_tolerances;
constexpr double pi = std::numbers::pi;

// The events and crossings of a run.
struct recorder : vimpact::flow_observer {
    std::vector<double> times, values, switch_times;
    std::vector<int> switches;
    template <class X>
    flow_control on_section(int, crossing, double t, const X& x)
    {
        times.push_back(t);
        values.push_back(x[0]);
        return flow_control::proceed;
    }
    template <class X>
    flow_control on_switch(int k, double t, const X&, const X&)
    {
        switches.push_back(k);
        switch_times.push_back(t);
        return flow_control::proceed;
    }
};

// ---- a bilinear oscillator ------------------------------------------------------------------

// x'' + (1 + kc on) x = 0, on = 1 where x > 0: a stiffer spring on one side.
struct bilinear {
    static constexpr std::string_view name = "bilinear";
    static constexpr std::string_view description = "a free oscillator with a stiffer spring for x > 0";
    static constexpr std::array<vimpact::state_variable, 2> state{{{"x"}, {"v"}}};
    static constexpr std::array<vimpact::parameter, 1> parameters{{{"kc", 3.0}}};
    static constexpr std::array<vimpact::impact_surface, 0> surfaces{};
    static constexpr std::array<vimpact::poincare_section, 0> sections{};
    static constexpr std::array<vimpact::switching_surface, 1> switches{{{"spring", "x = 0", crossing::both, true}}};

    explicit bilinear(std::span<const double> p) : kc(p[0]) {}

    template <class T>
    T switching(int, const vec_t<T, 2>& X) const
    {
        return X[0];
    }
    template <class T>
    vec_t<T, 2> derivatives(const vec_t<T, 2>& X, const switch_sides& s) const
    {
        return {X[1], -(1.0 + kc * s.on(0)) * X[0]};
    }
    double kc;
};

// From x = 0, v = 1: x = sin(w t) / w (w = sqrt(1 + kc)) for a half period pi / w, then a half
// period pi of the softer side. The maxima, 1 / w, come every pi + pi / w, the first at
// pi / (2 w); two crossings per period.
TEST(Switching, BilinearOscillatorMaximaEveryPeriodAtConstantAmplitude)
{
    const double kc = 3.0, w = std::sqrt(1.0 + kc);
    const vimpact::native_model<bilinear> m(std::vector<double>{kc});
    auto o = flow_tolerances(1e-13, 10.5 * (pi + pi / w));
    o.events = {flow_event::state_extrema(0, crossing::down)};
    vimpact::hybrid_flow<vimpact::native_model<bilinear>> flow(m, o);
    flow.start(0.0, vec<2>(0.0, 1.0));
    recorder r;
    EXPECT_EQ(flow.run(r), outcome::time_limit);
    ASSERT_EQ(r.times.size(), 11U);
    for (std::size_t k = 0; k < r.times.size(); ++k) {
        EXPECT_NEAR(r.times[k], pi / (2.0 * w) + static_cast<double>(k) * (pi + pi / w), 1e-9) << k;
        EXPECT_NEAR(r.values[k], 1.0 / w, 1e-9) << k;
    }
    // Crossings at t = pi / w + k (pi + pi / w) (downward) and (k + 1) (pi + pi / w) (upward).
    ASSERT_EQ(r.switch_times.size(), 21U);
    for (std::size_t j = 0; j < r.switch_times.size(); ++j) {
        const double k = static_cast<double>(j / 2);
        const double expected = j % 2 == 0 ? pi / w + k * (pi + pi / w) : (k + 1.0) * (pi + pi / w);
        EXPECT_NEAR(r.switch_times[j], expected, 1e-9) << j;
    }
    EXPECT_EQ(flow.stats().switchings, 21);
    EXPECT_EQ(flow.stats().impacts, 0);
}

// ---- Housner's rocking block, linearised ----------------------------------------------------

// theta'' = -p^2 (alpha side - theta) (the block rocks about one corner or the other, by the
// side of theta), and at each crossing of theta = 0 the angular velocity drops by eta.
struct rocking {
    static constexpr std::string_view name = "rocking";
    static constexpr std::string_view description = "Housner's rocking block, linearised";
    static constexpr std::array<vimpact::state_variable, 2> state{{{"theta"}, {"omega"}}};
    static constexpr std::array<vimpact::parameter, 3> parameters{{{"p", 2.0}, {"alpha", 0.2}, {"eta", 0.9}}};
    static constexpr std::array<vimpact::impact_surface, 0> surfaces{};
    static constexpr std::array<vimpact::poincare_section, 0> sections{};
    static constexpr std::array<vimpact::switching_surface, 1> switches{{{"pivot", "theta = 0", crossing::both, true}}};

    explicit rocking(std::span<const double> q) : p(q[0]), alpha(q[1]), eta(q[2]) {}

    template <class T>
    T switching(int, const vec_t<T, 2>& X) const
    {
        return X[0];
    }
    template <class T>
    vec_t<T, 2> derivatives(const vec_t<T, 2>& X, const switch_sides& s) const
    {
        return {X[1], -p * p * (alpha * s.side(0) - X[0])};
    }
    template <class T>
    vec_t<T, 2> switch_reset(int, const vec_t<T, 2>& X, const switch_sides&) const
    {
        return {X[0], eta * X[1]};
    }
    double p, alpha, eta;
};

// From rest at theta0: on each side (theta - alpha side)^2 - (omega / p)^2 is constant, so a
// turning point of amplitude a reaches theta = 0 after acosh(alpha / (alpha - a)) / p with
// speed u = p sqrt(alpha^2 - (alpha - a)^2); the reset leaves eta u, which turns after
// atanh(eta u / (alpha p)) / p at amplitude alpha - sqrt(alpha^2 - (eta u / p)^2), on the
// other side.
TEST(Switching, LinearisedRockingBlockTurningPointsFromHousnersClosedForm)
{
    const double p = 2.0, alpha = 0.2, eta = 0.9, theta0 = 0.1;
    const vimpact::native_model<rocking> m(std::vector<double>{p, alpha, eta});
    auto o = flow_tolerances(1e-13, 0.0);
    // The closed form's turning points, then the run up to just past the sixth.
    std::vector<double> times{0.0}, amplitudes{theta0};
    for (int k = 0; k < 6; ++k) {
        const double a = amplitudes.back();
        const double u = eta * p * std::sqrt(alpha * alpha - (alpha - a) * (alpha - a));
        times.push_back(times.back() + std::acosh(alpha / (alpha - a)) / p + std::atanh(u / (alpha * p)) / p);
        amplitudes.push_back(alpha - std::sqrt(alpha * alpha - (u / p) * (u / p)));
    }
    o.t_max = times.back() + 1e-3;
    o.events = {flow_event::state_extrema(0, crossing::both)};
    vimpact::hybrid_flow<vimpact::native_model<rocking>> flow(m, o);
    flow.start(0.0, vec<2>(theta0, 0.0));
    recorder r;
    EXPECT_EQ(flow.run(r), outcome::time_limit);
    ASSERT_EQ(r.times.size(), 6U);
    for (std::size_t k = 0; k < r.times.size(); ++k) {
        EXPECT_NEAR(r.times[k], times[k + 1], 1e-9) << k;
        EXPECT_NEAR(std::abs(r.values[k]), amplitudes[k + 1], 1e-9) << k;
        EXPECT_EQ(r.values[k] > 0.0, k % 2 == 1) << k;  // the first turning point is on the other side
    }
    EXPECT_EQ(r.switches.size(), 6U);
}

// ---- a relay: the fields point into the surface from both sides ------------------------------

// x' = -side: from x = 1 the motion reaches x = 0 at t = 1, where the field of the other side
// points back. It would slide there (Filippov), which a switch does not model: the run ends
// with `sliding` at the crossing.
struct relay {
    static constexpr std::string_view name = "relay";
    static constexpr std::string_view description = "x' = -sgn(x)";
    static constexpr std::array<vimpact::state_variable, 2> state{{{"x"}, {"y"}}};
    static constexpr std::array<vimpact::parameter, 0> parameters{};
    static constexpr std::array<vimpact::impact_surface, 0> surfaces{};
    static constexpr std::array<vimpact::poincare_section, 0> sections{};
    static constexpr std::array<vimpact::switching_surface, 1> switches{{{"relay", "x = 0", crossing::both, true}}};

    explicit relay(std::span<const double>) {}

    template <class T>
    T switching(int, const vec_t<T, 2>& X) const
    {
        return X[0];
    }
    template <class T>
    vec_t<T, 2> derivatives(const vec_t<T, 2>&, const switch_sides& s) const
    {
        return {T(-s.side(0)), T(1.0)};
    }
};

TEST(Switching, FieldsPointingIntoTheSurfaceFromBothSidesEndTheRunSliding)
{
    const vimpact::native_model<relay> m(std::vector<double>{});
    vimpact::hybrid_flow<vimpact::native_model<relay>> flow(m, flow_tolerances(1e-12, 5.0));
    flow.start(0.0, vec<2>(1.0, 0.0));
    recorder r;
    EXPECT_EQ(flow.run(r), outcome::sliding);
    EXPECT_NEAR(flow.t(), 1.0, 1e-12);
    EXPECT_NEAR(flow.x()[0], 0.0, 1e-12);
    EXPECT_EQ(r.switches.size(), 1U);
}

// ---- a forced oscillator with a compliant stop ---------------------------------------------

// y'' + 2 zeta y' + y + on (kc (y - d) + cc y') = F cos(phi), phi' = omega, on = 1 where y > d:
// a spring-dashpot stop. The dashpot's force cc y' jumps at y = d, so the saltation of a
// crossing is not the identity: S = I + (F+ - F-) n^T / (n^T F-) has -cc in its (y', y) entry.
// Leaving the stop (a downward crossing of h = y - d) multiplies y' by r_exit, a reset that
// adds R' to the jump.
struct compliant_stop {
    static constexpr std::string_view name = "compliant_stop";
    static constexpr std::string_view description = "a forced oscillator with a spring-dashpot stop at y = d";
    static constexpr std::array<vimpact::state_variable, 3> state{{{"y"}, {"ydot"}, {"phi", "", "", 2.0 * pi}}};
    static constexpr std::array<vimpact::parameter, 7> parameters{{
        {"zeta", 0.05},
        {"omega", 0.8},
        {"F", 1.0},
        {"d", 1.0},
        {"kc", 4.0},
        {"cc", 0.4},
        {"r_exit", 1.0},
    }};
    static constexpr std::array<vimpact::impact_surface, 0> surfaces{};
    static constexpr std::array<vimpact::poincare_section, 1> sections{{{"strobe", crossing::up}}};
    static constexpr std::array<vimpact::switching_surface, 1> switches{{{"contact", "y = d", crossing::down, true}}};

    explicit compliant_stop(std::span<const double> p)
        : zeta(p[0]), omega(p[1]), F(p[2]), d(p[3]), kc(p[4]), cc(p[5]), r_exit(p[6])
    {
    }

    template <class T>
    T switching(int, const vec_t<T, 3>& X) const
    {
        return X[0] - d;
    }
    template <class T>
    vec_t<T, 3> derivatives(const vec_t<T, 3>& X, const switch_sides& s) const
    {
        using std::cos;
        const T contact = s.on(0) * (kc * (X[0] - d) + cc * X[1]);
        return {X[1], -X[0] - 2.0 * zeta * X[1] + F * cos(X[2]) - contact, T(omega)};
    }
    template <class T>
    vec_t<T, 3> switch_reset(int, const vec_t<T, 3>& X, const switch_sides&) const
    {
        return {X[0], r_exit * X[1], X[2]};
    }
    template <class T>
    T section(int, const vec_t<T, 3>& X) const
    {
        using std::sin;
        return sin(X[2]);
    }
    double zeta, omega, F, d, kc, cc, r_exit;
};

using stop_model = vimpact::native_model<compliant_stop>;

stop_model stop_with(double r_exit)
{
    auto p = vimpact::test::defaults<compliant_stop>();
    p[6] = r_exit;
    return stop_model(p);
}

// The strobe point after 300 forcing periods from rest: on the attracting orbit.
vec<3> settled_point(const stop_model& m)
{
    auto o = flow_tolerances(1e-11, 1e5);
    o.events = {flow_event::section(0, crossing::up)};
    struct last_point : vimpact::flow_observer {
        vec<3> x = vec<3>::Zero();
        long n = 0;
        flow_control on_section(int, crossing, double, const vec<3>& p)
        {
            x = p;
            return ++n >= 300 ? flow_control::stop : flow_control::proceed;
        }
    } obs;
    vimpact::hybrid_flow<stop_model> flow(m, o);
    flow.start(0.0, vec<3>(0.0, 0.0, 0.5));
    flow.run(obs);
    return obs.x;
}

// The Jacobian of the strobe map from the tangent flow (saltation matrices at every crossing
// of the stop) against central differences of the map itself, in the section's chart (phi
// dropped); the tangent flow without the saltation (the identity jump) is far from them, so
// the comparison can tell.
void expect_map_jacobian_matches_differences(double r_exit)
{
    const stop_model m = stop_with(r_exit);
    const vec<3> x = settled_point(m);
    vimpact::section_map_options mo;
    const auto base = vimpact::section_map<vimpact::dop853>(m, x, 1, mo);
    ASSERT_TRUE(base.valid());
    ASSERT_GT(base.stats.switchings, 0);
    const vimpact::section_chart<stop_model> chart(m, 0, x);
    ASSERT_EQ(chart.dropped(), 2);
    const auto jacobian_of = [&](const vimpact::section_return<3>& r) {
        return vimpact::mat<2>(chart.projection() * r.return_derivative * chart.embedding(x));
    };
    const vimpact::mat<2> jac = jacobian_of(base);
    // Central differences at 1e-4: their truncation (h^2 times the map's curvature) stays below
    // the integration's noise divided by h, which grows as h shrinks (5e-6 at h = 1e-6).
    const vimpact::mat<2> fd = vimpact::test::map_differences(m, chart, x, 1, 1e-4, mo);
    EXPECT_LT(vimpact::test::max_abs_diff(jac, fd), 1e-6 * (1.0 + fd.cwiseAbs().maxCoeff())) << jac << "\n" << fd;
    mo.jump = vimpact::impact_tangent::identity;
    const auto without = vimpact::section_map<vimpact::dop853>(m, x, 1, mo);
    EXPECT_GT(vimpact::test::max_abs_diff(jacobian_of(without), fd), 1e-2);
    // Liouville with the jumps: det of the monodromy = exp(integral of div F) prod det S.
    EXPECT_NEAR(std::log(std::abs(base.monodromy.determinant())), base.divergence_integral + base.log_det_jumps, 1e-8);
}

TEST(Switching, CompliantStopSectionMapJacobianMatchesFiniteDifferences) { expect_map_jacobian_matches_differences(1.0); }

TEST(Switching, ResetAtACrossingAddsItsJacobianToTheSaltation) { expect_map_jacobian_matches_differences(0.8); }

// The same definition as a runtime model (its function table, as a plugin is loaded): the
// Floquet analysis finds the orbit by itself, and its multipliers are the trivial 1 (the
// forcing phase) and the eigenvalues of the differences of the strobe map above.
TEST(Switching, FloquetMultipliersOfTheRuntimeModelAreThoseOfTheMapsDifferences)
{
    const vimpact::model handle = vimpact::model::from_definition<compliant_stop>();
    ASSERT_EQ(handle.info().switches.size(), 1U);
    EXPECT_EQ(handle.info().switches[0].name, "contact");
    vimpact::floquet_options fo;
    fo.protocol.record_points = 20;
    const vimpact::floquet_result r = vimpact::floquet(handle, Eigen::Vector3d(0.0, 0.0, 0.5), fo);
    ASSERT_EQ(r.status, outcome::ok) << to_string(r.status);
    // Its crossings are the events of the protocol: the transient is 500 of them, and the orbit
    // is labelled by its period (P0 is an orbit away from every surface and switch).
    EXPECT_EQ(r.label, "P1");
    EXPECT_EQ(r.impacts_per_period, 0);
    EXPECT_EQ(r.section_returns, 1);
    EXPECT_LT(r.trivial_error, 1e-8);
    EXPECT_GT(r.tangent_stats.switchings, 0);

    const stop_model m = stop_with(1.0);
    const vec<3> x = r.orbit_point;
    const vimpact::section_chart<stop_model> chart(m, 0, x);
    const vimpact::mat<2> fd = vimpact::test::map_differences(m, chart, x, 1, 1e-4);
    Eigen::EigenSolver<vimpact::mat<2>> es(fd);
    ASSERT_EQ(r.multipliers.size(), 3U);
    EXPECT_NEAR(std::abs(r.multipliers[0] - 1.0), 0.0, 1e-8);
    // Each eigenvalue of the differences is one of the nontrivial multipliers (a complex pair
    // has one modulus: matched by distance, not by order).
    for (int k = 0; k < 2; ++k) {
        const std::complex<double> e = es.eigenvalues()[k];
        EXPECT_LT(std::min(std::abs(r.multipliers[1] - e), std::abs(r.multipliers[2] - e)), 1e-6) << e;
    }
}

// Lyapunov exponents of the stable orbit with a reset at the exit of the stop (det S != 1):
// the sum rule holds with the crossings' jumps counted (sum of exponents = mean divergence +
// the rate of ln|det S|), and the exponents are ln|mu| / T of the Floquet multipliers.
TEST(Switching, LyapunovExponentsOfTheOrbitAreItsFloquetMultipliersLogsOverThePeriod)
{
    const vimpact::model handle = vimpact::model::from_definition<compliant_stop>().with_parameter(6, 0.8);
    vimpact::floquet_options fo;
    fo.protocol.record_points = 20;
    const auto f = vimpact::floquet(handle, Eigen::Vector3d(0.0, 0.0, 0.5), fo);
    ASSERT_EQ(f.status, outcome::ok);
    ASSERT_EQ(f.section_returns, 1);
    std::vector<double> expected{0.0};
    for (std::size_t k = 1; k < f.multipliers.size(); ++k) expected.push_back(std::log(std::abs(f.multipliers[k])) / f.period);
    std::sort(expected.begin(), expected.end(), [](double a, double b) { return a > b; });
    // The linear mappings of the deviations at an event: at a crossing of a switch the
    // second-order mapping is the saltation matrix (a switch's jump has no second-order
    // discontinuity map here); and Benettin's two trajectories (lyapunov_tdm::trajectory).
    for (const auto tdm :
         {vimpact::lyapunov_tdm::saltation, vimpact::lyapunov_tdm::second_order, vimpact::lyapunov_tdm::trajectory}) {
        vimpact::lyapunov_options lo;
        lo.tdm = tdm;
        const auto l = vimpact::lyapunov(handle, Eigen::Vector3d(0.0, 0.0, 0.5), lo);
        ASSERT_EQ(l.status, outcome::ok);
        ASSERT_EQ(l.exponents.size(), 3);
        if (tdm != vimpact::lyapunov_tdm::trajectory) {  // Benettin's has no jump matrices to sum
            EXPECT_NE(l.jump_log_det_rate, 0.0);
            EXPECT_NEAR(l.exponents.sum(), l.sum_rule, 1e-8);
        }
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(l.exponents[k], expected[static_cast<std::size_t>(k)], 2e-3) << k << " tdm " << static_cast<int>(tdm);
    }
}

// ---- model files -----------------------------------------------------------------------------

vimpact::floquet_result stop_floquet(const vimpact::model& m)
{
    vimpact::floquet_options fo;
    fo.protocol.record_points = 20;
    return vimpact::floquet(m, Eigen::Vector3d(0.0, 0.0, 0.5), fo);
}

// examples/models/compliant_stop.toml is the system of the definition above, with the
// switch written `on(contact)` in the field: its compiled code gives the same orbit and
// multipliers as the definition's automatic derivatives.
TEST(Switching, ModelFileWithASwitchGivesTheDefinitionsOrbitAndMultipliers)
{
    const vimpact::model file = vimpact::test::example_model("compliant_stop");
    ASSERT_EQ(file.info().switches.size(), 1U);
    EXPECT_EQ(file.info().switches[0].name, "contact");
    EXPECT_EQ(file.info().switches[0].direction, crossing::both);
    const auto a = stop_floquet(file);
    const auto b = stop_floquet(vimpact::model::from_definition<compliant_stop>());
    ASSERT_EQ(a.status, outcome::ok);
    ASSERT_EQ(b.status, outcome::ok);
    EXPECT_LT((a.orbit_point - b.orbit_point).cwiseAbs().maxCoeff(), 1e-9);
    ASSERT_EQ(a.multipliers.size(), b.multipliers.size());
    for (std::size_t k = 0; k < a.multipliers.size(); ++k) EXPECT_LT(std::abs(a.multipliers[k] - b.multipliers[k]), 1e-9);
    EXPECT_NEAR(a.period, b.period, 1e-9);
}

// Grazing of a switch: the switch-free orbit holds the side of the start. Below the compliant
// stop (y < d) that is the linear forced oscillator, whose steady amplitude is X = F /
// sqrt((1 - omega^2)^2 + (2 zeta omega)^2): the distance d - y to the switch has its minimum d -
// X (negative: the free orbit would cross), and d_graze = X. With the stop at d = 5 the margin
// is 5 - X > 0. The impact-surface-free model has no surface: the switch alone is grazed.
TEST(Switching, GrazingOfASwitchIsTheSwitchFreeOrbitsDistanceToIt)
{
    const vimpact::model file = vimpact::test::example_model("compliant_stop");
    const int d_index = file.info().parameter_index("d");
    const double zeta = 0.05, omega = 0.8, F = 1.0;  // the file's
    const double X = F / std::sqrt((1.0 - omega * omega) * (1.0 - omega * omega) + 4.0 * zeta * zeta * omega * omega);
    vimpact::grazing_options go;
    go.parameter = vimpact::each_surface_gap_parameter;
    for (const double d : {1.0, 5.0}) {
        const vimpact::model m = file.with_parameter(d_index, d);
        const auto g = vimpact::grazing(m, Eigen::Vector3d(0.0, 0.0, 0.5), go);
        ASSERT_EQ(g.status, outcome::ok);
        EXPECT_TRUE(g.converged);
        EXPECT_TRUE(g.surfaces.empty());
        ASSERT_EQ(g.switches.size(), 1U);
        const auto& s = g.switches[0];
        EXPECT_TRUE(s.converged);
        EXPECT_NEAR(s.margin, d - X, 1e-9) << d;
        EXPECT_EQ(s.parameter, d_index);
        EXPECT_NEAR(s.parameter_value, X, 1e-9) << d;
        EXPECT_NEAR(s.x[0], X, 1e-9);  // at the maximum of y
        EXPECT_EQ(g.stats.switchings, 0);  // the switch-free system never crosses
    }
    EXPECT_EQ(vimpact::switch_parameters(file, 0), std::vector<int>{d_index});
}

// Continuation through the grazing of a switch: the compliant stop's P1 orbit followed in the
// stop's position d from 5 (clear of the stop: the linear oscillator's orbit) to 2 (in
// contact). The orbit first touches the stop where d is its amplitude X (closed form); the
// flow is continuous there, so the branch goes on, now crossing the switch twice per period.
// Its multipliers before the grazing are the linear oscillator's, exp(-2 pi zeta / omega)
// in modulus.
TEST(Switching, ContinuationLocatesTheGrazingOfASwitchAndGoesOn)
{
    const vimpact::model m = vimpact::test::example_model("compliant_stop");
    const double zeta = 0.05, omega = 0.8, F = 1.0;  // the file's
    const double X = F / std::sqrt((1.0 - omega * omega) * (1.0 - omega * omega) + 4.0 * zeta * zeta * omega * omega);
    vimpact::continuation_options o;
    o.parameter = m.info().parameter_index("d");
    o.start = 5.0;
    o.end = 2.0;
    o.protocol.record_points = 20;
    const auto res = vimpact::continuation(m.with_parameter(o.parameter, 5.0), {Eigen::Vector3d(0.0, 0.0, 0.5)}, o, 1);
    ASSERT_EQ(res.status, outcome::ok) << res.start_label;
    ASSERT_EQ(res.branches.size(), 1U);
    const auto& branch = res.branches[0];
    EXPECT_EQ(branch.end, vimpact::branch_end::range);
    std::vector<const vimpact::bifurcation*> grazings;
    for (const auto& b : res.bifurcations)
        if (b.type == vimpact::bifurcation_type::grazing) grazings.push_back(&b);
    ASSERT_EQ(grazings.size(), 1U);
    const auto& g = *grazings[0];
    EXPECT_EQ(g.switch_surface, 0);
    EXPECT_EQ(g.surface, -1);
    EXPECT_EQ(g.crossings_before, 0);
    EXPECT_EQ(g.crossings_after, 2);  // into the stop and out, once per period
    EXPECT_TRUE(g.located);
    EXPECT_NEAR(g.parameter, X, 1e-8);
    const double mod = std::exp(-2.0 * pi * zeta / omega);
    for (const auto& p : branch.points) {
        if (p.parameter < X + 0.01) continue;
        for (const auto& mu : p.section_multipliers) EXPECT_NEAR(std::abs(mu), mod, 1e-7) << p.parameter;
    }
    EXPECT_LT(branch.points.back().parameter, X);  // past the grazing
}

// The compliant stop's law written as users write it, with abs, sgn, heaviside, min or max of
// the state: each kink becomes a switch of its own (one per distinct argument, so each
// variant has one, named after the first of abs, sgn, heaviside, min, max that makes it),
// located as an event, and the orbit and multipliers are the explicit switch's. Inside a step the kink would cost the integrator its order and the monodromy its
// saltation (the dashpot's force jumps), which the multipliers' 1e-9 would show.
TEST(Switching, KinksOfTheStateInALawAreSwitchesOfTheirOwn)
{
    const std::string text = vimpact::test::example_text("compliant_stop");
    const std::string law = "on(contact)*(kc*(y - d) + cc*v)", declared = "[[switches]]";
    const auto at_law = text.find(law), at_switch = text.find(declared), at_sections = text.find("[[sections]]");
    ASSERT_NE(at_law, std::string::npos);
    ASSERT_NE(at_switch, std::string::npos);
    ASSERT_NE(at_sections, std::string::npos);
    const auto b = stop_floquet(vimpact::test::example_model("compliant_stop"));
    ASSERT_EQ(b.status, outcome::ok);
    const std::array<std::pair<std::string, std::string>, 4> written{{
        {"heaviside(y - d)*(kc*(y - d) + cc*v)", "heaviside#1"},
        {"(kc*max(y - d, 0) + cc*v*heaviside(y - d))", "heaviside#1"},
        {"(kc*(y - d + abs(y - d))/2 + cc*v*(1 + sgn(y - d))/2)", "abs#1"},
        {"(-kc*min(d - y, 0) + cc*v*heaviside(y - d))", "heaviside#1"},
    }};
    for (const auto& [form, name] : written) {
        std::string variant = text.substr(0, at_switch) + text.substr(at_sections);
        variant.replace(at_law, law.size(), form);
        const vimpact::model m = vimpact::test::model_from_text(variant, name + ".toml");
        ASSERT_EQ(m.info().switches.size(), 1U) << form;
        EXPECT_EQ(m.info().switches[0].name, name);
        EXPECT_EQ(m.info().switches[0].direction, crossing::both);
        const auto a = stop_floquet(m);
        ASSERT_EQ(a.status, outcome::ok) << form;
        EXPECT_LT((a.orbit_point - b.orbit_point).cwiseAbs().maxCoeff(), 1e-9) << form;
        ASSERT_EQ(a.multipliers.size(), b.multipliers.size());
        for (std::size_t k = 0; k < a.multipliers.size(); ++k)
            EXPECT_LT(std::abs(a.multipliers[k] - b.multipliers[k]), 1e-9) << form;
    }
}

// The time the full rocking block takes from a turning point of amplitude a to theta = 0 (or
// back), by quadrature of the energy: omega^2 = 2 p^2 (cos(alpha - a) - cos(alpha - theta)),
// T = integral over [0, a] of dtheta / |omega|. With theta = a - u^2 the square-root
// singularity at the turning point goes: cos(alpha - a) - cos(alpha - theta) = 2 sin(alpha -
// a + u^2/2) sin(u^2/2), and the integrand sqrt(2 / sinc(u^2/2)) / (p sqrt(sin(alpha - a +
// u^2/2))) is smooth on [0, sqrt(a)]: composite Simpson's rule with 4000 intervals.
double rocking_quarter_time(double a, double p, double alpha)
{
    const auto f = [&](double u) {
        const double s = 0.5 * u * u;
        const double sinc = s == 0.0 ? 1.0 : std::sin(s) / s;
        return std::sqrt(2.0 / sinc) / (p * std::sqrt(std::sin(alpha - a + s)));
    };
    const int n = 4000;
    const double h = std::sqrt(a) / n;
    double sum = f(0.0) + f(std::sqrt(a));
    for (int k = 1; k < n; ++k) sum += (k % 2 ? 4.0 : 2.0) * f(k * h);
    return sum * h / 3.0;
}

// examples/models/rocking_block.toml, Housner's full block. On each side the energy
// omega^2/2 + p^2 cos(alpha side - theta) is constant, so a crossing leaves with the speed it
// arrived at the one before times eta, and a turning point of amplitude a is followed by one
// of amplitude b on the other side with cos(alpha - b) = cos(alpha) + eta^2 (cos(alpha - a) -
// cos(alpha)); the times between them are quarter swings by the energy quadrature above. The
// crossings accumulate as the block comes to rest; once one is slower than the sticking
// velocity the run ends `sliding` there, at rest on theta = 0.
TEST(Switching, FullRockingBlockTurnsWhereItsEnergySaysAndComesToRest)
{
    const vimpact::model m = vimpact::test::example_model("rocking_block");
    const double p = 2.0, alpha = 0.2, eta = 1.0 - 1.5 * std::sin(alpha) * std::sin(alpha), theta0 = 0.1;  // the file's
    vimpact::protocol_options o;
    o.transient_impacts = 0;
    o.record_points = 100000;
    o.flow.integration.rtol = o.flow.integration.atol = 1e-12;
    const vimpact::simulation r = vimpact::simulate(m, Eigen::Vector2d(theta0, 0.0), o);
    EXPECT_EQ(r.status, outcome::sliding);
    EXPECT_LT(std::abs(r.final_state[0]), 1e-12);
    EXPECT_LT(std::abs(r.final_state[1]), 1e-8);
    // About log(1e-8 / 0.35) / log(eta) = 285 crossings before the speed falls below 1e-8.
    ASSERT_GT(r.switchings.size(), 200U);
    EXPECT_LT(r.switchings.size(), 400U);
    double a = theta0;
    double crossing = rocking_quarter_time(theta0, p, alpha);  // the first, from rest at theta0
    for (std::size_t k = 0; k < 20; ++k) {
        EXPECT_NEAR(r.switchings.pre.t(k), crossing, 1e-9) << k;
        a = alpha - std::acos(std::cos(alpha) + eta * eta * (std::cos(alpha - a) - std::cos(alpha)));
        EXPECT_NEAR(std::abs(r.points.x(k, 0)), a, 1e-9) << k;
        EXPECT_EQ(r.points.x(k, 0) > 0.0, k % 2 == 1) << k;
        const double quarter = rocking_quarter_time(a, p, alpha);
        EXPECT_NEAR(r.points.t(k), crossing + quarter, 1e-9) << k;
        crossing += 2.0 * quarter;
    }
    for (std::size_t k = 1; k < 20; ++k) {
        const double before = r.switchings.pre.x(k - 1, 1), now = r.switchings.pre.x(k, 1);
        EXPECT_NEAR(std::abs(now), eta * std::abs(before), 1e-9 * std::abs(before)) << k;
    }
}

// A model file's mistakes with switches are refused when it is loaded, naming the key.
TEST(Switching, ModelFileRefusesSidesWhereTheyCannotBe)
{
    const auto text = [](const std::string& derived, const std::string& field, const std::string& when) {
        return "name = \"s\"\nstate = [{ name = \"x\" }, { name = \"v\" }]\n"
               "[parameters]\nk = { default = 1.0 }\n" +
               (derived.empty() ? std::string() : "[derived]\nq = \"" + derived + "\"\n") +
               "[derivatives]\nx = \"v\"\nv = \"" + field + "\"\n"
               "[[switches]]\nname = \"spring\"\nwhen = \"" + when + "\"\n";
    };
    const auto message = [](const std::string& toml) {
        try {
            (void)vimpact::model::from_toml(toml, "s.toml");
        } catch (const vimpact::input_error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(message(text("", "-(1 + k*on(k))*x", "x")).find("'k' is not a switch"), std::string::npos);
    EXPECT_NE(message(text("", "-(1 + k*spring)*x", "x")).find("'spring' is a switch: write side(spring)"),
              std::string::npos);
    EXPECT_NE(message(text("k*side(spring)", "-x", "x")).find("derived.q"), std::string::npos);
    EXPECT_NE(message(text("", "-x", "x*side(spring)")).find("switching function cannot use side()"),
              std::string::npos);
    EXPECT_NE(message(text("", "-(1 + k*on())*x", "x")).find("on() takes the name of a switch"), std::string::npos);
    EXPECT_NE(message(text("", "-(1 + k*abs(x*side(spring)))*x", "x"))
                  .find("derivatives.v: abs() of an expression with side() or on() cannot become a switch"),
              std::string::npos);
}

}  // namespace
