// Continuation of impacting periodic orbits (analysis/continuation.hpp), checked against
// mathematics that does not use the code under test:
//  - the forced impact oscillator's 1:1 impacting orbits in closed form (exact_impact_oscillator.hpp):
//    every branch point is a fixed point of the exact stroboscopic map, its multipliers are
//    the eigenvalues of that map's finite-difference Jacobian, and the fold, period-doubling
//    and grazing points are the closed form's (an extremum of sigma(phi), det(J + I) = 0, an
//    interior minimum of the orbit touching the barrier), to 1e-8 in the parameter;
//  - branch switching: the new branch has twice the period, meets the old one at the
//    bifurcation point, and its orbits are period-2 points of the exact map;
//  - the paper's model: a located period doubling lies between two Floquet analyses on either
//    side (the multiplier through -1), unstable orbits' multipliers equal those of a
//    finite-difference Jacobian of the section map, and the grazing of the barrier-free orbit
//    equals the grazing analysis's value.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include <Eigen/Eigenvalues>

#include "exact_impact_oscillator.hpp"
#include "exact_two_sided_oscillator.hpp"
#include "test_support.hpp"
#include "vimpact/analysis/bifurcation_curve.hpp"
#include "vimpact/analysis/continuation.hpp"
#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/orbit_map.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/core/format.hpp"

