// Model files of any state dimension: the ones VIMPACT_MODEL_DIMS does not list run on
// table_model<Eigen::Dynamic>. The model here is K decoupled copies of the two-sided impact
// oscillator (examples/models/two_sided_impact_oscillator.toml), copy k with its own forcing
// amplitude a_k: every result of the K-copy model is known from K runs of the one-copy model.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "engine_instances.hpp"
#include "test_support.hpp"
#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/lyapunov.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/model/model.hpp"
#include "vimpact/model/model_file.hpp"

using namespace vimpact;

namespace {

// K copies: states x_k, v_k, p_k; the shared parameters of the example and a_k; the stops of
// copy k < `impacting` are surfaces 2k (right) and 2k + 1 (left), the other copies have none;
// the section is copy 0's phase (every copy's phase is the same, p_k' = w).
std::string copies_text(int K, int impacting)
{
    std::ostringstream t;
    t << "name = \"copies" << K << "\"\nstate = [";
    for (int k = 0; k < K; ++k) t << (k ? ", " : "") << "\"x" << k << "\", \"v" << k << "\", \"p" << k << "\"";
    t << "]\n[parameters]\nzeta = { default = 0.05 }\nw = { default = 1.2, above = 0 }\nd = { default = 1.0 }\n"
         "r = { default = 0.8 }\n";
    for (int k = 0; k < K; ++k) t << "a" << k << " = { default = 1.0 }\n";
    t << "[derivatives]\n";
    for (int k = 0; k < K; ++k)
        t << "x" << k << " = \"v" << k << "\"\nv" << k << " = \"-2*zeta*v" << k << " - x" << k << " + a" << k << "*cos(p"
          << k << ")\"\np" << k << " = \"w\"\n";
    t << "[angles]\n";
    for (int k = 0; k < K; ++k) t << "p" << k << " = \"2*pi\"\n";
    for (int k = 0; k < impacting; ++k)
        t << "[[surfaces]]\nname = \"right" << k << "\"\ngap = \"d - x" << k << "\"\nreset = { v" << k << " = \"-r*v" << k
          << "\" }\n[[surfaces]]\nname = \"left" << k << "\"\ngap = \"x" << k << " + d\"\nreset = { v" << k
          << " = \"-r*v" << k << "\" }\n";
    t << "[[sections]]\nname = \"strobe\"\nwhen = \"sin(p0)\"\ndirection = \"up\"\n";
    return t.str();
}

model copies(int K, int impacting)
{
    return model::with_defaults(compile_model_text(copies_text(K, impacting), "copies.toml"));
}
model copies(int K) { return copies(K, K); }

// Copy k's amplitude: close enough to the example's 1 that every copy has its period-1 orbit.
double amplitude(int k) { return 1.0 + 0.01 * k; }

model with_amplitudes(model m, int K)
{
    for (int k = 0; k < K; ++k) {
        std::ostringstream name;  // not "a" + std::to_string(k): a false -Wstringop-overflow in GCC 12
        name << "a" << k;
        m = test::with(m, name.str(), amplitude(k));
    }
    return m;
}
model single(int k) { return test::with(copies(1), "a0", amplitude(k)); }
// Copy k without stops: the one copy with its stops out of reach (the response's amplitude
// is about 2.3).
model free_single(int k) { return test::with(single(k), "d", 1e3); }

// Copy k starts at (0.1 k, 0, 0): the copies do not hit their stops at the same times.
Eigen::VectorXd start(int K)
{
    Eigen::VectorXd x = Eigen::VectorXd::Zero(3 * K);
    for (int k = 0; k < K; ++k) x[3 * k] = 0.1 * k;
    return x;
}
Eigen::VectorXd start_of(int k) { return start(k + 1).tail(3); }

// The integration tolerance of every run here. The copies' runs take other steps than the
// one-copy runs (the error norm is over all states), so their impacts agree to what the
// tolerance gives over the window, not to the bit: `agree` below.
constexpr double tol = 1e-12;
constexpr double agree = 1e-8;

protocol_options window(long points)
{
    protocol_options o;
    o.transient_impacts = 0;
    o.record_points = points;
    o.flow = test::flow_tolerances(tol, 1e5);
    return o;
}

// Every impact of copy k in the K-copy run `all` is the one-copy run's, at the same time and
// state; and so are the section points.
void expect_copy_matches(const simulation& all, const simulation& one, int k)
{
    std::vector<std::size_t> mine;
    for (std::size_t i = 0; i < all.impacts.size(); ++i)
        if (all.impacts.surface[i] / 2 == k) mine.push_back(i);
    ASSERT_EQ(mine.size(), one.impacts.size()) << "copy " << k;
    for (std::size_t j = 0; j < mine.size(); ++j) {
        const std::size_t i = mine[j];
        EXPECT_EQ(all.impacts.surface[i] % 2, one.impacts.surface[j]) << "copy " << k << " impact " << j;
        EXPECT_NEAR(all.impacts.pre.t(i), one.impacts.pre.t(j), agree * std::max(1.0, one.impacts.pre.t(j)))
            << "copy " << k << " impact " << j;
        const Eigen::VectorXd pre = all.impacts.pre.x(i).segment(3 * k, 3);
        EXPECT_LE((pre - one.impacts.pre.x(j)).cwiseAbs().maxCoeff(), agree) << "copy " << k << " impact " << j;
    }
    ASSERT_EQ(all.points.size(), one.points.size());
    for (std::size_t i = 0; i < one.points.size(); ++i) {
        EXPECT_NEAR(all.points.t(i), one.points.t(i), agree * std::max(1.0, one.points.t(i)));
        const Eigen::VectorXd x = all.points.x(i).segment(3 * k, 3);
        EXPECT_LE((x - one.points.x(i)).cwiseAbs().maxCoeff(), agree) << "copy " << k << " point " << i;
    }
}

// Every element of `want` matched by a distinct element of `got` within `eps` (and as many).
void expect_same_multiset(std::vector<std::complex<double>> got, const std::vector<std::complex<double>>& want,
                          double eps)
{
    ASSERT_EQ(got.size(), want.size());
    for (const auto& w : want) {
        auto best = std::min_element(got.begin(), got.end(),
                                     [&](const auto& a, const auto& b) { return std::abs(a - w) < std::abs(b - w); });
        ASSERT_NE(best, got.end());
        EXPECT_LE(std::abs(*best - w), eps) << "multiplier " << w << " nearest " << *best;
        got.erase(best);
    }
}

}  // namespace

