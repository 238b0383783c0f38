// Tests of the analysis layer: period detection on synthetic sequences (period.hpp), the
// paper's protocol and period labels (protocol.hpp, SPEC §2) against the paper's published
// results, and the grazing value (grazing.hpp) against the paper's printed values.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/model/wake_impact.hpp"

namespace {

using V3 = Eigen::Vector3d;
using X4 = vimpact::vec<4>;

std::vector<V3> repeat(const std::vector<V3>& cycle, int n)
{
    std::vector<V3> out;
    for (int i = 0; i < n; ++i) out.push_back(cycle[i % cycle.size()]);
    return out;
}

vimpact::wake_impact paper(double Ur, double sigma = -0.150298)
{
    vimpact::wake_impact_parameters p = vimpact::wake_impact_preset("paper");
    p.Ur = Ur;
    p.sigma = sigma;
    return vimpact::wake_impact(p);
}

const X4 paper_ic{0.0, 0.0, 0.0, 0.1};  // SPEC §1: the paper's initial state

}  // namespace

// ---- smallest_period on synthetic data ------------------------------------------------------

// Exactly periodic sequences of period 1, 2, 3 (distinct points within each cycle) give that
// period; the reported closure is the largest distance between points one period apart (0).
TEST(SmallestPeriod, ExactCycles)
{
    const V3 a(0.1, 0.2, 0.3), b(-0.4, 0.5, 0.0), c(0.7, -0.1, 0.9);
    double closure = -1.0;
    EXPECT_EQ(vimpact::smallest_period(repeat({a}, 20), 1e-8, &closure), 1);
    EXPECT_EQ(closure, 0.0);
    EXPECT_EQ(vimpact::smallest_period(repeat({a, b}, 20), 1e-8), 2);
    EXPECT_EQ(vimpact::smallest_period(repeat({a, b, c}, 21), 1e-8), 3);
    // Points that differ only in one coordinate still count as different (full state compared).
    const V3 a2(0.1, 0.2, 0.3 + 1e-3);
    EXPECT_EQ(vimpact::smallest_period(repeat({a, a2}, 20), 1e-8), 2);
    // A period is only accepted when it is seen at least twice: N <= points / 2.
    EXPECT_EQ(vimpact::smallest_period(repeat({a, b, c}, 6), 1e-8), 3);
    EXPECT_EQ(vimpact::smallest_period(repeat({a, b, c}, 5), 1e-8), 0);
}

// Chaotic data (logistic map x -> 4 x (1 - x), whose orbit has no period) is aperiodic.
TEST(SmallestPeriod, LogisticMapIsAperiodic)
{
    std::vector<V3> pts;
    double x = 0.1234;
    for (int i = 0; i < 200; ++i) {
        const double x1 = 4.0 * x * (1.0 - x);
        pts.emplace_back(x, x1, 0.0);
        x = x1;
    }
    EXPECT_EQ(vimpact::smallest_period(pts, 1e-8), 0);
    EXPECT_EQ(vimpact::smallest_period(pts, 1e-5), 0);
}

// Tolerance: a period-2 cycle whose points drift by delta every other cycle (so that it is
// exactly periodic with period 4, and points two apart differ by delta). With tol = 1e-8,
// delta = 1e-10 is period 2 with closure delta; delta = 1e-6 is not period 2 but 4.
TEST(SmallestPeriod, NearCoincidentPointsAndTolerance)
{
    auto seq = [](double delta) {
        std::vector<V3> out;
        for (int i = 0; i < 40; ++i) {
            V3 p = (i % 2 == 0) ? V3(0.3, -0.2, 0.5) : V3(-0.1, 0.6, 0.2);
            if ((i / 2) % 2 == 1) p[1] += delta;
            out.push_back(p);
        }
        return out;
    };
    double closure = -1.0;
    EXPECT_EQ(vimpact::smallest_period(seq(1e-10), 1e-8, &closure), 2);
    EXPECT_NEAR(closure, 1e-10, 1e-16);
    EXPECT_EQ(vimpact::smallest_period(seq(1e-6), 1e-8, &closure), 4);
    EXPECT_EQ(closure, 0.0);
    EXPECT_EQ(vimpact::smallest_period(seq(1e-6), 1e-5), 2);  // Fig. 4's looser tolerance
}

// ---- the paper's protocol -------------------------------------------------------------------

// SPEC §2 / the paper (Fig. 2e,f): with the paper preset and sigma = -0.150298, the attractor
// from (0, 0, 0, 0.1) is P2 at Ur = 16 and P3 at Ur = 19 (period tolerance 1e-8). At Ur = 16
// the P2 orbit impacts once per period (SPEC §4).
TEST(Protocol, PaperPeriodLabelsAtUr16And19)
{
    const vimpact::protocol_options opt;  // 500 transient impacts, 200 maxima
    {
        const auto m = paper(16.0);
        const auto res = vimpact::run_protocol(m, paper_ic, opt);
        ASSERT_EQ(res.status, vimpact::outcome::ok);
        EXPECT_TRUE(res.impacting);
        EXPECT_EQ(res.transient_impacts, 500);
        EXPECT_EQ(res.points.size(), 200u);
        const auto lab = vimpact::classify_period(m, res, 1e-8);
        EXPECT_EQ(lab.label, "P2");
        EXPECT_EQ(lab.period, 2);
        EXPECT_EQ(lab.impacts_per_period, 1);
        EXPECT_LE(lab.closure, 1e-8);
        // Points on the section: v = 0, and maxima of y lie above the barrier.
        for (const auto& p : res.points) {
            EXPECT_EQ(p.x[1], 0.0);
            EXPECT_GT(p.x[0], m.barrier());
        }
    }
    {
        const auto m = paper(19.0);
        const auto res = vimpact::run_protocol(m, paper_ic, opt);
        ASSERT_EQ(res.status, vimpact::outcome::ok);
        const auto lab = vimpact::classify_period(m, res, 1e-8);
        EXPECT_EQ(lab.label, "P3");
        EXPECT_EQ(lab.period, 3);
    }
}

