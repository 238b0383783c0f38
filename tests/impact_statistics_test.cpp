// Impact statistics against closed forms: the forced impact oscillator's 1:1 impacting orbit
// (impact velocity and excursion from the exact solution, energy (1 - r^2) v^2 / 2), its
// plastic (r = 0) orbit with a contact phase every period (contact fraction from the exact
// release and landing times), and on the paper's model the energy of every impact against
// (1 - r^2) ydot^2 / 2 and the excursion against the recorded maxima of y.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "exact_impact_oscillator.hpp"
#include "test_support.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol.hpp"

namespace {

using namespace vimpact;
using vimpact::test::exact_impact_oscillator;
using vimpact::test::ld;
using vimpact::test::with;

model oscillator(double zeta, double omega, double F, double sigma, double r)
{
    model m = model::builtin("forced_impact_oscillator");
    for (const auto& [name, v] : {std::pair{"zeta", zeta}, {"omega", omega}, {"F", F}, {"sigma", sigma}, {"r", r}})
        m = with(m, name, v);
    return m;
}

protocol_options tight()
{
    protocol_options o;
    o.flow.integration.rtol = 1e-12;
    o.flow.integration.atol = 1e-12;
    return o;
}

// The largest y on the flight from (t0, y0, v0): where v turns from positive to negative.
ld flight_maximum(const exact_impact_oscillator& ex, ld t0, ld y0, ld v0, ld t1)
{
    ld best = y0;
    const int n = 20000;
    ld ta = t0, va = v0;
    for (int k = 1; k <= n; ++k) {
        const ld tb = t0 + (t1 - t0) * k / n;
        const ld vb = ex.flow(t0, y0, v0, tb).second;
        if (va > 0 && vb <= 0) {
            const ld tm = exact_impact_oscillator::bisect([&](ld t) { return ex.flow(t0, y0, v0, t).second > 0; }, ta, tb);
            best = std::max(best, ex.flow(t0, y0, v0, tm).first);
        }
        ta = tb;
        va = vb;
    }
    return best;
}

TEST(ImpactStatistics, OneOneOrbitOfTheForcedOscillatorAgainstItsClosedForm)
{
    const ld zeta = 0.05L, omega = 0.8L, F = 1.0L, r = 0.8L, phi = 3.1L;
    const exact_impact_oscillator ex(zeta, omega, F, r);
    const auto [sigma, v] = ex.one_one(phi);
    ASSERT_LT(v, 0.0L);
    ASSERT_GT(ex.interior_min_gap(phi), 0.01L);  // a clean 1:1 orbit: no grazing inside the flight
    const model m = oscillator(0.05, 0.8, 1.0, static_cast<double>(sigma), 0.8);
    const auto run = run_and_classify(m, m.initial_state(), tight(), 1e-8);
    ASSERT_EQ(run.label.label, "P1");
    ASSERT_EQ(run.label.impacts_per_period, 1);
    const impact_statistics& s = run.run.statistics;

    const double speed = static_cast<double>(-v);
    EXPECT_NEAR(s.velocity_min, speed, 1e-8);
    EXPECT_NEAR(s.velocity_max, speed, 1e-8);
    EXPECT_NEAR(s.velocity_mean, speed, 1e-8);
    EXPECT_NEAR(s.velocity_rms, speed, 1e-8);
    const double energy = (1.0 - 0.64) * speed * speed / 2.0;
    EXPECT_NEAR(s.energy_per_impact, energy, 1e-8);
    EXPECT_NEAR(s.power, energy * static_cast<double>(s.impacts) / s.duration, 1e-12);
    // One impact per forcing period over the record (200 maxima, one per period).
    EXPECT_GE(s.impacts, 199);
    EXPECT_LE(s.impacts, 200);
    EXPECT_NEAR(s.duration, run.run.t_record_end - run.run.t_record_start, 0.0);
    EXPECT_NEAR(s.rate, static_cast<double>(omega / (2 * std::numbers::pi_v<ld>)), 0.01 * s.rate);
    EXPECT_EQ(s.contact_fraction, 0.0);
    // The excursion: the flight's highest point above the barrier.
    const ld t0 = phi / omega;
    const ld top = flight_maximum(ex, t0, sigma, -r * v, t0 + ex.period());
    ASSERT_EQ(s.excursion_by_surface.size(), 1u);
    EXPECT_NEAR(s.excursion, static_cast<double>(top - sigma), 1e-8);
    EXPECT_EQ(s.excursion, s.excursion_by_surface[0]);
}

TEST(ImpactStatistics, ContactFractionOfThePlasticOrbitAgainstExactReleaseAndLanding)
{
    // r = 0, barrier above the equilibrium (sigma = 0.5 > 0): every impact ends at rest on
    // the barrier, where the spring presses the mass on it until the forcing lifts it off at
    // F cos(theta) = sigma, rising. From there the orbit repeats every forcing period.
    const ld zeta = 0.05L, omega = 0.8L, F = 1.0L, sigma = 0.5L;
    const exact_impact_oscillator ex(zeta, omega, F, 0.0L);
    const ld T = ex.period();
    const ld t_release = (2 * std::numbers::pi_v<ld> - std::acos(sigma / F)) / omega;
    const auto landing = ex.next_impact(t_release, sigma, 0.0L, sigma, t_release + T);
    ASSERT_TRUE(landing.has_value());
    const auto [y_land, v_land] = ex.flow(t_release, sigma, 0.0L, *landing);
    ASSERT_LT(std::cos(omega * *landing) * F, sigma);  // it stays: the spring wins at landing
    const ld stick = t_release + T - *landing;         // from landing to the next release
    const ld top_t = exact_impact_oscillator::bisect(
        [&](ld t) { return ex.flow(t_release, sigma, 0.0L, t).second > 0; }, t_release + 1e-9L, *landing);
    const ld to_top = top_t - t_release;
    const ld top = ex.flow(t_release, sigma, 0.0L, top_t).first;

    const model m = oscillator(0.05, 0.8, 1.0, 0.5, 0.0);
    const Eigen::VectorXd ic = Eigen::Vector3d(0.5, 0.0, 0.0);  // at rest on the barrier
    const simulation run = simulate(m, ic, tight());
    ASSERT_EQ(run.status, outcome::ok);
    const impact_statistics& s = run.statistics;
    // The record runs from a landing (the last transient impact) to the 200th maximum: 200
    // contact phases, 199 landings, 199 whole periods plus one stick and one rise to the top.
    ASSERT_EQ(s.impacts, 199);
    const ld duration = 199 * T + stick + to_top;
    EXPECT_NEAR(s.duration, static_cast<double>(duration), 1e-7);
    EXPECT_NEAR(s.contact_fraction, static_cast<double>(200 * stick / duration), 1e-9);
    EXPECT_NEAR(s.velocity_max, static_cast<double>(-v_land), 1e-8);
    EXPECT_NEAR(s.velocity_min, static_cast<double>(-v_land), 1e-8);
    // Plastic: every impact takes all of v^2 / 2.
    EXPECT_NEAR(s.energy_per_impact, static_cast<double>(v_land * v_land / 2), 1e-8);
    EXPECT_NEAR(s.excursion, static_cast<double>(top - sigma), 1e-8);
    (void)y_land;
}

TEST(ImpactStatistics, PaperModelEnergyPerImpactIsTheRestitutionLaw)
{
    const model m = vimpact::test::paper(16.0);
    const simulation run = simulate(m, vimpact::test::paper_ic(), protocol_options{});
    ASSERT_EQ(run.status, outcome::ok);
    ASSERT_GT(run.impacts.size(), 50u);
    const double r = 0.8;
    const auto each = impact_velocities(m, run.impacts);
    double sum = 0.0;
    for (std::size_t k = 0; k < run.impacts.size(); ++k) {
        const double ydot = run.impacts.pre.x(k, 1);  // the barrier's gap is y - sigma
        EXPECT_NEAR(each[k].normal, -ydot, 1e-15);
        EXPECT_NEAR(each[k].rebound, -r * ydot, 1e-15);
        EXPECT_NEAR(each[k].energy, (1 - r * r) * ydot * ydot / 2, 1e-15);
        sum += (1 - r * r) * ydot * ydot / 2;
    }
    const impact_statistics& s = run.statistics;
    EXPECT_NEAR(s.energy_per_impact, sum / static_cast<double>(run.impacts.size()), 1e-15);
    EXPECT_NEAR(s.power, sum / (run.t_record_end - run.t_record_start), 1e-15);
    // Every maximum of y is a section point (the section is the maxima): the excursion is the
    // highest of them above the barrier.
    double top = -1e300;
    for (std::size_t i = 0; i < run.points.size(); ++i) top = std::max(top, run.points.x(i, 0));
    EXPECT_NEAR(s.excursion, top - (-0.150298), 1e-12);
}

TEST(ImpactStatistics, RunWithoutImpactsHasNoVelocities)
{
    const model m = vimpact::test::paper(16.0, -1.0);  // far below the free orbit: P0
    protocol_options o;
    o.quiet_time = 200.0;
    const simulation run = simulate(m, vimpact::test::paper_ic(), o);
    ASSERT_FALSE(run.impacting);
    EXPECT_EQ(run.statistics.impacts, 0);
    EXPECT_EQ(run.statistics.rate, 0.0);
    EXPECT_TRUE(std::isnan(run.statistics.velocity_max));
    EXPECT_EQ(run.statistics.power, 0.0);
    EXPECT_GT(run.statistics.excursion, 1.0);  // the free orbit stays above y = -1
}

}  // namespace