// 4 copies: 12 states, past the fixed-size instances of the default build (1 to 4).
TEST(AnyDimension, TwelveStatesAreFourCopies)
{
    constexpr int K = 4;
    const model m = with_amplitudes(copies(K), K);
    ASSERT_EQ(m.dim(), 3 * K);
    const simulation all = simulate(m, start(K), window(40));
    ASSERT_EQ(all.status, outcome::ok);
    for (int k = 0; k < K; ++k) {
        const simulation one = simulate(single(k), start_of(k), window(40));
        ASSERT_EQ(one.status, outcome::ok);
        expect_copy_matches(all, one, k);
    }
}

// Floquet: the monodromy of decoupled copies over the common period is block diagonal, so its
// multipliers are the copies' multipliers together (each copy's trivial 1 among them).
// Newton closes each orbit to 1e-11 and the tangent is integrated at 1e-12: the multipliers
// agree to 1e-7.
TEST(AnyDimension, FloquetMultipliersAreTheCopiesTogether)
{
    constexpr int K = 4;
    floquet_options o;
    o.protocol.flow = test::flow_tolerances(tol, 1e6);
    const floquet_result all = floquet(with_amplitudes(copies(K), K), start(K), o);
    ASSERT_EQ(all.status, outcome::ok) << all.label;
    std::vector<std::complex<double>> want;
    std::vector<floquet_result> ones;
    int period = 1;
    for (int k = 0; k < K; ++k) {
        ones.push_back(floquet(single(k), start_of(k), o));
        ASSERT_EQ(ones.back().status, outcome::ok) << ones.back().label;
        want.insert(want.end(), ones.back().multipliers.begin(), ones.back().multipliers.end());
        period = std::lcm(period, ones.back().section_returns);
    }
    long impacts = 0;
    for (const auto& one : ones) impacts += one.impacts_per_period * (period / one.section_returns);
    EXPECT_EQ(all.section_returns, period);
    EXPECT_EQ(all.impacts_per_period, impacts);
    expect_same_multiset(all.multipliers, want, 1e-7);
}

// Lyapunov: decoupled copies keep block-diagonal deviations, whose QR factors are block
// diagonal too, so the spectrum is the copies' spectra together. Both runs average over the
// same time from the same states; they differ by the integration only, far inside the
// standard error of the largest exponent, and 1e-6 for the others.
TEST(AnyDimension, LyapunovSpectrumIsTheCopiesTogether)
{
    constexpr int K = 4;
    lyapunov_options o;
    o.transient_impacts = 0;
    o.time = 64.0 * o.t0;
    o.flow = test::flow_tolerances(tol, 1e6);
    const lyapunov_result all = lyapunov(with_amplitudes(copies(K), K), start(K), o);
    ASSERT_EQ(all.status, outcome::ok);
    ASSERT_EQ(all.exponents.size(), 3 * K);
    std::vector<double> want;
    double largest_error = 0.0;
    for (int k = 0; k < K; ++k) {
        const lyapunov_result one = lyapunov(single(k), start_of(k), o);
        ASSERT_EQ(one.status, outcome::ok);
        want.insert(want.end(), one.exponents.begin(), one.exponents.end());
        largest_error = std::max(largest_error, one.lle_standard_error);
    }
    std::sort(want.begin(), want.end(), std::greater<>());
    EXPECT_NEAR(all.exponents[0], want[0], std::max(largest_error, 1e-6));
    for (int i = 1; i < 3 * K; ++i) EXPECT_NEAR(all.exponents[i], want[static_cast<std::size_t>(i)], 1e-6) << i;
}