// Determinism: the same inputs give bit-identical section points and impacts.
TEST(Protocol, RunsAreBitIdentical)
{
    vimpact::protocol_options opt;
    opt.transient_impacts = 100;
    opt.record_points = 50;
    const auto m = paper(18.0);
    const auto a = vimpact::run_protocol(m, paper_ic, opt);
    const auto b = vimpact::run_protocol(m, paper_ic, opt);
    ASSERT_EQ(a.points.size(), b.points.size());
    ASSERT_EQ(a.points.size(), 50u);
    ASSERT_TRUE(a.impacting);
    ASSERT_FALSE(a.impacts.empty());
    for (std::size_t i = 0; i < a.points.size(); ++i) {
        EXPECT_EQ(a.points[i].t, b.points[i].t);
        EXPECT_EQ(a.points[i].x, b.points[i].x);
    }
    ASSERT_EQ(a.impacts.size(), b.impacts.size());
    for (std::size_t i = 0; i < a.impacts.size(); ++i) EXPECT_EQ(a.impacts[i].post, b.impacts[i].post);
    EXPECT_EQ(a.final_state, b.final_state);
}

// Quiet rule: a barrier far below the orbit (sigma = -5) is never hit; the run is labelled P0
// (not impacting) and still records the requested number of section maxima, all on the
// section (v = 0) and recorded after the quiet time.
TEST(Protocol, FarBarrierIsP0AndRecordsMaxima)
{
    vimpact::protocol_options opt;
    opt.record_points = 50;
    const auto m = paper(16.0, -5.0);
    const auto res = vimpact::run_protocol(m, paper_ic, opt);
    ASSERT_EQ(res.status, vimpact::outcome::ok);
    EXPECT_FALSE(res.impacting);
    EXPECT_EQ(res.stats.impacts, 0);
    EXPECT_EQ(res.transient_impacts, 0);
    EXPECT_EQ(vimpact::classify_period(m, res, 1e-8).label, "P0");
    ASSERT_EQ(res.points.size(), 50u);
    EXPECT_GE(res.t_record_start, opt.quiet_time);
    double t_prev = res.t_record_start;
    for (const auto& p : res.points) {
        EXPECT_EQ(p.x[1], 0.0);
        EXPECT_GT(p.t, t_prev);
        t_prev = p.t;
        EXPECT_GT(p.x[0], 0.0);  // maxima of an oscillation about y ~ 0
    }
}

// ---- grazing value --------------------------------------------------------------------------

// The paper's printed grazing values at Ur = 25 (SPEC §2): -0.150298 for (A, eps) = (12, 0.3)
// and -0.130979 for (10, 0.333), to the six printed digits.
TEST(Grazing, PaperValuesAtUr25)
{
    {
        const auto g = vimpact::grazing_value(paper(25.0), paper_ic);
        ASSERT_EQ(g.status, vimpact::outcome::ok);
        EXPECT_TRUE(g.converged);
        EXPECT_NEAR(g.sigma_graze, -0.150298, 5e-7);
        EXPECT_EQ(g.x_graze[1], 0.0);  // a minimum of y lies on v = 0
        EXPECT_EQ(g.x_graze[0], g.sigma_graze);
    }
    {
        auto p = vimpact::wake_impact_preset("paper");
        p.Ur = 25.0;
        p.A = 10.0;
        p.eps = 0.333;
        const auto g = vimpact::grazing_value(vimpact::wake_impact(p), paper_ic);
        ASSERT_EQ(g.status, vimpact::outcome::ok);
        EXPECT_TRUE(g.converged);
        EXPECT_NEAR(g.sigma_graze, -0.130979, 5e-7);
    }
}

// The grazing definition (SPEC §2): a barrier just below the barrier-free orbit's minimum is
// never hit (P0), a barrier just above it is.
TEST(Grazing, BarrierJustBelowIsNotHitJustAboveIs)
{
    const auto g = vimpact::grazing_value(paper(25.0), paper_ic);
    ASSERT_TRUE(g.converged);
    vimpact::protocol_options opt;
    opt.record_points = 20;
    {
        const auto m = paper(25.0, g.sigma_graze - 1e-6);
        const auto res = vimpact::run_protocol(m, paper_ic, opt);
        ASSERT_EQ(res.status, vimpact::outcome::ok);
        EXPECT_FALSE(res.impacting);
        EXPECT_EQ(vimpact::classify_period(m, res, 1e-8).label, "P0");
    }
    {
        const auto m = paper(25.0, g.sigma_graze + 1e-4);
        const auto res = vimpact::run_protocol(m, paper_ic, opt);
        ASSERT_EQ(res.status, vimpact::outcome::ok);
        EXPECT_TRUE(res.impacting);
        EXPECT_GT(res.stats.impacts, 0);
    }
}