namespace {

using vimpact::bifurcation;
using vimpact::bifurcation_type;
using vimpact::continuation_options;
using vimpact::continuation_result;
using vimpact::model;
using vimpact::outcome;
using vimpact::test::exact_impact_oscillator;
using vimpact::test::ld;
using cplx = std::complex<double>;

double parameter(const model& m, const char* name) { return m.parameter(m.info().parameter_index(name)); }

model oscillator(double omega)
{
    return vimpact::test::with(model::builtin("forced_impact_oscillator"), "omega", omega);
}

exact_impact_oscillator exact_for(const model& m)
{
    return {parameter(m, "zeta"), parameter(m, "omega"), parameter(m, "F"), parameter(m, "r")};
}

// Continuation in `param` on the stroboscopic section, from the attractor at `start`.
continuation_options strobe_options(const model& m, const char* param, double start, double end)
{
    continuation_options o;
    o.parameter = m.info().parameter_index(param);
    o.start = start;
    o.end = end;
    o.protocol.section = vimpact::section_choice::crossings(m.info().section_index("strobe"));
    o.protocol.transient_impacts = 200;
    o.protocol.record_points = 20;
    return o;
}

continuation_options sigma_options(const model& m, double start, double end)
{
    return strobe_options(m, "sigma", start, end);
}

double pds_parameter(const continuation_result& r);

std::vector<const bifurcation*> of_type(const continuation_result& r, bifurcation_type t, int branch = -1)
{
    std::vector<const bifurcation*> out;
    for (const auto& b : r.bifurcations)
        if (b.type == t && (branch < 0 || b.branch == branch)) out.push_back(&b);
    return out;
}

double pds_parameter(const continuation_result& r)
{
    for (const auto& b : r.bifurcations)
        if (b.type == bifurcation_type::period_doubling) return b.parameter;
    return std::nan("");
}

// The eigenvalues of a 2 x 2 matrix, by decreasing modulus.
std::vector<cplx> eigenvalues(const Eigen::Matrix2d& J)
{
    const Eigen::EigenSolver<Eigen::Matrix2d> es(J, false);
    std::vector<cplx> v{es.eigenvalues()[0], es.eigenvalues()[1]};
    std::sort(v.begin(), v.end(), [](cplx a, cplx b) { return std::abs(a) > std::abs(b); });
    return v;
}

double distance(const std::vector<cplx>& a, const std::vector<cplx>& b)
{
    // Unordered comparison of two pairs (equal moduli of a complex pair).
    const double d1 = std::max(std::abs(a[0] - b[0]), std::abs(a[1] - b[1]));
    const double d2 = std::max(std::abs(a[0] - b[1]), std::abs(a[1] - b[0]));
    return std::min(d1, d2);
}

// Every point: closure within the tolerance, a fixed point of the exact map (periods-fold),
// multipliers of the exact map's Jacobian.
void check_points_exact(const model& m, const vimpact::continuation_branch& b, int every, const char* what)
{
    const auto ex = exact_for(m);
    int checked = 0, grazing = 0;
    double worst_fixed = 0.0, worst_mu = 0.0;
    for (std::size_t k = 0; k < b.points.size(); k += static_cast<std::size_t>(every)) {
        const auto& p = b.points[k];
        EXPECT_LE(p.closure, 1e-10) << what << " point " << k;
        // A grazing orbit (an impact velocity v or a gap minimum near 0) is not compared: the
        // exact map has no Jacobian there, and a gap minimum of -1e-12 (the located grazing's
        // accuracy) is an impact of velocity 1e-6 for the exact map.
        const double v_min = *std::min_element(p.min_impact_velocity.begin(), p.min_impact_velocity.end());
        const double g_min = *std::min_element(p.min_gap.begin(), p.min_gap.end());
        const double graze = std::min(v_min * v_min, std::abs(g_min));
        if (graze < 1e-8) {
            ++grazing;
            continue;
        }
        const ld y = p.state[0], v = p.state[1];
        const auto [y1, v1] = ex.strobe(y, v, p.parameter, b.returns);
        worst_fixed = std::max(worst_fixed, static_cast<double>(std::max(std::abs(y1 - y), std::abs(v1 - v))));
        // A difference step far below the distance to grazing (the map changes on the scale
        // v^2 there).
        const ld h = std::min(1e-6L, 1e-5L * static_cast<ld>(graze));
        const auto mu = eigenvalues(ex.strobe_jacobian(y, v, p.parameter, b.returns, h));
        ASSERT_EQ(p.section_multipliers.size(), 2U);
        // Relative to the largest multiplier (near grazing they grow like 1 / v), and to the
        // conditioning there: the map, accurate to about 1e-11, changes on the scale v^2.
        const double allowed = 1e-6 + 1e-11 / graze;
        worst_mu = std::max(worst_mu, distance(mu, p.section_multipliers) / std::max(1.0, std::abs(mu[0])) / allowed);
        EXPECT_EQ(p.stable, std::abs(mu[0]) < 1.0) << what << " point " << k << " |mu| " << std::abs(mu[0]);
        ++checked;
    }
    std::printf("%s: %d points against the exact map (%d grazing skipped): fixed-point error %.2e, multipliers %.2e of the allowed error\n",
                what, checked, grazing, worst_fixed, worst_mu);
    EXPECT_LE(worst_fixed, 1e-8) << what;
    EXPECT_LE(worst_mu, 1.0) << what;  // in units of the allowed error
    EXPECT_GE(checked, 5) << what;
}

// ---- fold -----------------------------------------------------------------------------------

// omega = 1.5: the 1:1 branch over sigma turns at a fold, the stable orbit (complex pair
// inside the circle) meeting an unstable one (a real multiplier through +1); the fold is the
// smallest sigma(phi) of the closed form.
TEST(Continuation, FoldOfTheOneOneOrbitIsTheExtremumOfTheClosedForm)
{
    const model m = oscillator(1.5);
    const auto ex = exact_for(m);
    // Golden section on sigma(phi) near its minimum.
    ld lo = 4.6L, hi = 5.2L;
    const ld g = (std::sqrt(5.0L) - 1) / 2;
    for (int it = 0; it < 200; ++it) {
        const ld a = hi - g * (hi - lo), b = lo + g * (hi - lo);
        if (ex.one_one(a).first < ex.one_one(b).first) hi = b;
        else lo = a;
    }
    const double sigma_fold = static_cast<double>(ex.one_one((lo + hi) / 2).first);

    auto o = sigma_options(m, 0.0, -3.0);
    const auto res = vimpact::continuation(m, {Eigen::Vector3d(0.5, 0.0, 0.0)}, o, 1);
    ASSERT_EQ(res.status, outcome::ok) << res.start_label;
    ASSERT_GE(res.branches.size(), 1U);
    const auto folds = of_type(res, bifurcation_type::fold, 0);
    ASSERT_EQ(folds.size(), 1U);
    std::printf("fold: sigma %.12f, closed form %.12f, error %.2e, multipliers %.6f %.6f\n", folds[0]->parameter,
                sigma_fold, folds[0]->parameter - sigma_fold, folds[0]->point.section_multipliers[0].real(),
                folds[0]->point.section_multipliers[1].real());
    EXPECT_TRUE(folds[0]->located);
    EXPECT_NEAR(folds[0]->parameter, sigma_fold, 1e-8);
    // At the fold a multiplier is 1.
    EXPECT_NEAR(folds[0]->point.section_multipliers[0].real(), 1.0, 1e-5);
    // Stable before it, unstable after it.
    const auto& pts = res.branches[0].points;
    const auto after = static_cast<std::size_t>(folds[0]->after_point);
    EXPECT_TRUE(pts[after].stable);
    ASSERT_LT(after + 2, pts.size());
    EXPECT_FALSE(pts[after + 2].stable);
    check_points_exact(m, res.branches[0], 3, "omega 1.5 branch");
}

// ---- period doubling and branch switching ---------------------------------------------------

// omega = 0.8: a real multiplier of the 1:1 orbit goes through -1 as sigma decreases.
TEST(Continuation, PeriodDoublingAndSwitchedBranchAgainstTheExactMap)
{
    const model m = oscillator(0.8);
    const auto ex = exact_for(m);
    // The closed form's period doubling: det(J + I) = 0 along phi, J the exact map's Jacobian
    // at the 1:1 orbit's strobe point.
    auto pd_test = [&](ld phi) {
        const auto [sigma, v] = ex.one_one(phi);
        const auto [y0, v0] = ex.one_one_strobe_point(phi);
        const Eigen::Matrix2d J = ex.strobe_jacobian(y0, v0, sigma);
        return (J + Eigen::Matrix2d::Identity()).determinant();
    };
    const bool sign_lo = pd_test(3.18L) > 0;
    ASSERT_NE(sign_lo, pd_test(3.22L) > 0);
    const ld phi_pd = exact_impact_oscillator::bisect([&](ld p) { return (pd_test(p) > 0) == sign_lo; }, 3.18L, 3.22L);
    const double sigma_pd = static_cast<double>(ex.one_one(phi_pd).first);

    auto o = sigma_options(m, -1.5, -2.3);
    o.switch_depth = 1;
    const auto res = vimpact::continuation(m, {Eigen::Vector3d(0.5, 0.0, 0.0)}, o, 2);
    ASSERT_EQ(res.status, outcome::ok) << res.start_label;
    const auto pds = of_type(res, bifurcation_type::period_doubling, 0);
    ASSERT_EQ(pds.size(), 1U);
    const bifurcation& pd = *pds[0];
    std::printf("period doubling: sigma %.12f, closed form %.12f, error %.2e\n", pd.parameter, sigma_pd,
                pd.parameter - sigma_pd);
    EXPECT_TRUE(pd.located);
    EXPECT_NEAR(pd.parameter, sigma_pd, 1e-8);
    EXPECT_NEAR(pd.point.section_multipliers.back().real() < -0.5 ? pd.point.section_multipliers.back().real()
                                                                  : pd.point.section_multipliers.front().real(),
                -1.0, 1e-5);
    check_points_exact(m, res.branches[0], 3, "omega 0.8 branch");

    // The doubled branch, from the bifurcation point.
    int switched = 0;
    const double T = static_cast<double>(ex.period());
    for (std::size_t b = 1; b < res.branches.size(); ++b) {
        const auto& br = res.branches[b];
        if (br.parent != 0) continue;
        ++switched;
        EXPECT_EQ(br.returns, 2);
        EXPECT_EQ(br.origin, static_cast<int>(&pd - res.bifurcations.data()));
        ASSERT_GE(br.points.size(), 5U);
        // It meets the old branch at the bifurcation point.
        EXPECT_EQ(br.points.front().parameter, pd.parameter);
        EXPECT_LE(vimpact::test::max_abs_diff(br.points.front().state, pd.point.state), 1e-12);
        for (const auto& p : br.points) EXPECT_NEAR(p.period, 2.0 * T, 1e-9);
        // Away from it, a genuine period-2 orbit: P(x) != x.
        const auto& q = br.points[4];
        EXPECT_GT(std::abs(q.section_points.x(1, 0) - q.section_points.x(0, 0)), 1e-6);
        std::vector<vimpact::continuation_point> rest(br.points.begin() + 1, br.points.end());
        vimpact::continuation_branch tail = br;
        tail.points = rest;
        check_points_exact(m, tail, 4, "doubled branch");
    }
    EXPECT_EQ(switched, 1);
}

// ---- grazing ----------------------------------------------------------------------------------

// omega = 0.8, sigma increasing from -1: the 1:1 orbit's interior minimum comes down to the
// barrier; there the impact sequence changes.
TEST(Continuation, GrazingIsWhereTheClosedFormsInteriorMinimumTouchesTheBarrier)
{
    const model m = oscillator(0.8);
    const auto ex = exact_for(m);
    ASSERT_LT(ex.interior_min_gap(2.91L), 0);
    ASSERT_GT(ex.interior_min_gap(2.93L), 0);
    const ld phi_g = exact_impact_oscillator::bisect([&](ld p) { return ex.interior_min_gap(p) < 0; }, 2.91L, 2.93L);
    const double sigma_g = static_cast<double>(ex.one_one(phi_g).first);

    const auto o = sigma_options(m, -1.0, -0.3);
    const auto res = vimpact::continuation(m, {Eigen::Vector3d(0.5, 0.0, 0.0)}, o, 1);
    ASSERT_EQ(res.status, outcome::ok);
    const auto g = of_type(res, bifurcation_type::grazing, 0);
    ASSERT_GE(g.size(), 1U);
    std::printf("grazing: sigma %.12f, closed form %.12f, error %.2e; branch ends %s\n", g[0]->parameter, sigma_g,
                g[0]->parameter - sigma_g, std::string(vimpact::to_string(res.branches[0].end)).c_str());
    EXPECT_TRUE(g[0]->located);
    EXPECT_NEAR(g[0]->parameter, sigma_g, 1e-8);
    EXPECT_EQ(g[0]->surface, 0);
    EXPECT_EQ(g[0]->sequence_before, std::vector<int>{0});
    EXPECT_EQ(g[0]->sequence_after, (std::vector<int>{0, 0}));
    EXPECT_LE(std::abs(g[0]->point.min_gap[0]), 1e-9);
}

// From the side without the impact, past the grazing onto the family with the new impact: the
// 1:1 orbit at omega = 0.8 whose interior minimum reaches the barrier goes on as an orbit with
// two impacts per period, every point of which is a fixed point of the exact map.
TEST(Continuation, PastAGrazingOntoTheFamilyWithTheNewImpact)
{
    const model m = oscillator(0.8);
    const auto o = sigma_options(m, -1.0, -0.3);
    const auto res = vimpact::continuation(m, {Eigen::Vector3d(0.5, 0.0, 0.0)}, o, 1);
    ASSERT_EQ(res.status, outcome::ok);
    const auto& b = res.branches[0];
    const auto g = of_type(res, bifurcation_type::grazing, 0);
    ASSERT_GE(g.size(), 1U);
    EXPECT_EQ(g[0]->sequence_after, (std::vector<int>{0, 0}));
    // Points past the grazing with two impacts per period.
    vimpact::continuation_branch past = b;
    past.points.clear();
    for (std::size_t k = static_cast<std::size_t>(g[0]->after_point) + 1; k < b.points.size(); ++k)
        if (b.points[k].impacts() == 2) past.points.push_back(b.points[k]);
    std::printf("past the grazing at sigma = %.9f: %zu points with two impacts, sigma %.6f .. %.6f; branch ends %s\n",
                g[0]->parameter, past.points.size(), past.points.empty() ? NAN : past.points.front().parameter,
                past.points.empty() ? NAN : past.points.back().parameter, std::string(vimpact::to_string(b.end)).c_str());
    ASSERT_GE(past.points.size(), 5U);
    check_points_exact(m, past, 1, "two-impact branch past the grazing");
}

// ---- Neimark-Sacker ---------------------------------------------------------------------------

// A forced linear oscillator whose damping c may be negative (a model file), its barrier far
// away: the periodic response y_p is an orbit for every c, and its strobe multipliers are
// exp((-c +- i sqrt(1 - c^2)) T), T = 2 pi / w: a complex pair that leaves the unit circle at
// c = 0 with argument +-T (mod 2 pi).
TEST(Continuation, NeimarkSackerOfTheForcedResponseIsAtZeroDamping)
{
    const char* text = R"toml(
name = "signed_damping_oscillator"
state = [{ name = "y" }, { name = "ydot" }, { name = "theta", unit = "rad" }]
initial_state = [0.0, 0.0, 0.0]
[parameters]
c = { default = 0.05, meaning = "damping ratio, of either sign" }
w = { default = 1.3 }
F = { default = 1.0 }
sigma = { default = -100.0 }
[derivatives]
y = "ydot"
ydot = "-2*c*ydot - y + F*cos(theta)"
theta = "w"
[angles]
theta = "2*pi"
[[surfaces]]
name = "barrier"
gap = "y - sigma"
reset = { ydot = "-0.8*ydot" }
[[sections]]
name = "strobe"
when = "sin(theta)"
direction = "up"
)toml";
    const model m = model::from_toml(text, "signed_damping_oscillator.toml");
    continuation_options o;
    o.parameter = m.info().parameter_index("c");
    o.start = 0.05;
    o.end = -0.05;
    o.protocol.section = vimpact::section_choice::crossings(m.info().section_index("strobe"));
    // From a point (the orbit closes after one return), not an attractor: Newton finds it.
    o.from_attractor = false;
    o.returns = 1;
    const auto res = vimpact::continuation(m, {Eigen::Vector3d(0.0, 0.0, 0.0)}, o, 1);
    ASSERT_EQ(res.status, outcome::ok);
    const auto ns = of_type(res, bifurcation_type::neimark_sacker, 0);
    ASSERT_EQ(ns.size(), 1U);
    const double T = 2.0 * std::numbers::pi / 1.3;
    const cplx mu = ns[0]->point.section_multipliers[0];
    std::printf("Neimark-Sacker: c = %.3e, multiplier %.12f%+.12fi (|mu| - 1 = %.1e), closed form arg %.12f\n",
                ns[0]->parameter, mu.real(), mu.imag(), std::abs(mu) - 1.0, std::remainder(T, 2.0 * std::numbers::pi));
    EXPECT_TRUE(ns[0]->located);
    EXPECT_NEAR(ns[0]->parameter, 0.0, 1e-8);
    EXPECT_NEAR(std::abs(mu), 1.0, 1e-7);
    EXPECT_NEAR(std::abs(std::arg(mu)), std::abs(std::remainder(T, 2.0 * std::numbers::pi)), 1e-7);
    // No fold or period doubling on the way, stable before and unstable after.
    EXPECT_EQ(res.bifurcations.size(), 1U);
    const auto& pts = res.branches[0].points;
    EXPECT_TRUE(pts.front().stable);
    EXPECT_FALSE(pts.back().stable);
    // Every point is the forced response: y_p(0) = F (1 - w^2) / D, ydot_p(0) = 2 c w^2 F / D.
    for (const auto& p : pts) {
        const double c = p.parameter, w = 1.3;
        const double D = (1 - w * w) * (1 - w * w) + (2 * c * w) * (2 * c * w);
        EXPECT_NEAR(p.state[0], (1 - w * w) / D, 1e-9);
        EXPECT_NEAR(p.state[1], 2 * c * w * w / D, 1e-9);
        EXPECT_NEAR(std::abs(p.section_multipliers[0]), std::exp(-c * T), 1e-8);
    }
}