// Identical copies started alike hit their stops at the same instant, one surface per copy:
// each impact after the located one is taken at that instant too (not a start beyond the
// surface, which ended the run inadmissible). Each copy runs the one-copy orbit, and the
// monodromy is the one copy's block K times: its multipliers, each K times. 3 copies: 9
// states, sized at run time.
TEST(AnyDimension, IdenticalCopiesHitTheirStopsTogether)
{
    constexpr int K = 3;
    const model m = copies(K);  // every a_k = 1
    const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(3 * K);
    const simulation all = simulate(m, x0, window(40));
    ASSERT_EQ(all.status, outcome::ok);
    const simulation one = simulate(single(0), Eigen::VectorXd::Zero(3), window(40));  // a_0 = 1
    ASSERT_EQ(one.status, outcome::ok);
    ASSERT_GT(one.impacts.size(), 10U);
    for (int k = 0; k < K; ++k) expect_copy_matches(all, one, k);
    // The copies' impacts come K at a time, at one instant.
    ASSERT_EQ(all.impacts.size(), K * one.impacts.size());
    for (std::size_t i = 0; i < all.impacts.size(); i += K)
        for (std::size_t j = 1; j < static_cast<std::size_t>(K); ++j)
            EXPECT_EQ(all.impacts.pre.t(i + j), all.impacts.pre.t(i)) << i;

    floquet_options o;
    o.protocol.flow = test::flow_tolerances(tol, 1e6);
    const floquet_result f = floquet(m, x0, o);
    const floquet_result g = floquet(copies(1), Eigen::VectorXd::Zero(3), o);
    ASSERT_EQ(f.status, outcome::ok) << f.label;
    ASSERT_EQ(g.status, outcome::ok) << g.label;
    EXPECT_EQ(f.impacts_per_period, K * g.impacts_per_period);
    std::vector<std::complex<double>> want;
    for (int k = 0; k < K; ++k) want.insert(want.end(), g.multipliers.begin(), g.multipliers.end());
    expect_same_multiset(f.multipliers, want, 1e-7);
}

