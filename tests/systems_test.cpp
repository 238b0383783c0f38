// The steppable systems (include/vimpact/system/) against independent truths: the forced
// impact oscillator's closed form (impact times, states, the strobe map's Jacobian), the
// protocol's recorded section points (simulate: the same flow driven by its own observer),
// and finite differences of the systems' own steps for the tangent.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "exact_impact_oscillator.hpp"
#include "test_support.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/system/hybrid_system.hpp"
#include "vimpact/system/section_system.hpp"
#include "vimpact/system/tangent_system.hpp"

namespace {

using vimpact::hybrid_system;
using vimpact::outcome;
using vimpact::section_choice;
using vimpact::section_system;
using vimpact::tangent_system;
using vimpact::test::exact_impact_oscillator;
using vimpact::test::ld;
using vimpact::test::with;

constexpr double zeta = 0.05, omega = 0.8, F = 1.0, sigma = -1.0, r = 0.8;

vimpact::model forced()
{
    const auto m = vimpact::model::builtin("forced_impact_oscillator");
    return with(with(with(with(with(m, "zeta", zeta), "omega", omega), "F", F), "sigma", sigma), "r", r);
}

vimpact::flow_options tight(double tol = 1e-12)
{
    vimpact::flow_options f;
    f.integration.rtol = tol;
    f.integration.atol = tol;
    return f;
}

// The impact times and states of the closed form, and the state at a time landed on exactly.
TEST(Systems, HybridStepsMatchTheClosedForm)
{
    const exact_impact_oscillator exact(zeta, omega, F, r);
    const double t_end = 3.0 * static_cast<double>(exact.period());
    hybrid_system sys(forced(), Eigen::Vector3d(0.5, 0.0, 0.0), 0.0, {.flow = tight()});
    ld t = 0, y = 0.5, v = 0;  // the exact orbit, from its own impacts
    int impacts = 0;
    while (sys.time() < t_end) {
        ASSERT_EQ(sys.step(), outcome::ok);
        const auto& im = sys.impacts();
        for (std::size_t k = 0; k < im.size(); ++k, ++impacts) {
            const auto ti = exact.next_impact(t, y, v, sigma, t_end + 1);
            ASSERT_TRUE(ti.has_value());
            const auto [yi, vi] = exact.flow(t, y, v, *ti);
            EXPECT_NEAR(im.pre.t(k), static_cast<double>(*ti), 1e-8);
            EXPECT_NEAR(im.pre.x(k)[1], static_cast<double>(vi), 1e-8);
            EXPECT_EQ(im.post.x(k)[0], sigma);
            EXPECT_NEAR(im.post.x(k)[1], static_cast<double>(-r * vi), 1e-8);
            t = *ti;
            y = sigma;
            v = -r * vi;
        }
    }
    EXPECT_GE(impacts, 2);
    const double t_land = t_end + 1.25;  // mid-flight
    ASSERT_EQ(sys.advance_to(t_land), outcome::ok);
    EXPECT_EQ(sys.time(), t_land);  // exactly
    ASSERT_FALSE(exact.next_impact(t, y, v, sigma, t_land).has_value());
    const auto [ye, ve] = exact.flow(t, y, v, t_land);
    EXPECT_NEAR(sys.state()[0], static_cast<double>(ye), 1e-8);
    EXPECT_NEAR(sys.state()[1], static_cast<double>(ve), 1e-8);
    EXPECT_NEAR(sys.state()[2], omega * t_land, 1e-9);
    EXPECT_EQ(sys.step(0.5), outcome::ok);
    EXPECT_EQ(sys.time(), t_land + 0.5);
}

// Stepping the section system n times gives the points the protocol records from the same
// start with no transient: the same flow, driven by the protocol's observer there.
TEST(Systems, SectionStepsGiveTheProtocolsPoints)
{
    const auto m = vimpact::test::paper(16.0);
    for (const section_choice choice : {section_choice::crossings(0), section_choice::crossings(1), section_choice::impacts()}) {
        vimpact::protocol_options po;
        po.transient_impacts = 0;
        po.record_points = 25;
        po.section = choice;
        const auto sim = vimpact::simulate(m, vimpact::test::paper_ic(), po);
        ASSERT_EQ(sim.status, outcome::ok);
        section_system sys(m, vimpact::test::paper_ic(), 0.0, {.section = choice, .flow = po.flow, .method = po.method});
        for (std::size_t k = 0; k < sim.points.size(); ++k) {
            ASSERT_EQ(sys.step(), outcome::ok) << k;
            EXPECT_EQ(sys.time(), sim.points.t(k)) << k;
            EXPECT_LE(vimpact::test::max_abs_diff(sys.state(), sim.points.x(k)), 0.0) << k;
        }
    }
}

// The strobe map's Jacobian (theta = 0 to 2 pi) in (y, ydot) from the tangent system's
// projected deviations, against central differences of the closed form in long double.
TEST(Systems, TangentSectionJacobianMatchesTheClosedForm)
{
    const exact_impact_oscillator exact(zeta, omega, F, r);
    const double y0 = 0.5, v0 = 0.3;
    tangent_system sys(forced(), Eigen::Vector3d(y0, v0, 0.0), 0.0, {.flow = tight(), .section = 2});
    ASSERT_EQ(sys.step(), outcome::ok);
    EXPECT_NEAR(sys.time(), static_cast<double>(exact.period()), 1e-9);
    const Eigen::Matrix2d J = exact.strobe_jacobian(y0, v0, sigma);
    const Eigen::MatrixXd W = sys.deviations();
    EXPECT_LE(vimpact::test::max_abs_diff(W.topLeftCorner(2, 2), J), 1e-6 * J.cwiseAbs().maxCoeff()) << W << "\n" << J;
    // The strobe section moves the phase only: its row of the projected Jacobian is zero.
    EXPECT_LE(W.row(2).cwiseAbs().maxCoeff(), 1e-12);
}

// The continuous tangent's deviations through impacts against central differences of the
// hybrid system's own states at a time landed on exactly.
TEST(Systems, TangentFlowMatchesDifferencesOfTheFlow)
{
    const auto m = vimpact::test::paper(16.0);
    const Eigen::VectorXd x0 = vimpact::test::paper_ic();
    const double T = 30.0, h = 1e-6;
    tangent_system tan(m, x0, 0.0, {.flow = tight()});
    ASSERT_EQ(tan.advance_to(T), outcome::ok);
    EXPECT_EQ(tan.time(), T);
    EXPECT_GE(tan.stats().impacts, 1);
    for (int j = 0; j < 4; ++j) {
        Eigen::VectorXd xp = x0, xm = x0;
        xp[j] += h;
        xm[j] -= h;
        hybrid_system a(m, xp, 0.0, {.flow = tight()}), b(m, xm, 0.0, {.flow = tight()});
        ASSERT_EQ(a.advance_to(T), outcome::ok);
        ASSERT_EQ(b.advance_to(T), outcome::ok);
        const Eigen::VectorXd fd = (a.state() - b.state()) / (2 * h);
        EXPECT_LE((tan.deviations().col(j) - fd).cwiseAbs().maxCoeff(), 1e-5 * std::max(1.0, fd.cwiseAbs().maxCoeff()))
            << "column " << j << ": " << tan.deviations().col(j).transpose() << " vs " << fd.transpose();
    }
}

// The discrete tangent's deviations against differences of section steps from points of the
// section (perturbed along it: every coordinate but ydot, the section's).
TEST(Systems, TangentSectionMatchesDifferencesOfSectionSteps)
{
    const auto m = vimpact::test::paper(19.0);
    section_system on(m, vimpact::test::paper_ic(), 0.0, {.flow = tight()});
    ASSERT_EQ(on.step(40), outcome::ok);
    const Eigen::VectorXd xs = on.state();
    tangent_system tan(m, xs, 0.0, {.flow = tight(), .section = 0});
    ASSERT_EQ(tan.step(), outcome::ok);
    const double h = 1e-6;
    for (int j : {0, 2, 3}) {
        Eigen::VectorXd xp = xs, xm = xs;
        xp[j] += h;
        xm[j] -= h;
        section_system a(m, xp, 0.0, {.flow = tight()}), b(m, xm, 0.0, {.flow = tight()});
        ASSERT_EQ(a.step(), outcome::ok);
        ASSERT_EQ(b.step(), outcome::ok);
        const Eigen::VectorXd fd = (a.state() - b.state()) / (2 * h);
        EXPECT_LE((tan.deviations().col(j) - fd).cwiseAbs().maxCoeff(), 1e-5 * std::max(1.0, fd.cwiseAbs().maxCoeff()))
            << "column " << j << ": " << tan.deviations().col(j).transpose() << " vs " << fd.transpose();
    }
}

// reinit starts again as a new system: the same steps, to the bit; a copy goes on alike.
TEST(Systems, ReinitAndCopiesRepeatTheBits)
{
    const auto m = vimpact::test::paper(19.0);
    const Eigen::VectorXd x0 = vimpact::test::paper_ic();
    hybrid_system sys(m, x0);
    for (int k = 0; k < 300; ++k) ASSERT_EQ(sys.step(), outcome::ok);
    const Eigen::VectorXd x300 = sys.state();
    const double t300 = sys.time();
    hybrid_system copy = sys;
    ASSERT_EQ(sys.advance_to(t300 + 7.5), outcome::ok);
    ASSERT_EQ(copy.advance_to(t300 + 7.5), outcome::ok);
    EXPECT_EQ(sys.state(), copy.state());
    sys.reinit(x0);
    EXPECT_EQ(sys.time(), 0.0);
    for (int k = 0; k < 300; ++k) ASSERT_EQ(sys.step(), outcome::ok);
    EXPECT_EQ(sys.time(), t300);
    EXPECT_EQ(sys.state(), x300);

    tangent_system tan(m, x0, 0.0, {.section = 0});
    ASSERT_EQ(tan.step(5), outcome::ok);
    const Eigen::MatrixXd w5 = tan.deviations();
    tan.reinit(x0);
    ASSERT_EQ(tan.step(5), outcome::ok);
    EXPECT_EQ(tan.deviations(), w5);
}

// A parameter set on the system is the model's: the same steps as a system made with it.
TEST(Systems, SetParameterIsTheModelsValue)
{
    const Eigen::VectorXd x0 = vimpact::test::paper_ic();
    section_system a(vimpact::test::paper(16.0), x0);
    a.set_parameter(0, 19.0);
    section_system b(vimpact::test::paper(19.0), x0);
    ASSERT_EQ(a.step(10), outcome::ok);
    ASSERT_EQ(b.step(10), outcome::ok);
    EXPECT_EQ(a.state(), b.state());
    EXPECT_EQ(a.parameters()[0], 19.0);
    EXPECT_THROW(a.set_parameter(0, -1.0), vimpact::input_error);
}

std::string message_of(const std::function<void()>& f)
{
    try {
        f();
    } catch (const vimpact::input_error& e) {
        return e.what();
    }
    return "(no input_error)";
}

TEST(Systems, BadInputIsNamed)
{
    const auto m = vimpact::test::paper(16.0);
    const Eigen::VectorXd x0 = vimpact::test::paper_ic();
    EXPECT_NE(message_of([&] { hybrid_system(m, Eigen::Vector3d(0, 0, 0)); }).find("initial state"), std::string::npos);
    EXPECT_NE(message_of([&] { hybrid_system(m, Eigen::Vector4d(-1, 0, 0, 0.1)); }).find("not admissible"),
              std::string::npos);
    EXPECT_NE(message_of([&] { section_system(m, x0, 0.0, {.section = section_choice::crossings(5)}); }).find("5"),
              std::string::npos);
    EXPECT_NE(message_of([&] { tangent_system(m, x0, 0.0, {.section = 2}); }).find("section 2"), std::string::npos);
    EXPECT_NE(message_of([&] { tangent_system(m, x0, 0.0, {.deviations = 5}); }).find("deviations"), std::string::npos);
    hybrid_system sys(m, x0);
    ASSERT_EQ(sys.step(1.0), outcome::ok);
    EXPECT_NE(message_of([&] { sys.advance_to(0.5); }).find("t = 0.5"), std::string::npos);
    EXPECT_NE(message_of([&] { sys.step(-1.0); }).find("dt"), std::string::npos);
    tangent_system tan(m, x0, 0.0, {.section = 0});
    EXPECT_NE(message_of([&] { tan.advance_to(3.0); }).find("discrete"), std::string::npos);
    EXPECT_NE(message_of([&] { tan.set_deviations(Eigen::MatrixXd::Identity(4, 3)); }).find("4 x 4"), std::string::npos);
}

// In a contact phase (at rest on the barrier, the phase running on) a time is landed on
// exactly too: the constrained motion is y = sigma, ydot = 0, theta = omega t.
TEST(Systems, HybridLandsOnTimesInAContactPhase)
{
    const auto m = with(with(forced(), "sigma", 0.0), "r", 0.3);
    hybrid_system sys(m, Eigen::Vector3d(0.5, 0.0, 0.0), 0.0, {.flow = tight(1e-10)});
    for (int k = 0; k < 100000 && !sys.in_contact(); ++k) ASSERT_EQ(sys.step(), outcome::ok);
    ASSERT_TRUE(sys.in_contact());
    // The release comes when the free acceleration -y + F cos(theta) turns positive; stay before it.
    const double t0 = sys.time();
    const double theta_release = 2.0 * std::numbers::pi * std::ceil(sys.state()[2] / (2.0 * std::numbers::pi)) -
                                 std::numbers::pi / 2.0;
    const double t = t0 + 0.5 * std::max(0.0, (theta_release - sys.state()[2]) / omega);
    ASSERT_GT(t, t0);
    const double stuck_before = sys.stats().sticking_time;
    ASSERT_EQ(sys.advance_to(t), outcome::ok);
    EXPECT_EQ(sys.time(), t);
    EXPECT_TRUE(sys.in_contact());
    // Time in contact is counted once: the contact step that went past t is cut back to t.
    EXPECT_NEAR(sys.stats().sticking_time - stuck_before, t - t0, 1e-12 * t);
    EXPECT_EQ(sys.state()[0], 0.0);
    EXPECT_EQ(sys.state()[1], 0.0);
    EXPECT_NEAR(sys.state()[2], omega * t, 1e-9 * std::max(1.0, omega * t));
}

// A numerical end is an outcome: a step limit stops the system, which then stays.
TEST(Systems, LimitsAreOutcomes)
{
    vimpact::flow_options f;
    f.max_steps = 10;
    hybrid_system sys(vimpact::test::paper(16.0), vimpact::test::paper_ic(), 0.0, {.flow = f});
    EXPECT_EQ(sys.advance_to(1e3), outcome::step_limit);
    const double t = sys.time();
    EXPECT_EQ(sys.step(), outcome::step_limit);
    EXPECT_EQ(sys.time(), t);
    EXPECT_EQ(sys.status(), outcome::step_limit);
}

}  // namespace
