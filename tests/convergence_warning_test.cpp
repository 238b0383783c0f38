// The warnings a result carries when the protocol was too short for it (period_label::settled,
// lyapunov_result::settled) and the limits that end a run in bounded memory (sample_limit).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "test_support.hpp"
#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/lyapunov.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/engine/lyapunov.hpp"

using namespace vimpact;
using test::paper;
using test::paper_ic;

namespace {

// A record of `n` section points of the paper's model: the first `drifting` of them wander
// (distinct values), the rest repeat with period 2; one impact between points.
simulation synthetic_record(int n, int drifting)
{
    simulation s;
    s.points = state_series(4);
    s.impacts = impact_series(4);
    for (int i = 0; i < n; ++i) {
        const double y = i < drifting ? 0.1 + 0.001 * i : (i % 2 == 0 ? 0.2 : 0.3);
        s.points.push_back(static_cast<double>(i), Eigen::Vector4d(y, 0.0, 0.0, 0.0));
    }
    return s;
}

}  // namespace

TEST(Settled, AperiodicRecordWithAPeriodicLastHalfIsNotSettled)
{
    const model m = paper(16.0);
    // Drifting for 40 of 200 points: aperiodic as a whole, P2 in the last half.
    const auto late = classify_period(m, synthetic_record(200, 40), 1e-8);
    EXPECT_EQ(late.label, "aperiodic");
    EXPECT_FALSE(late.settled);
    // Drifting throughout: aperiodic, and no period in the last half either.
    const auto chaotic = classify_period(m, synthetic_record(200, 200), 1e-8);
    EXPECT_EQ(chaotic.label, "aperiodic");
    EXPECT_TRUE(chaotic.settled);
    // Drifting into the last half (120 of 200): the last half is not periodic either.
    EXPECT_TRUE(classify_period(m, synthetic_record(200, 120), 1e-8).settled);
    // Periodic throughout.
    const auto periodic = classify_period(m, synthetic_record(200, 0), 1e-8);
    EXPECT_EQ(periodic.label, "P2");
    EXPECT_TRUE(periodic.settled);
}

// The paper's P2 at Ur = 16 recorded from the start (no transient) is not yet periodic over
// the record; after 500 impacts it is, and settled.
TEST(Settled, PaperOrbitWithoutTransientIsNotSettled)
{
    protocol_options o;
    o.transient_impacts = 0;
    const auto early = run_and_classify(paper(16.0), paper_ic(), o, 1e-8);
    EXPECT_EQ(early.label.label, "aperiodic");
    EXPECT_FALSE(early.label.settled);
    o.transient_impacts = 500;
    const auto late = run_and_classify(paper(16.0), paper_ic(), o, 1e-8);
    EXPECT_EQ(late.label.label, "P2");
    EXPECT_TRUE(late.label.settled);
}

// ---- slowly converging records ----------------------------------------------------------------

namespace {

// The forced impact oscillator at sigma = 0, omega = 3.0515, on its stroboscopic section: a
// stable P4 orbit (four impacts per period) just before its period doubling.
model slow_p4_model()
{
    return test::with(test::with(model::builtin("forced_impact_oscillator"), "sigma", 0.0), "omega", 3.0515);
}

protocol_options strobe_protocol(const model& m, long transient)
{
    protocol_options o;
    o.section = section_choice::crossings(m.info().section_index("strobe"));
    o.transient_impacts = transient;
    return o;
}

// The protocol's label of the run from ic after the default transient (500 impacts) is `early`
// and not settled; after 3000 impacts it is P4 and settled.
void expect_p4_only_after_a_long_transient(const Eigen::Vector3d& ic, const char* early_label)
{
    const model m = slow_p4_model();
    const auto early = run_and_classify(m, ic, strobe_protocol(m, 500), 1e-8);
    EXPECT_EQ(early.label.label, early_label);
    EXPECT_FALSE(early.label.settled);
    const auto late = run_and_classify(m, ic, strobe_protocol(m, 3000), 1e-8);
    EXPECT_EQ(late.label.label, "P4");
    EXPECT_TRUE(late.label.settled);
}

}  // namespace

