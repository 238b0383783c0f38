// Tests of the section map, Newton shooting and Floquet analysis (stability/section_map.hpp,
// stability/floquet.hpp): the trivial multiplier on impacting P1, P2 and P3 orbits of the
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

#include "vimpact/model/forced_impact_oscillator.hpp"
#include "vimpact/model/wake_impact.hpp"
#include "vimpact/stability/floquet.hpp"

namespace {

using vimpact::floquet_status;
using vimpact::impact_tangent;
using vimpact::mat;
using vimpact::vec;
using cplx = std::complex<double>;
constexpr double pi = std::numbers::pi;

vimpact::wake_impact paper(double Ur)
{
    vimpact::wake_impact_parameters p;
    p.Ur = Ur;
    return vimpact::wake_impact(p);
}

const vec<4> paper_ic(0.0, 0.0, 0.0, 0.1);

vimpact::floquet_result<4> paper_floquet(double Ur, impact_tangent jump = impact_tangent::saltation)
{
    vimpact::floquet_options opt;
    opt.jump = jump;
    return vimpact::floquet_analysis(paper(Ur), paper_ic, opt);
}

double distance_to_one(const std::vector<cplx>& mu)
{
    double d = 1e300;
    for (const auto& m : mu) d = std::min(d, std::abs(m - 1.0));
    return d;
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
        ASSERT_EQ(r.status, floquet_status::ok) << "Ur " << e.Ur;
        EXPECT_EQ(r.label, e.label);
        EXPECT_EQ(r.impacts_per_period, 1);
        EXPECT_LE(r.closure, 1e-11);
        ASSERT_EQ(r.multipliers.size(), 4u);
        EXPECT_LE(r.trivial_error, 1e-9) << "Ur " << e.Ur;
        EXPECT_LE(r.trivial_residual, 1e-9) << "Ur " << e.Ur;
        EXPECT_TRUE(r.stable());
        const auto without_s = paper_floquet(e.Ur, impact_tangent::reset_jacobian);
        const auto nothing = paper_floquet(e.Ur, impact_tangent::identity);
        ASSERT_EQ(without_s.status, floquet_status::ok);
        ASSERT_EQ(nothing.status, floquet_status::ok);
        EXPECT_GT(distance_to_one(without_s.multipliers), 0.03) << "Ur " << e.Ur;
        EXPECT_GT(distance_to_one(nothing.multipliers), 0.03) << "Ur " << e.Ur;
        std::printf("[ measured ] Ur = %g %s: T = %.10g, closure %.2e (from %.2e, %d Newton steps), "
                    "|mu_trivial - 1| = %.2e with saltation, min |mu - 1| = %.3f with R' alone, "
                    "%.3f with the identity\n",
                    e.Ur, e.label, r.period, r.closure, r.initial_closure, r.newton_iterations,
                    r.trivial_error, distance_to_one(without_s.multipliers), distance_to_one(nothing.multipliers));
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
        const auto m = paper(Ur);
        vimpact::floquet_options opt;
        opt.sample_dt = 1e-3;
        const auto r = vimpact::floquet_analysis(m, paper_ic, opt);
        ASSERT_EQ(r.status, floquet_status::ok);
        const double rr = m.restitution();
        EXPECT_NEAR(r.log_det_jumps, static_cast<double>(r.impacts_per_period) * std::log(rr * rr), 1e-12);
        const double predicted = std::exp(r.divergence_integral) * std::pow(rr, 2.0 * static_cast<double>(r.impacts_per_period));
        const double rel = std::abs(r.det_monodromy - predicted) / predicted;
        EXPECT_LE(rel, Ur == 14.0 ? 1e-8 : 1e-4) << "Ur " << Ur;

        // Simpson's rule on the samples (uniform except the last, shorter interval).
        const auto& s = r.orbit;
        ASSERT_GT(s.size(), 1000u);
        double integral = 0.0;
        std::size_t i = 0;
        for (; i + 2 < s.size() && s[i + 2].t <= r.period; i += 2)
            integral += (s[i + 2].t - s[i].t) / 6.0 *
                        (m.divergence(s[i].x) + 4.0 * m.divergence(s[i + 1].x) + m.divergence(s[i + 2].x));
        for (; i + 1 < s.size(); ++i)
            integral += 0.5 * (s[i + 1].t - s[i].t) * (m.divergence(s[i].x) + m.divergence(s[i + 1].x));
        EXPECT_NEAR(integral, r.divergence_integral, 1e-7 * std::abs(r.divergence_integral));
        std::printf("[ measured ] Ur = %g: det Phi = %.10e, exp(int div F) r^(2 n) = %.10e, relative "
                    "difference %.2e\n",
                    Ur, r.det_monodromy, predicted, rel);
    }
}

// ---- the section map ----------------------------------------------------------------------

