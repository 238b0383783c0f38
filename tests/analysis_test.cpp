// The protocol, period labels and grazing values: synthetic sequences for the period rule,
// the paper's published labels and grazing values for the paper's model.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "test_support.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/analysis/response.hpp"

using namespace vimpact;
using test::paper;
using test::paper_ic;

namespace {

using V3 = Eigen::Vector3d;

int period_of(const std::vector<V3>& pts, double tol, double* closure = nullptr)
{
    return smallest_period(
        static_cast<int>(pts.size()), tol, [&](int i, int j) { return (pts[static_cast<std::size_t>(i)] - pts[static_cast<std::size_t>(j)]).cwiseAbs().maxCoeff(); },
        closure);
}

std::vector<V3> repeat(const std::vector<V3>& cycle, int n)
{
    std::vector<V3> out;
    for (int i = 0; i < n; ++i) out.push_back(cycle[static_cast<std::size_t>(i) % cycle.size()]);
    return out;
}

}  // namespace

// ---- smallest_period on synthetic data ------------------------------------------------------

TEST(SmallestPeriod, ExactCycles)
{
    const V3 a(0.1, 0.2, 0.3), b(-0.4, 0.5, 0.0), c(0.7, -0.1, 0.9);
    double closure = -1.0;
    EXPECT_EQ(period_of(repeat({a}, 20), 1e-8, &closure), 1);
    EXPECT_EQ(closure, 0.0);
    EXPECT_EQ(period_of(repeat({a, b}, 20), 1e-8), 2);
    EXPECT_EQ(period_of(repeat({a, b, c}, 21), 1e-8), 3);
    const V3 a2(0.1, 0.2, 0.3 + 1e-3);  // differs in one coordinate only: still different
    EXPECT_EQ(period_of(repeat({a, a2}, 20), 1e-8), 2);
    EXPECT_EQ(period_of(repeat({a, b, c}, 6), 1e-8), 3);  // N <= points / 2
    EXPECT_EQ(period_of(repeat({a, b, c}, 5), 1e-8), 0);
}

// The logistic map x -> 4 x (1 - x) has no period.
TEST(SmallestPeriod, LogisticMapIsAperiodic)
{
    std::vector<V3> pts;
    double x = 0.1234;
    for (int i = 0; i < 200; ++i) {
        const double x1 = 4.0 * x * (1.0 - x);
        pts.emplace_back(x, x1, 0.0);
        x = x1;
    }
    EXPECT_EQ(period_of(pts, 1e-8), 0);
    EXPECT_EQ(period_of(pts, 1e-5), 0);
}

// A P2 cycle whose points drift by delta every other cycle (exactly periodic with period 4).
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
    EXPECT_EQ(period_of(seq(1e-10), 1e-8, &closure), 2);
    EXPECT_NEAR(closure, 1e-10, 1e-16);
    EXPECT_EQ(period_of(seq(1e-6), 1e-8, &closure), 4);
    EXPECT_EQ(closure, 0.0);
    EXPECT_EQ(period_of(seq(1e-6), 1e-5), 2);  // Fig. 4's looser tolerance
}

// Phases are compared modulo their period: states one forcing period apart coincide.
TEST(SmallestPeriod, PhasesCompareModuloTheirPeriod)
{
    const model m = model::builtin("two_sided_impact_oscillator");
    const Eigen::Vector3d a(0.1, 0.2, 0.3);
    Eigen::Vector3d b = a;
    b[2] += 6.0 * std::numbers::pi;
    EXPECT_LT(state_distance(m.info(), a, b), 1e-14);
    b[2] += 0.5;
    EXPECT_NEAR(state_distance(m.info(), a, b), 0.5, 1e-12);
}

// ---- the paper's protocol -------------------------------------------------------------------

// The paper (Fig. 2e,f): from (0, 0, 0, 0.1), P2 at Ur = 16 with one impact per period, P3 at
// Ur = 19 (tolerance 1e-8).
TEST(Protocol, PaperPeriodLabelsAtUr16And19)
{
    const protocol_options opt;  // 500 transient impacts, 200 maxima
    {
        const model m = paper(16.0);
        const auto res = simulate(m, paper_ic(), opt);
        ASSERT_EQ(res.status, outcome::ok);
        EXPECT_TRUE(res.impacting);
        EXPECT_EQ(res.transient_impacts, 500);
        EXPECT_EQ(res.points.size(), 200u);
        const auto lab = classify_period(m, res, 1e-8);
        EXPECT_EQ(lab.label, "P2");
        EXPECT_EQ(lab.period, 2);
        EXPECT_EQ(lab.impacts_per_period, 1);
        EXPECT_EQ(lab.impacts_by_surface, std::vector<long>{1});
        EXPECT_LE(lab.closure, 1e-8);
        for (std::size_t i = 0; i < res.points.size(); ++i) {
            EXPECT_EQ(res.points.x(i, 1), 0.0);  // on the section ydot = 0
            EXPECT_GT(res.points.x(i, 0), -0.150298);
        }
        for (std::size_t k = 0; k < res.impacts.size(); ++k) EXPECT_EQ(res.impacts.pre.x(k, 0), -0.150298);
    }
    {
        const auto r = run_and_classify(paper(19.0), paper_ic(), opt, 1e-8);
        ASSERT_EQ(r.run.status, outcome::ok);
        EXPECT_EQ(r.label.label, "P3");
    }
}