// A stable P4 with its slowest multiplier at -0.934 (measured by Floquet shooting, not by the
// label) converges by 0.934 a period: started 5e-3 from it, the default transient of 500
// impacts (125 periods) leaves it about 1e-4 away, and the 200 points of the record (50
// periods) bring it to 4e-6, far above the period tolerance. The label is aperiodic, and the
// record's last half is not periodic either, but it has not settled: the distances between
// points 4 apart shrink by the same factor all along. After 3000 impacts it is P4, settled.
TEST(Settled, SlowlyConvergingP4IsNotSettledUntilItHasConverged)
{
    const model m = slow_p4_model();
    const Eigen::Vector3d ic(0.11, 0.32, 0.0);
    floquet_options fo;
    fo.protocol = strobe_protocol(m, 3000);
    const floquet_result f = floquet(m, ic, fo);
    ASSERT_EQ(f.label, "P4");
    std::printf("slow P4: multipliers %.6f %.6f\n", f.multipliers[1].real(), f.multipliers[2].real());
    EXPECT_NEAR(f.multipliers[1].real(), -0.934, 0.002);
    EXPECT_NEAR(f.multipliers[1].imag(), 0.0, 1e-12);
    expect_p4_only_after_a_long_transient(ic, "aperiodic");
}

// The same P4 approached from closer: after the default transient the points 8 apart are
// within the tolerance before those 4 apart are (their distance is |mu^2 - 1| = 0.13 times
// |mu - 1| = 1.93 times the distance to the orbit), so the record is labelled P8; it is not
// settled (the points 4 apart still converge), and after 3000 impacts it is P4.
TEST(Settled, ALabelWhosePeriodIsStillHalvingIsNotSettled)
{
    expect_p4_only_after_a_long_transient(Eigen::Vector3d(0.1113, 0.3242, 0.0), "P8");
}

// converging_period on synthetic records: geometric convergence onto a period-3 orbit, real or
// spiralling, is found at 3 however slowly it goes (multiplier modulus 0.98 over 200 points);
// a chaotic record (the logistic map at 4), a drifting one and one converging too little (a
// factor below 2 over the record) are not converging.
TEST(Settled, ConvergingPeriodOnSyntheticRecords)
{
    const auto record = [](int n, const auto& x) {
        std::vector<double> v(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) v[static_cast<std::size_t>(i)] = x(i);
        return v;
    };
    const auto converging = [](const std::vector<double>& v) {
        return converging_period(static_cast<int>(v.size()),
                                 [&](int i, int j) { return std::abs(v[static_cast<std::size_t>(i)] - v[static_cast<std::size_t>(j)]); },
                                 [](int) { return true; });
    };
    const double cycle[3] = {0.2, 0.5, 0.9};
    const auto on_cycle = [&](int i) { return cycle[i % 3]; };
    EXPECT_EQ(converging(record(200, [&](int i) { return on_cycle(i) + 1e-3 * std::pow(-0.98, i / 3.0); })), 3);
    EXPECT_EQ(converging(record(200, [&](int i) { return on_cycle(i) + 1e-3 * std::pow(0.9, i / 3.0) * std::cos(0.7 * i / 3); })), 3);
    double x = 0.3;
    EXPECT_EQ(converging(record(200, [&](int) { return x = 4.0 * x * (1.0 - x); })), 0);
    EXPECT_EQ(converging(record(200, [&](int i) { return 0.1 + 0.001 * i; })), 0);
    EXPECT_EQ(converging(record(200, [&](int i) { return on_cycle(i) + 1e-3 * std::pow(0.995, i / 3.0); })), 0);
}

// The chaotic attractors of the paper's protocol stay settled.
TEST(Settled, ChaoticPaperRecordsStaySettled)
{
    for (const auto& [Ur, sigma] : {std::pair{25.0, -0.146}, std::pair{24.4, -0.150298}}) {
        const auto r = run_and_classify(paper(Ur, sigma), paper_ic(), protocol_options{}, 1e-8);
        EXPECT_EQ(r.label.label, "aperiodic") << Ur;
        EXPECT_TRUE(r.label.settled) << Ur;
    }
}

namespace {

// finish_exponents on a synthetic history of 64 unit intervals: the first exponent's growth
// is `a` in the first half and `b` in the second, plus alternating noise of size `noise`.
lyapunov_result finished(double a, double b, double noise)
{
    lyapunov_result r;
    r.t_start = 0.0;
    vec<2> sum = vec<2>::Zero();
    for (int i = 0; i < 64; ++i) {
        Eigen::VectorXd g(2);
        g << (i < 32 ? a : b) + (i % 2 == 0 ? noise : -noise), -1.0;
        r.history.push_back(g);
        r.history_t.push_back(i + 1.0);
        sum += g;
    }
    r.time = 64.0;
    engine::finish_exponents<2>(r, sum);
    return r;
}

}  // namespace