// ---- the paper's model ------------------------------------------------------------------------

// Continuation in Ur on the paper's section (maxima of y), paper preset.
continuation_options paper_options(double start, double end)
{
    const model m;
    continuation_options o;
    o.parameter = m.info().parameter_index("Ur");
    o.start = start;
    o.end = end;
    return o;
}

// The P1 branch from Ur = 12 loses stability at a period doubling: a Floquet analysis of the
// orbit on either side (Newton from the branch's points, its own monodromy) has its multiplier
// on either side of -1, and a sweep that follows P1 upward leaves the label P1 there.
TEST(ContinuationPaper, PeriodDoublingOfP1AgreesWithFloquetAndTheSweep)
{
    const model m = vimpact::test::paper(12.0);
    const auto res = vimpact::continuation(m, {vimpact::test::paper_ic()}, paper_options(12.0, 15.1), 1);
    ASSERT_EQ(res.status, outcome::ok);
    EXPECT_EQ(res.start_label, "P1");
    const auto pds = of_type(res, bifurcation_type::period_doubling, 0);
    ASSERT_EQ(pds.size(), 1U);
    const double ur = pds[0]->parameter;
    std::printf("P1 period doubling at Ur = %.12f\n", ur);
    EXPECT_TRUE(pds[0]->located);
    // Floquet on either side, 1e-6 away, from the bifurcation's orbit point.
    vimpact::floquet_options fo;
    double lowest[2];
    for (int side = 0; side < 2; ++side) {
        const model ms = vimpact::test::with(m, "Ur", ur + (side == 0 ? -1e-6 : 1e-6));
        const auto f = vimpact::floquet_from_point(ms, pds[0]->point.state, 1, fo);
        ASSERT_EQ(f.status, outcome::ok);
        lowest[side] = 0.0;
        for (std::size_t i = 1; i < f.multipliers.size(); ++i)
            lowest[side] = std::min(lowest[side], f.multipliers[i].real());
    }
    std::printf("Floquet at Ur -+ 1e-6: smallest multiplier %.9f, %.9f\n", lowest[0], lowest[1]);
    EXPECT_GT(lowest[0], -1.0);
    EXPECT_LT(lowest[1], -1.0);
    // A sweep that follows P1 upward in steps of 0.02 has P1 up to the period doubling and
    // another label past it. Close below it the multiplier is near -1 and the transient decays
    // like |mu|^n: the 500 impacts settle to the period tolerance only from 0.025 below.
    vimpact::sweep_options so;
    so.parameter = m.info().parameter_index("Ur");
    so.values = vimpact::grid_values(14.94, 15.10, 9);
    // From the branch's orbit (P1 and P2 coexist there: the paper's start goes to P2).
    for (const auto& p : res.branches[0].points)
        if (p.parameter <= so.values.front()) so.initial_state = p.state;
    so.start = vimpact::sweep_start::follow;
    vimpact::job_options jo;
    jo.threads = 1;
    const auto sw = vimpact::sweep(vimpact::test::with(m, "Ur", 14.94), so, jo);
    int checked = 0;
    for (const auto& p : sw.points) {
        std::printf("  sweep Ur = %.2f: %s\n", p.value, p.label.label.c_str());
        if (p.value <= ur - 0.025) {
            EXPECT_EQ(p.label.label, "P1") << p.value;
        }
        if (p.value >= ur) {
            EXPECT_NE(p.label.label, "P1") << p.value;
        }
        checked += p.value <= ur - 0.025 || p.value >= ur;
    }
    EXPECT_GE(checked, 7);
}

