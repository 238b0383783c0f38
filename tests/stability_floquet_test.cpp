// Tests of the section map, Newton shooting and Floquet analysis (tangent/section_map.hpp,
// analysis/floquet.hpp): the trivial multiplier on impacting P1, P2 and P3 orbits of the
// paper's model with and without the saltation correction, Liouville's identity for the
// determinant, the section map's Jacobian against finite differences, and the forced impact
// oscillator's one-impact orbits against their closed form. Measured numbers are printed
// (docs/stability.md quotes them).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <vector>

#include "test_support.hpp"
#include "vimpact/analysis/floquet.hpp"
#include "vimpact/model/builtin/wake_impact.hpp"
#include "vimpact/model/native_model.hpp"
#include "map_differences.hpp"
#include "vimpact/tangent/section_map.hpp"

namespace {

using vimpact::impact_tangent;
using vimpact::mat;
using vimpact::outcome;
using vimpact::vec;
using vimpact::test::paper;
using vimpact::test::paper_ic;
using cplx = std::complex<double>;
using wake = vimpact::native_model<vimpact::wake_impact>;
constexpr double pi = std::numbers::pi;

vimpact::floquet_result paper_floquet(double Ur, impact_tangent jump = impact_tangent::saltation)
{
    vimpact::floquet_options opt;
    opt.jump = jump;
    return vimpact::floquet(paper(Ur), paper_ic(), opt);
}

double distance_to_one(const std::vector<cplx>& mu)
{
    double d = 1e300;
    for (const auto& m : mu) d = std::min(d, std::abs(m - 1.0));
    return d;
}

vimpact::model forced(double zeta, double F, double omega, double sigma)
{
    using vimpact::test::with;
    return with(with(with(with(vimpact::model::builtin("forced_impact_oscillator"), "zeta", zeta), "F", F), "omega",
                     omega),
                "sigma", sigma);
}

// ---- the trivial multiplier ---------------------------------------------------------------

// With the saltation matrix at the impacts the monodromy maps F(x*) to itself: one multiplier
// is 1 to within 1e-9 (in practice ~1e-12). With the reset Jacobian alone, or nothing, at the
// impacts, no multiplier is near 1: the tangent dynamics is wrong at every impact.
TEST(StabilityFloquet, TrivialMultiplierIsOneOnlyWithSaltation)
{
    struct expectation {
        double Ur;
        const char* label;
    };
    for (const auto& e : {expectation{14.0, "P1"}, expectation{16.0, "P2"}, expectation{19.0, "P3"}}) {
        const auto r = paper_floquet(e.Ur);
        ASSERT_EQ(r.status, outcome::ok) << "Ur " << e.Ur;
        EXPECT_EQ(r.label, e.label);
        EXPECT_EQ(r.impacts_per_period, 1);
        EXPECT_EQ(r.impacts_by_surface, std::vector<long>{1});
        EXPECT_LE(r.closure, 1e-11);
        ASSERT_EQ(r.multipliers.size(), 4u);
        EXPECT_LE(r.trivial_error, 1e-9) << "Ur " << e.Ur;
        EXPECT_LE(r.trivial_residual, 1e-9) << "Ur " << e.Ur;
        EXPECT_TRUE(r.stable());
        const auto without_s = paper_floquet(e.Ur, impact_tangent::reset_jacobian);
        const auto nothing = paper_floquet(e.Ur, impact_tangent::identity);
        ASSERT_EQ(without_s.status, outcome::ok);
        ASSERT_EQ(nothing.status, outcome::ok);
        EXPECT_GT(distance_to_one(without_s.multipliers), 0.03) << "Ur " << e.Ur;
        EXPECT_GT(distance_to_one(nothing.multipliers), 0.03) << "Ur " << e.Ur;
        std::printf("[ measured ] Ur = %g %s: T = %.10g, closure %.2e (from %.2e, %d Newton steps), "
                    "|mu_trivial - 1| = %.2e with saltation, min |mu - 1| = %.3f with R' alone, "
                    "%.3f with the identity\n",
                    e.Ur, e.label, r.period, r.closure, r.initial_closure, r.newton_iterations, r.trivial_error,
                    distance_to_one(without_s.multipliers), distance_to_one(nothing.multipliers));
    }
}

// ---- Liouville's identity -----------------------------------------------------------------

// det Phi(T) = exp(integral of div F over T) * r^(2 * impacts). The divergence integral is the
// quadrature carried by the variational flow; it is itself checked against Simpson's rule on
// the sampled orbit. The determinant is resolved relative to |Phi|^N eps: with multipliers
// 1, 0.49, 0.059, 4e-5 (P1, Ur = 14) the identity holds to 1e-8; at Ur = 16 the smallest
// multiplier is 5e-9 and the determinant 2e-12, so round-off and the 1e-12 tolerance of the
// tangent allow 1e-4 relative there.
TEST(StabilityFloquet, DeterminantObeysLiouvilleWithRSquaredPerImpact)
{
    for (double Ur : {14.0, 16.0}) {
        const vimpact::model m = paper(Ur);
        const wake native(m.parameters());
        vimpact::floquet_options opt;
        opt.sample_dt = 1e-3;
        const auto r = vimpact::floquet(m, paper_ic(), opt);
        ASSERT_EQ(r.status, outcome::ok);
        const double rr = m.parameter(m.info().parameter_index("r"));
        const double n = static_cast<double>(r.impacts_per_period);
        EXPECT_NEAR(r.log_det_jumps, n * std::log(rr * rr), 1e-12);
        const double predicted = std::exp(r.divergence_integral) * std::pow(rr, 2.0 * n);
        const double rel = std::abs(r.det_monodromy - predicted) / predicted;
        EXPECT_LE(rel, Ur == 14.0 ? 1e-8 : 1e-4) << "Ur " << Ur;
        EXPECT_NEAR(r.liouville_det, predicted, 1e-12 * predicted);

        // Simpson's rule on the samples (uniform except the last, shorter interval).
        const auto& s = r.orbit;
        ASSERT_GT(s.size(), 1000u);
        auto div_at = [&](std::size_t i) { return native.divergence(vec<4>(s.x(i))); };
        double integral = 0.0;
        std::size_t i = 0;
        for (; i + 2 < s.size() && s.t(i + 2) <= r.period; i += 2)
            integral += (s.t(i + 2) - s.t(i)) / 6.0 * (div_at(i) + 4.0 * div_at(i + 1) + div_at(i + 2));
        for (; i + 1 < s.size(); ++i) integral += 0.5 * (s.t(i + 1) - s.t(i)) * (div_at(i) + div_at(i + 1));
        EXPECT_NEAR(integral, r.divergence_integral, 1e-7 * std::abs(r.divergence_integral));
        std::printf("[ measured ] Ur = %g: det Phi = %.10e, exp(int div F) r^(2 n) = %.10e, relative "
                    "difference %.2e\n",
                    Ur, r.det_monodromy, predicted, rel);
    }
}

// ---- the section map ----------------------------------------------------------------------

// D P^k from the tangent flow (flow STMs, saltation matrices, projection along F onto Sigma)
// against central differences of the map itself, in the chart of the section (ydot dropped).
TEST(StabilityFloquet, SectionMapJacobianMatchesFiniteDifferences)
{
    const vimpact::model handle = paper(16.0);
    const wake m(handle.parameters());
    const auto r = paper_floquet(16.0);
    ASSERT_EQ(r.status, outcome::ok);
    const vec<4> x_star = r.orbit_point;
    const auto base = vimpact::section_map<vimpact::dop853>(m, x_star, 2);
    ASSERT_TRUE(base.valid());
    const vimpact::section_chart<wake> chart(m, 0, x_star);
    ASSERT_EQ(chart.dropped(), 1);  // the section ydot = 0 is solved for ydot
    const mat<3> jac = chart.projection() * base.return_derivative * chart.embedding(x_star);
    const mat<3> fd = vimpact::test::map_differences(m, chart, x_star, 2, 1e-6);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            EXPECT_NEAR(jac(i, j), fd(i, j), 1e-6 * (1.0 + std::abs(fd(i, j)))) << i << "," << j;
    // On Sigma the end state has v = 0 exactly, and the period is the sum of two returns.
    EXPECT_EQ(base.x_end[1], 0.0);
    EXPECT_NEAR(base.time, r.period, 1e-12);
}

// Newton converges to the same orbit from a start 1e-3 away, quadratically (a few steps).
TEST(StabilityFloquet, NewtonConvergesFromAPerturbedStart)
{
    const vimpact::model handle = paper(16.0);
    const wake m(handle.parameters());
    const auto r = paper_floquet(16.0);
    ASSERT_EQ(r.status, outcome::ok);
    const vec<4> x_star = r.orbit_point;
    const vec<4> guess = x_star + vec<4>(1e-3, 0.0, -1e-3, 2e-3);
    const auto orb = vimpact::find_periodic_orbit<vimpact::dop853>(m, guess, 2);
    ASSERT_EQ(orb.status, outcome::ok);
    EXPECT_LE(orb.iterations, 5);
    EXPECT_LE(orb.closure, 1e-11);
    EXPECT_LE(vimpact::test::max_abs_diff(orb.x, x_star), 1e-10);
}

// A chaotic point is reported as aperiodic, with no multipliers.
TEST(StabilityFloquet, AperiodicPointHasNoMultipliers)
{
    const auto r = vimpact::floquet(paper(25.0, -0.146), paper_ic(), {});
    EXPECT_EQ(r.status, outcome::aperiodic);
    EXPECT_EQ(r.label, "aperiodic");
    EXPECT_FALSE(r.has_multipliers());
    EXPECT_TRUE(r.multipliers.empty());
}

// A tangent run through a sticking phase is reported, not computed (variational.hpp). The
// forcing pulls the structure onto the barrier: it chatters (each hop a return to Sigma),
// sticks, is released and oscillates; 200 returns include the sticking phase.
TEST(StabilityFloquet, StickingIsReportedAsSuch)
{
    const auto m = forced(0.0, 1.0 / 32.0, 0.05, 1.0 / 64.0);
    const auto r = vimpact::floquet_from_point(m, Eigen::Vector3d(1.0 / 32.0, 0.0, pi), 200, {});
    EXPECT_EQ(r.status, outcome::sticking);
    EXPECT_TRUE(r.multipliers.empty());
}

TEST(StabilityFloquet, ResultsAreBitIdentical)
{
    const auto a = paper_floquet(19.0);
    const auto b = paper_floquet(19.0);
    ASSERT_EQ(a.multipliers.size(), b.multipliers.size());
    for (std::size_t i = 0; i < a.multipliers.size(); ++i) EXPECT_EQ(a.multipliers[i], b.multipliers[i]);
    EXPECT_EQ(a.period, b.period);
}

// ---- the forced impact oscillator in closed form --------------------------------------------
//
// y'' + 2 zeta y' + y = F cos(theta), theta' = omega. Between impacts (y, v) = P(theta) +
// E(t) ((y, v)(0) - P(theta0)) with the periodic response P(theta) = (y_p, omega y_p'),
// y_p = C cos theta + D sin theta, C = F (1 - omega^2) / Delta, D = 2 zeta omega F / Delta,
// Delta = (1 - omega^2)^2 + (2 zeta omega)^2, and E(t) = exp(t [[0, 1], [-1, -2 zeta]]) =
// e^{-zeta t} [[c + zeta s / w, s / w], [-s / w, c - zeta s / w]] (w = sqrt(1 - zeta^2),
// c = cos w t, s = sin w t).
// An orbit with one impact per forcing period T = 2 pi / omega, at phase phi with speed v < 0:
// E(T) (sigma - y_p(phi), -r v - v_p(phi)) = (sigma - y_p(phi), v - v_p(phi)). The first row
// gives v(phi) explicitly, the second a scalar equation g(phi) = 0 for the phase.
// Its monodromy from just after the impact is M = S Phi_T with
// Phi_T = [[E(T), (I - E(T)) P'(phi)], [0, 0, 1]] and S the saltation matrix at (sigma, v, phi)
// in closed form, S = [[-r, 0, 0], [(a+ + r a-)/v, -r, 0], [0, 0, 1]] with the accelerations
// a-+ = -sigma -+ 2 zeta (v, -r v) + F cos phi before and after. One multiplier is 1
// (theta' = omega is constant); the other two satisfy mu1 mu2 = det M = r^2 e^{-2 zeta T} and
// mu1 + mu2 = trace M - 1.
struct forced_parameters {
    double zeta = 0.05, omega = 0.8, F = 1.0, sigma = -1.0, r = 0.8;  // the model's defaults
};

struct forced_orbit {
    double phase;
    double v;
    cplx mu1, mu2;
};

std::vector<forced_orbit> forced_one_impact_orbits(const forced_parameters& p)
{
    const double z = p.zeta, om = p.omega, r = p.r, sg = p.sigma;
    const double w = std::sqrt(1.0 - z * z), T = 2.0 * pi / om;
    const double delta = (1 - om * om) * (1 - om * om) + (2 * z * om) * (2 * z * om);
    const double C = p.F * (1 - om * om) / delta, D = 2 * z * om * p.F / delta;
    const double c = std::cos(w * T), s = std::sin(w * T), e = std::exp(-z * T);
    mat<2> E;
    E << e * (c + z * s / w), e * s / w, -e * s / w, e * (c - z * s / w);
    auto yp = [&](double ph) { return C * std::cos(ph) + D * std::sin(ph); };
    auto vp = [&](double ph) { return om * (-C * std::sin(ph) + D * std::cos(ph)); };
    auto v_of = [&](double ph) {
        return (E(0, 0) * (sg - yp(ph)) - E(0, 1) * vp(ph) - (sg - yp(ph))) / (r * E(0, 1));
    };
    auto g = [&](double ph) {
        const double v = v_of(ph);
        return E(1, 0) * (sg - yp(ph)) + E(1, 1) * (-r * v - vp(ph)) - (v - vp(ph));
    };
    std::vector<forced_orbit> out;
    const int n = 7200;
    for (int k = 0; k < n; ++k) {
        double a = 2 * pi * k / n, b = 2 * pi * (k + 1) / n;
        double ga = g(a);
        const double gb = g(b);
        if ((ga > 0) == (gb > 0)) continue;
        for (int it = 0; it < 200 && b - a > 1e-16; ++it) {
            const double mid = 0.5 * (a + b), gm = g(mid);
            if ((gm > 0) == (ga > 0)) {
                a = mid;
                ga = gm;
            } else {
                b = mid;
            }
        }
        const double ph = 0.5 * (a + b), v = v_of(ph);
        if (!(v < 0.0)) continue;
        const double am = -sg - 2.0 * z * v + p.F * std::cos(ph);
        const double ap = -sg + 2.0 * z * r * v + p.F * std::cos(ph);
        mat<3> S;
        S << -r, 0.0, 0.0, (ap + r * am) / v, -r, 0.0, 0.0, 0.0, 1.0;
        const vec<2> dP(-C * std::sin(ph) + D * std::cos(ph), om * (-C * std::cos(ph) - D * std::sin(ph)));
        mat<3> Phi = mat<3>::Identity();
        Phi.block<2, 2>(0, 0) = E;
        Phi.block<2, 1>(0, 2) = (mat<2>::Identity() - E) * dP;
        const mat<3> M = S * Phi;
        const double tau = M.trace() - 1.0, det = r * r * std::exp(-2.0 * z * T);
        const cplx root = std::sqrt(cplx(tau * tau - 4.0 * det, 0.0));
        out.push_back({ph, v, 0.5 * (tau + root), 0.5 * (tau - root)});
    }
    return out;
}

void check_forced_against_closed_form(const forced_parameters& p, const char* expected_label)
{
    using vimpact::test::with;
    const vimpact::model m = with(forced(p.zeta, p.F, p.omega, p.sigma), "r", p.r);
    vimpact::floquet_options opt;
    opt.protocol.transient_impacts = 200;
    opt.protocol.record_points = 40;
    const auto r = vimpact::floquet(m, Eigen::Vector3d::Zero(), opt);
    ASSERT_EQ(r.status, outcome::ok);
    EXPECT_EQ(r.label, expected_label);
    ASSERT_EQ(r.impacts_per_period, 1);
    EXPECT_NEAR(r.period, 2.0 * pi / p.omega, 1e-10);
    const double raw_phase = std::remainder(r.impacts.pre.x(0, 2), 2.0 * pi);
    const double phase = raw_phase + (raw_phase < 0 ? 2.0 * pi : 0.0);
    const auto closed = forced_one_impact_orbits(p);
    const forced_orbit* match = nullptr;
    for (const auto& o : closed)
        if (std::abs(std::remainder(o.phase - phase, 2.0 * pi)) < 1e-6) match = &o;
    ASSERT_NE(match, nullptr) << "no closed-form orbit at the impact phase " << phase;
    EXPECT_NEAR(r.impacts.pre.x(0, 1), match->v, 1e-9);
    EXPECT_NEAR(std::abs(std::remainder(match->phase - phase, 2.0 * pi)), 0.0, 1e-9);
    EXPECT_LE(r.trivial_error, 1e-12);
    ASSERT_EQ(r.multipliers.size(), 3u);
    // The nontrivial pair, as an unordered pair.
    const cplx a = r.multipliers[1], b = r.multipliers[2];
    const double d1 = std::max(std::abs(a - match->mu1), std::abs(b - match->mu2));
    const double d2 = std::max(std::abs(a - match->mu2), std::abs(b - match->mu1));
    EXPECT_LE(std::min(d1, d2), 1e-9);
    std::printf("[ measured ] forced oscillator omega = %g, sigma = %g (%s): multipliers %.12f%+.12fi, "
                "%.12f%+.12fi; closed form %.12f%+.12fi, %.12f%+.12fi; max difference %.2e\n",
                p.omega, p.sigma, expected_label, a.real(), a.imag(), b.real(), b.imag(), match->mu1.real(),
                match->mu1.imag(), match->mu2.real(), match->mu2.imag(), std::min(d1, d2));
}

// P1: one maximum and one impact per forcing period.
TEST(StabilityFloquet, ForcedOscillatorP1MultipliersMatchClosedForm)
{
    forced_parameters p;
    p.omega = 1.2;
    p.sigma = -0.3;
    check_forced_against_closed_form(p, "P1");
}

// One impact per forcing period but two maxima (label P2): the closed form is the same.
TEST(StabilityFloquet, ForcedOscillatorOneImpactOrbitWithTwoMaximaMatchesClosedForm)
{
    check_forced_against_closed_form(forced_parameters{}, "P2");
}

}  // namespace