TEST(Settled, LyapunovDriftBetweenHalvesIsReported)
{
    // Equal halves with noise: settled, whatever the noise.
    EXPECT_TRUE(finished(0.05, 0.05, 0.01).settled);
    // A drift of 0.01 between the halves, each half steady: not settled (the step between the
    // halves must not count as noise).
    EXPECT_FALSE(finished(0.05, 0.04, 0.0).settled);
    EXPECT_FALSE(finished(0.05, 0.04, 0.001).settled);
    // A drift below the floor of 1e-3 of the spread: settled.
    EXPECT_TRUE(finished(0.05, 0.0499, 0.0).settled);
    const auto r = finished(0.05, 0.04, 0.0);
    EXPECT_NEAR(r.exponents[0], 0.045, 1e-12);
}

// The running estimates every front end shows (convergence.csv, Python's running_exponents):
// growth k and -1 on unit intervals from t_start = 2 average to (k + 1) / 2 and -1 after
// interval k; the last estimate is the exponents, before their sort.
TEST(Settled, RunningEstimatesAreTheGrowthSoFarOverTheTimeSoFar)
{
    lyapunov_result r;
    r.t_start = 2.0;
    vec<2> sum = vec<2>::Zero();
    for (int k = 1; k <= 10; ++k) {
        r.history.push_back(Eigen::Vector2d(k, -1.0));
        r.history_t.push_back(2.0 + k);
        sum += r.history.back();
    }
    r.time = 10.0;
    const auto running = r.running_exponents();
    ASSERT_EQ(running.size(), 10U);
    for (int k = 1; k <= 10; ++k) {
        EXPECT_DOUBLE_EQ(running[static_cast<std::size_t>(k - 1)][0], (k + 1) / 2.0) << k;
        EXPECT_DOUBLE_EQ(running[static_cast<std::size_t>(k - 1)][1], -1.0) << k;
    }
    engine::finish_exponents<2>(r, sum);
    EXPECT_DOUBLE_EQ(r.exponents[0], running.back()[0]);
    EXPECT_DOUBLE_EQ(r.exponents[1], running.back()[1]);
    EXPECT_TRUE(lyapunov_result{}.running_exponents().empty());
}

TEST(Settled, TooFewIntervalsSayNothing)
{
    lyapunov_result r;
    vec<2> sum(0.1, -1.0);
    r.history.push_back(Eigen::Vector2d(0.1, -1.0));
    r.history_t.push_back(1.0);
    r.time = 1.0;
    engine::finish_exponents<2>(r, sum);
    EXPECT_TRUE(r.settled);
    EXPECT_TRUE(std::isnan(r.lle_standard_error));
}

// ---- bounded runs -----------------------------------------------------------------------------

TEST(SampleLimit, ASamplingStepBelowTheTimeResolutionEnds)
{
    protocol_options o;
    o.transient_impacts = 20;
    o.record_points = 20;
    o.sample_dt = 1e-300;
    const auto r = simulate(paper(16.0), paper_ic(), o);
    EXPECT_EQ(r.status, outcome::sample_limit);
    EXPECT_LT(r.series.size(), 10u);
}

TEST(SampleLimit, TheSeriesStopsAtItsLimit)
{
    protocol_options o;
    o.transient_impacts = 20;
    o.record_points = 20;
    o.sample_dt = 1e-3;
    o.max_samples = 5000;  // far fewer than the window needs (about 1e5)
    const auto r = simulate(paper(16.0), paper_ic(), o);
    EXPECT_EQ(r.status, outcome::sample_limit);
    EXPECT_EQ(r.series.size(), 5000u);
    // Under the limit nothing changes.
    o.max_samples = 1'000'000;
    const auto full = simulate(paper(16.0), paper_ic(), o);
    EXPECT_EQ(full.status, outcome::ok);
    EXPECT_GT(full.series.size(), 5000u);
}

TEST(Limits, OutOfRangeCountsAndIntervalsAreInputErrors)
{
    protocol_options o;
    o.transient_impacts = 2'000'000'000;
    EXPECT_THROW(simulate(paper(16.0), paper_ic(), o), input_error);
    o = {};
    o.record_points = 20'000'000;
    EXPECT_THROW(simulate(paper(16.0), paper_ic(), o), input_error);
    for (const double band : {1.0, -0.1, std::nan("")}) {
        o = {};
        o.flow.integration.hold_band = band;
        EXPECT_THROW(simulate(paper(16.0), paper_ic(), o), input_error) << band;
    }
    lyapunov_options lo;
    lo.t0 = 1e-3;  // 1e9 intervals up to max_time
    EXPECT_THROW(validate(paper(16.0), lo), input_error);
    lo.time = 100.0;  // 1e5 intervals over the given time: allowed
    EXPECT_NO_THROW(validate(paper(16.0), lo));
    EXPECT_THROW(paper(16.0).with_parameter(0, 4.9e-324), input_error);
}