// Switched at that period doubling, the P2 branch is unstable, turns at a grazing of the
// barrier (an impact's velocity going to 0) and comes back as the stable P2 with one impact
// per period. Every orbit closes to 1e-10, and the unstable ones have the multipliers of a
// finite-difference Jacobian of the section map without the tangent flow.
TEST(ContinuationPaper, UnstableP2MultipliersEqualFiniteDifferencesOfTheSectionMap)
{
    const model m = vimpact::test::paper(14.0);
    auto o = paper_options(14.0, 15.3);
    o.switch_depth = 1;
    const auto res = vimpact::continuation(m, {vimpact::test::paper_ic()}, o, 2);
    ASSERT_EQ(res.status, outcome::ok);
    ASSERT_GE(res.branches.size(), 2U);
    const auto& p2 = res.branches[1];
    EXPECT_EQ(p2.returns, 2);
    int unstable = 0;
    double worst = 0.0;
    for (const auto& p : p2.points) {
        EXPECT_LE(p.closure, 1e-10);
        if (p.stable || std::abs(p.section_multipliers[0]) < 1.05) continue;
        // The difference step far below the distance to grazing (v^2 for an impact of velocity
        // v: the map changes on that scale), and orbits that all but graze left out.
        const double v = *std::min_element(p.min_impact_velocity.begin(), p.min_impact_velocity.end());
        if (v * v < 1e-6) continue;
        const double h = std::min(1e-6, 1e-3 * v * v);
        // The map's Jacobian in the branch's chart by central differences of plain runs.
        const model mp = vimpact::test::with(m, "Ur", p.parameter);
        vimpact::orbit_map_request rq;
        rq.section = 0;
        rq.returns = 2;
        rq.chart_coordinate = p2.chart_coordinate;
        rq.guess = p.state;
        rq.tangent = false;
        const Eigen::VectorXd z = vimpact::chart_of(p.state, p2.chart_coordinate);
        Eigen::Matrix3d J;
        for (int j = 0; j < 3; ++j) {
            rq.z = z;
            rq.z[j] += h;
            const auto a = vimpact::orbit_map(mp, rq);
            rq.z = z;
            rq.z[j] -= h;
            const auto b = vimpact::orbit_map(mp, rq);
            ASSERT_TRUE(a.ok() && b.ok());
            J.col(j) = (a.residual - b.residual) / (2 * h);
        }
        J += Eigen::Matrix3d::Identity();
        const Eigen::EigenSolver<Eigen::Matrix3d> es(J, false);
        double largest = 0.0;
        for (int i = 0; i < 3; ++i) largest = std::max(largest, std::abs(es.eigenvalues()[i]));
        const double ours = std::abs(p.section_multipliers[0]);
        worst = std::max(worst, std::abs(largest - ours) / ours);
        ++unstable;
    }
    std::printf("%d unstable P2 orbits: largest multiplier against finite differences, worst relative error %.2e\n",
                unstable, worst);
    EXPECT_GE(unstable, 3);
    EXPECT_LE(worst, 1e-5);
    // The grazing turn, and the stable P2 at Ur = 15.3 with one impact per period.
    const auto g = of_type(res, bifurcation_type::grazing, 1);
    ASSERT_EQ(g.size(), 1U);
    EXPECT_EQ(g[0]->sequence_before.size(), 2U);
    EXPECT_EQ(g[0]->sequence_after.size(), 1U);
    EXPECT_LT(g[0]->parameter, pds_parameter(res));
    EXPECT_TRUE(p2.points.back().stable);
    EXPECT_EQ(p2.points.back().impacts(), 1);
    EXPECT_EQ(p2.end, vimpact::branch_end::range);
}