// D P^k from the tangent flow (flow STMs, saltation matrices, projection along F onto Sigma)
// against central differences of the map itself.
TEST(StabilityFloquet, SectionMapJacobianMatchesFiniteDifferences)
{
    const auto m = paper(16.0);
    const auto r = paper_floquet(16.0);
    ASSERT_EQ(r.status, floquet_status::ok);
    const auto base = vimpact::section_map(m, r.orbit_point, 2);
    ASSERT_TRUE(base.valid());
    const double h = 1e-6;
    mat<3> fd;
    for (int j = 0; j < 3; ++j) {
        vec<3> z = vimpact::to_section<vimpact::wake_impact>(r.orbit_point);
        z[j] += h;
        const auto plus = vimpact::section_map(m, vimpact::from_section<vimpact::wake_impact>(z), 2);
        z[j] -= 2.0 * h;
        const auto minus = vimpact::section_map(m, vimpact::from_section<vimpact::wake_impact>(z), 2);
        ASSERT_TRUE(plus.valid() && minus.valid());
        fd.col(j) = (vimpact::to_section<vimpact::wake_impact>(plus.x_end) -
                     vimpact::to_section<vimpact::wake_impact>(minus.x_end)) / (2.0 * h);
    }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            EXPECT_NEAR(base.jacobian(i, j), fd(i, j), 1e-6 * (1.0 + std::abs(fd(i, j)))) << i << "," << j;
    // On Sigma the end state has v = 0 exactly, and the period is the sum of two returns.
    EXPECT_EQ(base.x_end[1], 0.0);
    EXPECT_NEAR(base.time, r.period, 1e-12);
}

// Newton converges to the same orbit from a start 1e-3 away, quadratically (a few steps).
TEST(StabilityFloquet, NewtonConvergesFromAPerturbedStart)
{
    const auto m = paper(16.0);
    const auto r = paper_floquet(16.0);
    ASSERT_EQ(r.status, floquet_status::ok);
    vec<4> guess = r.orbit_point + vec<4>(1e-3, 0.0, -1e-3, 2e-3);
    const auto orb = vimpact::find_periodic_orbit(m, guess, 2);
    ASSERT_EQ(orb.status, vimpact::shooting_status::converged);
    EXPECT_LE(orb.iterations, 5);
    EXPECT_LE(orb.closure, 1e-11);
    EXPECT_LE((orb.x - r.orbit_point).cwiseAbs().maxCoeff(), 1e-10);
}

// A chaotic point is reported as aperiodic, with no multipliers.
TEST(StabilityFloquet, AperiodicPointHasNoMultipliers)
{
    vimpact::wake_impact_parameters p;
    p.Ur = 25.0;
    p.sigma = -0.146;
    const auto r = vimpact::floquet_analysis(vimpact::wake_impact(p), paper_ic);
    EXPECT_EQ(r.status, floquet_status::aperiodic);
    EXPECT_EQ(r.label, "aperiodic");
    EXPECT_TRUE(r.multipliers.empty());
}

// A tangent run through a sticking phase is reported, not computed (variational.hpp). The
// forcing pulls the structure onto the barrier: it chatters (each hop a return to Sigma),
// sticks, is released and oscillates; 200 returns include the sticking phase.
TEST(StabilityFloquet, StickingIsReportedAsSuch)
{
    vimpact::forced_impact_parameters p;
    p.zeta = 0.0;
    p.F = 1.0 / 32.0;
    p.omega = 0.05;
    p.sigma = 1.0 / 64.0;
    const vimpact::forced_impact_oscillator m(p);
    const auto r = vimpact::floquet_from_point(m, vec<3>(1.0 / 32.0, 0.0, pi), 200);
    EXPECT_EQ(r.status, floquet_status::sticking);
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
// Phi_T = [[E(T), (I - E(T)) P'(phi)], [0, 0, 1]] and S the saltation matrix (Eq. 8) at
// (sigma, v, phi). One multiplier is 1 (theta' = omega is constant); the other two satisfy
// mu1 mu2 = det M = r^2 e^{-2 zeta T} and mu1 + mu2 = trace M - 1.
struct forced_orbit {
    double phase;
    double v;
    cplx mu1, mu2;
};

std::vector<forced_orbit> forced_one_impact_orbits(const vimpact::forced_impact_parameters& p)
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
        double ga = g(a), gb = g(b);
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
        const vimpact::forced_impact_oscillator m(p);
        const mat<3> S = vimpact::saltation_matrix(m, vec<3>(sg, v, ph));
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

void check_forced_against_closed_form(const vimpact::forced_impact_parameters& p, const char* expected_label)
{
    const vimpact::forced_impact_oscillator m(p);
    vimpact::floquet_options opt;
    opt.protocol.transient_impacts = 200;
    opt.protocol.record_points = 40;
    const auto r = vimpact::floquet_analysis(m, vec<3>(0.0, 0.0, 0.0), opt);
    ASSERT_EQ(r.status, floquet_status::ok);
    EXPECT_EQ(r.label, expected_label);
    ASSERT_EQ(r.impacts_per_period, 1);
    EXPECT_NEAR(r.period, 2.0 * pi / p.omega, 1e-10);
    const double phase = std::remainder(r.impacts[0].pre[2], 2.0 * pi) + (std::remainder(r.impacts[0].pre[2], 2.0 * pi) < 0 ? 2.0 * pi : 0.0);
    const auto closed = forced_one_impact_orbits(p);
    const forced_orbit* match = nullptr;
    for (const auto& o : closed)
        if (std::abs(std::remainder(o.phase - phase, 2.0 * pi)) < 1e-6) match = &o;
    ASSERT_NE(match, nullptr) << "no closed-form orbit at the impact phase " << phase;
    EXPECT_NEAR(r.impacts[0].pre[1], match->v, 1e-9);
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
    vimpact::forced_impact_parameters p;
    p.omega = 1.2;
    p.sigma = -0.3;
    check_forced_against_closed_form(p, "P1");
}

// One impact per forcing period but two maxima (label P2): the closed form is the same.
TEST(StabilityFloquet, ForcedOscillatorOneImpactOrbitWithTwoMaximaMatchesClosedForm)
{
    check_forced_against_closed_form(vimpact::forced_impact_parameters{}, "P2");
}

}  // namespace