TEST(Protocol, RunsAreBitIdentical)
{
    protocol_options opt;
    opt.transient_impacts = 100;
    opt.record_points = 50;
    const model m = paper(18.0);
    const auto a = simulate(m, paper_ic(), opt);
    const auto b = simulate(m, paper_ic(), opt);
    ASSERT_EQ(a.points.size(), 50u);
    ASSERT_GT(a.impacts.size(), 0u);
    EXPECT_EQ(a.points.times(), b.points.times());
    EXPECT_EQ(a.points.values(), b.points.values());
    EXPECT_EQ(a.impacts.post.values(), b.impacts.post.values());
    EXPECT_EQ(a.final_state, b.final_state);
}

// A barrier far below the orbit is never hit: P0, with maxima recorded after the quiet time.
TEST(Protocol, FarBarrierIsP0AndRecordsMaxima)
{
    protocol_options opt;
    opt.record_points = 50;
    const model m = paper(16.0, -5.0);
    const auto res = simulate(m, paper_ic(), opt);
    ASSERT_EQ(res.status, outcome::ok);
    EXPECT_FALSE(res.impacting);
    EXPECT_EQ(res.stats.impacts, 0);
    EXPECT_EQ(classify_period(m, res, 1e-8).label, "P0");
    ASSERT_EQ(res.points.size(), 50u);
    EXPECT_GE(res.t_record_start, opt.quiet_time);
    for (std::size_t i = 0; i < res.points.size(); ++i) {
        EXPECT_EQ(res.points.x(i, 1), 0.0);
        EXPECT_GT(res.points.x(i, 0), 0.0);
    }
}

// ---- grazing --------------------------------------------------------------------------------

// The paper's printed grazing values at Ur = 25: -0.150298 for (A, eps) = (12, 0.3) and
// -0.130979 for (10, 0.333), to the six printed digits; sigma_graze is the minimum of y.
TEST(Grazing, PaperValuesAtUr25)
{
    const model m = paper(25.0);
    const int sigma = m.info().parameter_index("sigma");
    grazing_options o;
    o.parameter = sigma;
    {
        const auto g = grazing(m, paper_ic(), o);
        ASSERT_EQ(g.status, outcome::ok);
        ASSERT_TRUE(g.converged);
        const auto& s = g.surfaces.at(0);
        EXPECT_NEAR(s.parameter_value, -0.150298, 5e-7);
        EXPECT_EQ(s.x[1], 0.0);              // a minimum of y lies on ydot = 0
        EXPECT_EQ(s.parameter_value, s.x[0]);  // sigma_graze = min y, exactly
        EXPECT_EQ(s.margin, s.x[0] - m.parameter(sigma));
    }
    {
        const model m2 = test::with(test::with(m, "A", 10.0), "eps", 0.333);
        const auto g = grazing(m2, paper_ic(), o);
        ASSERT_TRUE(g.converged);
        EXPECT_NEAR(g.surfaces.at(0).parameter_value, -0.130979, 5e-7);
    }
}

// The grazing runs take the protocol's step cap (integrate/tangent_integration.hpp): no step
// longer than the cap, while without it the same run takes longer steps, so the cap is what
// bounds them.
TEST(Grazing, RunsKeepTheProtocolsStepCap)
{
    const model m = paper(25.0);
    integrator_options protocol;
    grazing_options free = job_grazing_options(protocol, 200.0);
    free.parameter = m.info().parameter_index("sigma");
    free.t_max = 2000.0;
    const double cap = 0.02;
    protocol.h_max = cap;
    grazing_options capped = job_grazing_options(protocol, 200.0);
    capped.parameter = free.parameter;
    capped.t_max = free.t_max;
    const auto a = grazing(m, paper_ic(), free), b = grazing(m, paper_ic(), capped);
    EXPECT_GT(a.stats.h_max, cap);
    EXPECT_LE(b.stats.h_max, cap);
    EXPECT_GE(static_cast<double>(b.stats.steps), b.stats.t_final / cap * (1.0 - 1e-9));
}

// The definition: a barrier just below the surface-free orbit's minimum is never hit (P0), one
// just above it is.
TEST(Grazing, BarrierJustBelowIsNotHitJustAboveIs)
{
    const model m = paper(25.0);
    grazing_options o;
    o.parameter = m.info().parameter_index("sigma");
    const double sg = grazing(m, paper_ic(), o).surfaces.at(0).parameter_value;
    ASSERT_TRUE(std::isfinite(sg));
    protocol_options opt;
    opt.record_points = 20;
    const auto below = run_and_classify(paper(25.0, sg - 1e-6), paper_ic(), opt, 1e-8);
    EXPECT_FALSE(below.run.impacting);
    EXPECT_EQ(below.label.label, "P0");
    const auto above = simulate(paper(25.0, sg + 1e-4), paper_ic(), opt);
    EXPECT_TRUE(above.impacting);
    EXPECT_GT(above.stats.impacts, 0);
}