// The stable P2 followed downward from Ur = 16 reaches its grazing (its second minimum touches
// the barrier), goes on as the unstable P2 with two impacts per period, and turns where it
// meets P1 taken twice: the P1 period doubling (a pitchfork of P^2), located on the P1 family
// from this side to the P1 branch's own value, to 1e-8.
TEST(ContinuationPaper, TheStableP2LeadsBackToThePeriodDoublingOfP1)
{
    const model m = vimpact::test::paper(16.0);
    const auto from_p1 = vimpact::continuation(vimpact::test::paper(14.0), {vimpact::test::paper_ic()},
                                               paper_options(14.0, 15.3), 1);
    const double pd = pds_parameter(from_p1);
    const auto res = vimpact::continuation(m, {vimpact::test::paper_ic()}, paper_options(16.0, 14.5), 1);
    ASSERT_EQ(res.status, outcome::ok);
    EXPECT_EQ(res.start_label, "P2");
    const auto g = of_type(res, bifurcation_type::grazing, 0);
    const auto pds = of_type(res, bifurcation_type::period_doubling, 0);
    ASSERT_GE(g.size(), 1U);
    ASSERT_EQ(pds.size(), 1U);
    EXPECT_TRUE(of_type(res, bifurcation_type::fold, 0).empty());
    std::printf("stable P2 from Ur = 16: grazing at %.10f, P1's period doubling met at %.12f (from the P1 branch %.12f)\n",
                g[0]->parameter, pds[0]->parameter, pd);
    EXPECT_NEAR(pds[0]->parameter, pd, 1e-8);
    EXPECT_EQ(g[0]->sequence_before.size(), 1U);
    EXPECT_EQ(g[0]->sequence_after.size(), 2U);
    // The point is the P1 orbit: one section point, a multiplier at -1.
    EXPECT_EQ(pds[0]->point.section_points.size(), 1U);
    EXPECT_NEAR(pds[0]->point.section_multipliers[0].real(), -1.0, 1e-6);
    // Past it the branch runs back down to the grazing on its other leg.
    EXPECT_GE(g.size(), 2U);
}

// Continuation in sigma from -0.2 (where the paper's attractor misses the barrier) to -0.1.
continuation_options barrier_free_in_sigma(const model& m)
{
    continuation_options o;
    o.parameter = m.info().parameter_index("sigma");
    o.start = -0.2;
    o.end = -0.1;
    return o;
}

// In sigma at Ur = 25 the barrier-free orbit (P0) is followed up to where its minimum of y
// reaches the barrier: the grazing analysis's value; past it, onto the impacting orbits.
TEST(ContinuationPaper, GrazingOfTheBarrierFreeOrbitIsTheGrazingValue)
{
    const model m = vimpact::test::paper(25.0, -0.2);
    const continuation_options o = barrier_free_in_sigma(m);
    const auto res = vimpact::continuation(m, {vimpact::test::paper_ic()}, o, 1);
    ASSERT_EQ(res.status, outcome::ok);
    EXPECT_EQ(res.start_label, "P0");
    const auto g = of_type(res, bifurcation_type::grazing, 0);
    ASSERT_EQ(g.size(), 1U);
    vimpact::grazing_options go;
    go.parameter = m.info().parameter_index("sigma");
    const auto gr = vimpact::grazing(m, vimpact::test::paper_ic(), go);
    ASSERT_EQ(gr.status, outcome::ok);
    const double expected = gr.surfaces[0].parameter_value;
    std::printf("grazing by continuation %.12f, by the grazing analysis %.12f\n", g[0]->parameter, expected);
    EXPECT_NEAR(g[0]->parameter, expected, 1e-8);
    // Past it the orbit hits the barrier: the branch goes on with an impact per period.
    const auto& pts = res.branches[0].points;
    ASSERT_GT(pts.size(), static_cast<std::size_t>(g[0]->after_point) + 2);
    EXPECT_EQ(pts[static_cast<std::size_t>(g[0]->after_point)].impacts(), 0);
    EXPECT_GE(pts.back().impacts(), 1);
    EXPECT_GT(pts.back().parameter, expected);
}