// Two balls dropped together from height 1 onto their floors (gravity 1, restitution r), 4
// states (a fixed size): both bounce at the closed-form instants t_1 = sqrt 2, t_(k+1) = t_k +
// 2 r^k sqrt 2, arriving at r^(k-1) sqrt 2, each pair of impacts at one instant.
TEST(AnyDimension, TwoBallsDroppedTogetherBounceTogether)
{
    const model m = model::with_defaults(compile_model_text(R"(
name = "two_balls"
state = ["x0", "v0", "x1", "v1"]
[parameters]
r = { default = 0.8 }
[derivatives]
x0 = "v0"
v0 = "-1"
x1 = "v1"
v1 = "-1"
[[surfaces]]
name = "floor0"
gap = "x0"
reset = { v0 = "-r*v0" }
[[surfaces]]
name = "floor1"
gap = "x1"
reset = { v1 = "-r*v1" }
[[sections]]
name = "apex"
when = "v0"
direction = "down"
)", "two_balls.toml"));
    protocol_options o = window(6);
    const Eigen::Vector4d x0(1.0, 0.0, 1.0, 0.0);
    const simulation s = simulate(m, x0, o);
    ASSERT_EQ(s.status, outcome::ok);
    ASSERT_GE(s.impacts.size(), 12U);
    const double r = 0.8, root2 = std::sqrt(2.0);
    double t = root2, speed = root2;
    for (std::size_t k = 0; k + 1 < s.impacts.size(); k += 2) {
        for (std::size_t j = 0; j < 2; ++j) {
            EXPECT_EQ(s.impacts.surface[k + j], static_cast<int>(j)) << k;
            EXPECT_NEAR(s.impacts.pre.t(k + j), t, 1e-9) << k;
            EXPECT_NEAR(s.impacts.pre.x(k + j)[2 * j + 1], -speed, 1e-9) << k;
            EXPECT_NEAR(s.impacts.post.x(k + j)[2 * j + 1], r * speed, 1e-9) << k;
        }
        t += 2.0 * r * speed;
        speed *= r;
    }
}

// 22 copies: 66 states (a tangent state of 66 + 66^2 numbers). Only copy 0 has its stops: with
// all 44 surfaces the model's own compilation takes minutes (the generated derivatives).
TEST(AnyDimension, SixtySixStatesAreTwentyTwoCopies)
{
    constexpr int K = 22;
    const model m = with_amplitudes(copies(K, 1), K);
    ASSERT_EQ(m.dim(), 66);
    const simulation all = simulate(m, start(K), window(12));
    ASSERT_EQ(all.status, outcome::ok);
    ASSERT_GT(all.impacts.size(), 0U);
    for (int k = 0; k < K; ++k) {
        const simulation one = simulate(k == 0 ? single(k) : free_single(k), start_of(k), window(12));
        ASSERT_EQ(one.status, outcome::ok);
        expect_copy_matches(all, one, k);
    }
    // The period: copy 0's (the free copies follow the forcing, one section point per period).
    protocol_options po;
    po.flow = test::flow_tolerances(tol, 1e6);
    const period_label one = run_and_classify(single(0), start_of(0), po, default_period_tolerance).label;
    ASSERT_GT(one.period, 0) << one.label;
    const period_label p = run_and_classify(m, start(K), po, default_period_tolerance).label;
    EXPECT_EQ(p.period, one.period) << p.label;
    EXPECT_EQ(p.impacts_per_period, one.impacts_per_period);
}

// A 3-state model on the fixed-size instance and on the dynamic one: the same arithmetic (the
// model's own fused step, the same event location), so the same numbers up to how Eigen
// vectorises fixed and dynamic sizes.
TEST(AnyDimension, DynamicStatesComputeWhatFixedOnesDo)
{
    const model m = single(0);
    const table_model<3> fixed(m.table(), m.context());
    const table_model<Eigen::Dynamic> dynamic(m.table(), m.context());
    const protocol_options o = window(20);
    const simulation a = detail::run_simulate(fixed, start_of(0), o);
    const simulation b = detail::run_simulate(dynamic, start_of(0), o);
    ASSERT_EQ(a.status, outcome::ok);
    ASSERT_EQ(b.status, outcome::ok);
    ASSERT_EQ(a.impacts.size(), b.impacts.size());
    ASSERT_EQ(a.points.size(), b.points.size());
    EXPECT_EQ(a.stats.steps, b.stats.steps);
    for (std::size_t i = 0; i < a.impacts.size(); ++i) {
        EXPECT_NEAR(a.impacts.pre.t(i), b.impacts.pre.t(i), 1e-12 * a.impacts.pre.t(i));
        EXPECT_LE((a.impacts.post.x(i) - b.impacts.post.x(i)).cwiseAbs().maxCoeff(), 1e-12);
    }
    floquet_options fo;
    const floquet_result fa = detail::run_floquet(fixed, start_of(0), fo, m.info());
    const floquet_result fb = detail::run_floquet(dynamic, start_of(0), fo, m.info());
    ASSERT_EQ(fa.status, outcome::ok);
    ASSERT_EQ(fb.status, outcome::ok);
    expect_same_multiset(fb.multipliers, fa.multipliers, 1e-11);
    lyapunov_options lo;
    lo.impacts = 100;
    const lyapunov_result la = detail::run_lyapunov(fixed, start_of(0), lo);
    const lyapunov_result lb = detail::run_lyapunov(dynamic, start_of(0), lo);
    ASSERT_EQ(la.status, outcome::ok);
    ASSERT_EQ(lb.status, outcome::ok);
    EXPECT_LE((la.exponents - lb.exponents).cwiseAbs().maxCoeff(), 1e-11);
}

TEST(AnyDimension, AnAbsurdDimensionIsRefused)
{
    const int n = max_model_dimension + 1;
    std::ostringstream text, derivatives;
    text << "name = \"huge\"\nstate = [";
    for (int j = 0; j < n; ++j) {
        text << (j > 0 ? ", " : "") << "\"x" << j << "\"";
        derivatives << "x" << j << " = \"0\"\n";
    }
    text << "]\n[parameters]\n[derivatives]\n" << derivatives.str();
    try {
        (void)compile_model_text(text.str(), "huge.toml");
        ADD_FAILURE() << "no error";
    } catch (const input_error& e) {
        EXPECT_EQ(std::string(e.what()), "model file huge.toml has 1001 state variables; vimpact runs models with 1 to "
                                         "1000 (a tangent run carries N + N^2 numbers per state)");
    }
    EXPECT_THROW(check_engine_dimension(0, "model"), input_error);
    EXPECT_NO_THROW(check_engine_dimension(max_model_dimension, "model"));
}