// Gap parameters: sigma moves the paper's barrier and nothing else; d moves both stops.
TEST(Grazing, GapParametersAreFoundByProbing)
{
    const model w;
    EXPECT_EQ(gap_parameters(w, 0), std::vector<int>{w.info().parameter_index("sigma")});
    const model two = model::builtin("two_sided_impact_oscillator");
    const std::vector<int> d{two.info().parameter_index("d")};
    EXPECT_EQ(gap_parameters(two, 0), d);
    EXPECT_EQ(gap_parameters(two, 1), d);
    grazing_options o;
    o.parameter = w.info().parameter_index("Ur");
    EXPECT_THROW((void)grazing(w, paper_ic(), o), input_error);  // Ur enters the field
}

// Two stops: the free response of the linear oscillator is x(t) -> X cos(w t - phase), X the
// steady amplitude a / sqrt((1 - w^2)^2 + (2 zeta w)^2); the grazing values of d are X for both
// stops (the right stop at x = d is grazed by the maximum, the left at -d by the minimum).
TEST(Grazing, TwoStopsAreGrazedAtTheClosedFormAmplitude)
{
    const model m = model::builtin("two_sided_impact_oscillator");
    const double zeta = 0.05, a = 1.0, w = 1.2;
    const double X = a / std::sqrt((1 - w * w) * (1 - w * w) + (2 * zeta * w) * (2 * zeta * w));
    grazing_options o;
    o.parameter = m.info().parameter_index("d");
    o.response_variable = 0;
    const auto g = grazing(m, m.initial_state(), o);
    ASSERT_EQ(g.status, outcome::ok);
    ASSERT_TRUE(g.converged);
    EXPECT_NEAR(g.surfaces.at(0).parameter_value, X, 1e-9);
    EXPECT_NEAR(g.surfaces.at(1).parameter_value, X, 1e-9);
    EXPECT_NEAR(g.surfaces.at(0).margin, 1.0 - X, 1e-9);
    EXPECT_NEAR(g.response_max, X, 1e-9);
    EXPECT_NEAR(g.response_min, -X, 1e-9);
    EXPECT_NEAR(g.response_omega, w, 1e-9);
}

// A response's curves set their parameters at each value of the swept one: over w, the curves
// a = 1 and a = 2 of the two stops' linear oscillator give the closed-form amplitude above,
// the second twice the first; response_model names the model each point runs.
TEST(Response, EachCurveRunsAtItsParametersAndTheClosedFormAmplitude)
{
    const model m = model::builtin("two_sided_impact_oscillator");
    const auto& info = m.info();
    const int a = info.parameter_index("a"), w = info.parameter_index("w");
    const double zeta = m.parameter(info.parameter_index("zeta"));
    response_options o;
    o.parameter = w;
    o.values = value_grid::range(1.1, 1.3, 2);
    o.curves = {{{a, 1.0}}, {{a, 2.0}}};
    o.variable = 0;
    o.grazing.parameter = info.parameter_index("d");
    const auto r = response(m, o);
    ASSERT_EQ(r.points.size(), 4u);
    for (const auto& p : r.points) {
        const double amplitude = (p.curve + 1) / std::sqrt((1 - p.value * p.value) * (1 - p.value * p.value) +
                                                           (2 * zeta * p.value) * (2 * zeta * p.value));
        EXPECT_NEAR(p.amplitude, amplitude, 1e-9) << "curve " << p.curve << " at w = " << p.value;
        const model at = response_model(m, o, p.curve, p.value);
        EXPECT_EQ(at.parameter(a), p.curve + 1.0);
        EXPECT_EQ(at.parameter(w), p.value);
    }
    // Beyond the curves: the model's own values.
    EXPECT_EQ(response_model(m, o, 2, 1.2).parameter(a), m.parameter(a));
    EXPECT_THROW((void)response_model(m, o, 0, -1.0), input_error);  // w > 0
}

// Summaries and legends read P2 before P10 (not as strings), then aperiodic, then failed runs.
TEST(Labels, ReadingOrderIsByPeriodThenAperiodicThenOutcomes)
{
    const std::vector<std::string> order{"P0", "P1", "P2", "P10", "P32", "aperiodic", "chattering", "non_finite"};
    std::vector<std::string> shuffled{"P10", "non_finite", "aperiodic", "P2", "P32", "P0", "chattering", "P1"};
    std::sort(shuffled.begin(), shuffled.end(),
              [](const std::string& a, const std::string& b) { return vimpact::label_before(a, b); });
    EXPECT_EQ(shuffled, order);
    EXPECT_FALSE(vimpact::label_before("P2", "P2"));
    EXPECT_TRUE(vimpact::label_before("P9", "P10"));
}