// ---- the two-sided oscillator: the strobe meets an impact, a double grazing -------------------

using vimpact::test::exact_two_sided_oscillator;

exact_two_sided_oscillator exact_two_sided(double w) { return {0.05L, 1.0L, w, 0.8L}; }

// Continuation of the two-sided oscillator's symmetric P1 orbit in w on its strobe section
// (phase 0), from the attractor at `start`.
continuation_options two_sided_in_w(const model& m, double start, double end)
{
    return strobe_options(m, "w", start, end);
}

// The closed form's symmetric P1 orbit (d = 1) followed in w from its phase at w = 1: the
// phase of its right-stop impact at w (unwrapped, tracked from w = 1 in steps of 0.005).
ld tracked_phase(ld w)
{
    ld phi = exact_two_sided(1.0).symmetric_phase_near(1.0L, 0.0754L);
    for (ld at = 1.0L; at > w;) {
        at = std::max(w, at - 0.005L);
        phi = exact_two_sided(static_cast<double>(at)).symmetric_phase_near(1.0L, phi);
    }
    return phi;
}

// Where the closed form's tracked phase of the right-stop impact passes through 0.
ld closed_form_event()
{
    return exact_impact_oscillator::bisect([](ld w) { return tracked_phase(w) < 0; }, 0.78L, 0.80L);
}

// The orbit of `b` whose section point is closest to the right stop: the located event.
const vimpact::continuation_point& event_point(const vimpact::continuation_branch& b)
{
    return *std::min_element(b.points.begin(), b.points.end(), [](const auto& p, const auto& q) {
        return std::abs(1.0 - p.state[0]) < std::abs(1.0 - q.state[0]);
    });
}

// The symmetric P1 orbit of the closed form meets the strobe section (its right-stop impact at
// phase 0) where the tracked phase passes through 0, and grazes where the largest interior
// maximum of its flight from the right stop to the left one reaches the right stop.
TEST(ContinuationTwoSided, BranchGoesOnWhereTheStrobeMeetsAnImpactDownToTheDoubleGrazing)
{
    // The closed form, by bisection in w (nothing of the continuation is used).
    const ld w_event = closed_form_event();
    const ld phi_g = tracked_phase(0.53L);
    const ld w_graze = exact_impact_oscillator::bisect(
        [&](ld w) {
            const auto ex = exact_two_sided(static_cast<double>(w));
            return ex.interior_extrema(ex.symmetric_phase_near(1.0L, phi_g)).first > 1.0L;
        },
        0.52L, 0.53L);
    std::printf("closed form: the strobe meets the right-stop impact at w = %.12Lf, the orbit grazes at w = %.12Lf\n",
                w_event, w_graze);

    const model m = model::builtin("two_sided_impact_oscillator");
    const auto o = two_sided_in_w(m, 1.0, 0.4);
    const auto res = vimpact::continuation(m, {m.initial_state()}, o, 1);
    ASSERT_EQ(res.status, outcome::ok) << res.start_label;
    ASSERT_EQ(res.branches.size(), 1U);
    const auto& b = res.branches[0];
    std::printf("branch: %zu points, w %.12f .. %.12f, ends %s\n", b.points.size(), b.points.back().parameter,
                b.points.front().parameter, vimpact::end_reason(b, "w").c_str());
    // Through the event: orbits on both sides of it, and the one where it happens (its section
    // point on the right stop) at the closed form's w.
    const auto& e = event_point(b);
    std::printf("located event: w %.12f, error %.2e, gap at the section point %.2e\n", e.parameter,
                e.parameter - static_cast<double>(w_event), 1.0 - e.state[0]);
    EXPECT_NEAR(e.parameter, static_cast<double>(w_event), 1e-9);
    EXPECT_LE(std::abs(1.0 - e.state[0]), 1e-10);
    EXPECT_TRUE(std::any_of(b.points.begin(), b.points.end(), [](const auto& p) { return p.parameter < 0.7; }));
    // The double grazing, located to the closed form's value, both stops at once; the branch
    // ends there.
    const auto g = of_type(res, bifurcation_type::grazing, 0);
    ASSERT_EQ(g.size(), 2U);
    for (const auto* gb : g) {
        std::printf("grazing (surface %d) at w = %.12f, closed form %.12Lf, error %.2e\n", gb->surface, gb->parameter,
                    w_graze, gb->parameter - static_cast<double>(w_graze));
        EXPECT_TRUE(gb->located);
        EXPECT_NEAR(gb->parameter, static_cast<double>(w_graze), 1e-9);
        EXPECT_LE(gb->point.min_gap[static_cast<std::size_t>(gb->surface)], 1e-9);
        EXPECT_EQ(gb->sequence_before.size(), 2U);
        EXPECT_GT(gb->sequence_after.size(), 2U);
    }
    EXPECT_NE(g[0]->surface, g[1]->surface);
    EXPECT_EQ(b.end, vimpact::branch_end::grazing);
    EXPECT_EQ(b.points.back().parameter, g[0]->parameter);
    EXPECT_EQ(vimpact::end_reason(b, "w"), "grazing at w = " + vimpact::format_double(g[0]->parameter));
    // Every orbit of the branch, on both sides of the event, a fixed point of the exact
    // stroboscopic map (away from the event and the grazing, where it is not smooth).
    double worst = 0.0;
    int checked = 0, below = 0;
    for (const auto& p : b.points) {
        if (std::abs(p.parameter - static_cast<double>(w_event)) < 1e-6 || p.parameter < static_cast<double>(w_graze) + 1e-4)
            continue;
        const auto ex = exact_two_sided(p.parameter);
        const auto [x1, v1] = ex.strobe(p.state[0], p.state[1], 1.0L);
        worst = std::max(worst, static_cast<double>(std::max(std::abs(x1 - p.state[0]), std::abs(v1 - p.state[1]))));
        ++checked;
        below += p.parameter < static_cast<double>(w_event);
    }
    std::printf("%d orbits (%d past the event) against the exact map: fixed-point error %.2e\n", checked, below, worst);
    EXPECT_GE(below, 10);
    EXPECT_LE(worst, 1e-8);
}

