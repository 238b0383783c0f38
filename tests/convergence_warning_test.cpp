// The warnings a result carries when the protocol was too short for it (period_label::settled,
// lyapunov_result::settled) and the limits that end a run in bounded memory (sample_limit).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "test_support.hpp"
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