// The other way through the same event: from w = 0.7 up, the right-stop impact comes just
// before the strobe's return and then just after it; the branch goes on to the range's end.
TEST(ContinuationTwoSided, UpwardsThroughTheStrobeEventToTheRangesEnd)
{
    const ld w_event = closed_form_event();
    const model m = model::builtin("two_sided_impact_oscillator");
    const auto res = vimpact::continuation(m, {m.initial_state()}, two_sided_in_w(m, 0.7, 1.0), 1);
    ASSERT_EQ(res.branches.size(), 1U);
    const auto& b = res.branches[0];
    const auto& e = event_point(b);
    std::printf("upwards: %zu points, ends %s; event at w %.12f, error %.2e, gap at the section point %.2e\n",
                b.points.size(), vimpact::end_reason(b, "w").c_str(), e.parameter,
                e.parameter - static_cast<double>(w_event), 1.0 - e.state[0]);
    EXPECT_NEAR(e.parameter, static_cast<double>(w_event), 1e-9);
    EXPECT_LE(std::abs(1.0 - e.state[0]), 1e-10);
    EXPECT_EQ(b.end, vimpact::branch_end::range);
    EXPECT_EQ(b.points.back().parameter, 1.0);
    double worst = 0.0;
    for (const auto& p : b.points) {
        if (std::abs(p.parameter - static_cast<double>(w_event)) < 1e-6) continue;
        const auto [x1, v1] = exact_two_sided(p.parameter).strobe(p.state[0], p.state[1], 1.0L);
        worst = std::max(worst, static_cast<double>(std::max(std::abs(x1 - p.state[0]), std::abs(v1 - p.state[1]))));
    }
    EXPECT_LE(worst, 1e-8);
}

// Every end of a branch says what happened, with the parameter value where it did.
TEST(ContinuationEnds, EveryEndSaysWhatHappenedAndWhere)
{
    const model m = model::builtin("two_sided_impact_oscillator");
    // The range's end.
    auto o = two_sided_in_w(m, 1.0, 0.9);
    auto res = vimpact::continuation(m, {m.initial_state()}, o, 1);
    ASSERT_EQ(res.branches.size(), 1U);
    EXPECT_EQ(res.branches[0].end, vimpact::branch_end::range);
    EXPECT_EQ(vimpact::end_reason(res.branches[0], "w"), "range");
    EXPECT_EQ(res.branches[0].points.back().parameter, 0.9);
    // The point limit.
    o.arclength.max_points = 4;
    res = vimpact::continuation(m, {m.initial_state()}, o, 1);
    ASSERT_EQ(res.branches.size(), 1U);
    EXPECT_EQ(res.branches[0].points.size(), 4U);
    EXPECT_EQ(res.branches[0].end, vimpact::branch_end::point_limit);
    EXPECT_EQ(vimpact::end_reason(res.branches[0], "w"),
              "max points at w = " + vimpact::format_double(res.branches[0].points.back().parameter));
    // Steps the corrector cannot close in one Newton iteration and may not shorten: the first
    // step fails at its minimum length.
    o = two_sided_in_w(m, 1.0, 0.4);
    o.arclength.newton_iterations = 1;
    o.arclength.step = o.arclength.min_step = o.arclength.max_step = 0.05;
    res = vimpact::continuation(m, {m.initial_state()}, o, 1);
    ASSERT_EQ(res.branches.size(), 1U) << vimpact::to_string(res.status);
    EXPECT_EQ(res.branches[0].end, vimpact::branch_end::step_too_small);
    EXPECT_EQ(vimpact::end_reason(res.branches[0], "w"), "step too small at w = 1");
}

// A reset that moves the forcing phase (the stop delays the forcing by 0.1) makes the strobe
// section skip a crossing when the impact moves before it: there the section map is not
// smooth, and the branch ends where its section point meets the impact, located (the section
// point on the stop).
TEST(ContinuationEnds, SectionMeetingAnImpactThatCannotBeCrossedEndsTheBranchThere)
{
    std::ifstream in(VIMPACT_SOURCE_DIR "/examples/models/two_sided_impact_oscillator.toml");
    std::stringstream file;
    file << in.rdbuf();
    std::string text = file.str();
    const std::string reset = "reset = { v = \"-r*v\" }";
    const auto at = text.find(reset);
    ASSERT_NE(at, std::string::npos);
    text.replace(at, reset.size(), "reset = { v = \"-r*v\", phi = \"phi + 0.1\" }");
    const model m = model::from_toml(text);
    const auto o = two_sided_in_w(m, 1.0, 0.4);
    const auto res = vimpact::continuation(m, {m.initial_state()}, o, 1);
    ASSERT_EQ(res.branches.size(), 1U) << vimpact::to_string(res.status);
    const auto& b = res.branches[0];
    std::printf("phase-shifting stop: %zu points, ends %s; gap at the last section point %.2e\n", b.points.size(),
                vimpact::end_reason(b, "w").c_str(), 1.0 - b.points.back().state[0]);
    EXPECT_EQ(b.end, vimpact::branch_end::section_impact);
    EXPECT_LE(std::abs(1.0 - b.points.back().state[0]), 1e-9);
    EXPECT_EQ(vimpact::end_reason(b, "w"),
              "section meets an impact at w = " + vimpact::format_double(b.points.back().parameter));
}

// ---- two-parameter curves ---------------------------------------------------------------------

// The curve's points against the exact map: each a fixed point whose Jacobian has the
// bifurcation's multiplier (+1 fold, -1 period doubling), or whose flight just touches the
// barrier (grazing).
void check_curve_exact(const model& m, const vimpact::bifurcation_curve& c, const char* q_name, int returns,
                       const char* what)
{
    double worst_fixed = 0.0, worst_condition = 0.0;
    for (const auto& p : c.points) {
        EXPECT_LE(p.closure, 1e-10) << what;
        const model mq = vimpact::test::with(vimpact::test::with(m, "sigma", p.parameter), q_name, p.parameter2);
        const auto ex = exact_for(mq);
        const ld y = p.state[0], v = p.state[1];
        // A grazing orbit's minimum is 0 to about 1e-12 of either sign, and a negative one is
        // an impact of velocity 1e-6 to the exact map: the barrier is lowered by 1e-9 for it.
        const ld shift = c.type == bifurcation_type::grazing ? 1e-9L : 0.0L;
        const auto [y1, v1] = ex.strobe(y, v, p.parameter - shift, returns);
        worst_fixed = std::max(worst_fixed, static_cast<double>(std::max(std::abs(y1 - y), std::abs(v1 - v))));
        double condition = 0.0;
        if (c.type == bifurcation_type::grazing) {
            condition = static_cast<double>(std::abs(ex.smallest_interior_gap(y, v, p.parameter - shift, returns) - shift));
        } else {
            const double target = c.type == bifurcation_type::fold ? 1.0 : -1.0;
            const auto mu = eigenvalues(ex.strobe_jacobian(y, v, p.parameter, returns));
            condition = std::min(std::abs(mu[0] - target), std::abs(mu[1] - target));
        }
        worst_condition = std::max(worst_condition, condition);
    }
    std::printf("%s: %zu points, %s from %.4f to %.4f (ends %s, %s); fixed-point error %.2e, condition error %.2e\n",
                what, c.points.size(), q_name, c.points.front().parameter2, c.points.back().parameter2,
                std::string(vimpact::to_string(c.end_backward)).c_str(), std::string(vimpact::to_string(c.end_forward)).c_str(),
                worst_fixed, worst_condition);
    EXPECT_GE(c.points.size(), 5U) << what;
    EXPECT_LE(worst_fixed, 1e-8) << what;
    EXPECT_LE(worst_condition, 1e-8) << what;
}

TEST(BifurcationCurves, FoldPeriodDoublingAndGrazingCurvesOfTheImpactOscillatorAgainstTheExactMap)
{
    // Fold of the 1:1 orbit at omega = 1.5, followed in r.
    {
        const model m = oscillator(1.5);
        const auto o = sigma_options(m, 0.0, -3.0);
        const auto res = vimpact::continuation(m, {Eigen::Vector3d(0.5, 0.0, 0.0)}, o, 1);
        ASSERT_EQ(of_type(res, bifurcation_type::fold, 0).size(), 1U);
        vimpact::curve_options c;
        c.parameter2 = m.info().parameter_index("r");
        c.lo2 = 0.6;
        c.hi2 = 0.95;
        c.types = {bifurcation_type::fold};
        const auto curves = vimpact::continue_bifurcations(m, res, o, c, 1);
        ASSERT_EQ(curves.size(), 1U);
        check_curve_exact(m, curves[0], "r", 1, "fold curve");
        EXPECT_DOUBLE_EQ(curves[0].points[curves[0].start].parameter2, 0.8);
    }
    // Period doubling and grazing of the 1:1 orbit at omega = 0.8, followed in omega.
    {
        const model m = oscillator(0.8);
        auto o = sigma_options(m, -1.0, -2.3);
        const auto res = vimpact::continuation(m, {Eigen::Vector3d(0.5, 0.0, 0.0)}, o, 1);
        vimpact::curve_options c;
        c.parameter2 = m.info().parameter_index("omega");
        c.lo2 = 0.75;
        c.hi2 = 0.85;
        c.types = {bifurcation_type::period_doubling};
        const auto pd = vimpact::continue_bifurcations(m, res, o, c, 1);
        ASSERT_EQ(pd.size(), 1U);
        check_curve_exact(m, pd[0], "omega", 1, "period-doubling curve");

        o = sigma_options(m, -1.0, -0.3);
        const auto rg = vimpact::continuation(m, {Eigen::Vector3d(0.5, 0.0, 0.0)}, o, 1);
        c.types = {bifurcation_type::grazing};
        const auto g = vimpact::continue_bifurcations(m, rg, o, c, 1);
        ASSERT_EQ(g.size(), 1U);
        check_curve_exact(m, g[0], "omega", 1, "grazing curve");
    }
}

// The grazing of the paper's barrier-free orbit followed in (sigma, Ur) is the grazing line of
// the periodicity map: at every point the grazing analysis's value of sigma.
TEST(BifurcationCurves, GrazingCurveOfTheBarrierFreeOrbitIsTheGrazingLine)
{
    const model m = vimpact::test::paper(25.0, -0.2);
    const continuation_options o = barrier_free_in_sigma(m);
    const auto res = vimpact::continuation(m, {vimpact::test::paper_ic()}, o, 1);
    vimpact::curve_options c;
    c.parameter2 = m.info().parameter_index("Ur");
    c.lo2 = 12.0;
    c.hi2 = 25.0;
    const auto curves = vimpact::continue_bifurcations(m, res, o, c, 1);
    ASSERT_EQ(curves.size(), 1U);
    const auto& g = curves[0];
    EXPECT_EQ(g.type, bifurcation_type::grazing);
    ASSERT_GE(g.points.size(), 10U);
    EXPECT_DOUBLE_EQ(g.points.front().parameter2, 12.0);
    EXPECT_DOUBLE_EQ(g.points.back().parameter2, 25.0);
    double worst = 0.0;
    vimpact::grazing_options go;
    go.parameter = m.info().parameter_index("sigma");
    for (std::size_t k = 0; k < g.points.size(); k += 3) {
        const auto& p = g.points[k];
        const auto gr = vimpact::grazing(vimpact::test::with(m, "Ur", p.parameter2), vimpact::test::paper_ic(), go);
        ASSERT_EQ(gr.status, outcome::ok);
        worst = std::max(worst, std::abs(p.parameter - gr.surfaces[0].parameter_value));
    }
    std::printf("grazing curve: %zu points over Ur 12..25, worst difference from the grazing analysis %.2e\n",
                g.points.size(), worst);
    EXPECT_LE(worst, 1e-9);
}

}  // namespace

