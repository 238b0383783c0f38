// Tests of the models (wake_impact.hpp, forced_impact_oscillator.hpp): derivatives against
// finite differences of the vector field, the vector field against the equations of SPEC §1,
// the saltation matrix of SPEC §4 (Eq. 12) against its general definition, and parameter
// validation.
#include <gtest/gtest.h>

#include "test_support.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include <Eigen/LU>

#include "vimpact/core/input_error.hpp"
#include "vimpact/hybrid/flow.hpp"
#include "vimpact/model/forced_impact_oscillator.hpp"
#include "vimpact/model/wake_impact.hpp"

namespace {

using vimpact::mat;
using vimpact::vec;

// Central difference of F along direction e with step h, Richardson-extrapolated
// ((4 D(h/2) - D(h)) / 3): error O(h^4).
template <int N, class F>
vec<N> richardson_directional(F&& f, const vec<N>& x, const vec<N>& e, double h)
{
    auto central = [&](double s) { return vec<N>((f(vec<N>(x + s * e)) - f(vec<N>(x - s * e))) / (2.0 * s)); };
    return vec<N>((4.0 * central(h / 2.0) - central(h)) / 3.0);
}

template <int N, class F>
mat<N> fd_jacobian(F&& f, const vec<N>& x, double h = 1e-3)
{
    mat<N> J;
    for (int j = 0; j < N; ++j) J.col(j) = richardson_directional<N>(f, x, vec<N>::Unit(j), h);
    return J;
}

// Mixed second difference of F in directions u, v (independent of the Jacobian):
// [F(x+hu+hv) - F(x+hu-hv) - F(x-hu+hv) + F(x-hu-hv)] / (4 h^2), Richardson-extrapolated.
template <int N, class F>
vec<N> fd_second(F&& f, const vec<N>& x, const vec<N>& u, const vec<N>& v, double h = 1e-3)
{
    auto mixed = [&](double s) {
        return vec<N>((f(vec<N>(x + s * u + s * v)) - f(vec<N>(x + s * u - s * v)) -
                       f(vec<N>(x - s * u + s * v)) + f(vec<N>(x - s * u - s * v))) /
                      (4.0 * s * s));
    };
    return vec<N>((4.0 * mixed(h / 2.0) - mixed(h)) / 3.0);
}

using vimpact::test::random_vec;

// Max-norm by a plain loop (Eigen's vectorised cwiseAbs().maxCoeff() on 4x4 matrices trips a
// false -Wmaybe-uninitialized in GCC 12's AVX-512 headers).
template <class D>
double max_abs(const Eigen::MatrixBase<D>& m)
{
    const typename D::PlainObject e = m;
    double r = 0.0;
    for (Eigen::Index i = 0; i < e.size(); ++i) r = std::max(r, std::abs(e(i)));
    return r;
}

std::string message_of(auto&& f)
{
    try {
        f();
    } catch (const vimpact::input_error& e) {
        return e.what();
    } catch (...) {
        return "<other exception>";
    }
    return "<no exception>";
}

vimpact::wake_impact paper_model(double Ur)
{
    vimpact::wake_impact_parameters p;
    p.Ur = Ur;
    return vimpact::wake_impact(p);
}

}  // namespace

// ---- wake_impact: the vector field against SPEC §1 ------------------------------------------

// rhs written out from SPEC §1 in the test (delta = 1/(St Ur), alpha = 2 xi delta + gamma/mu,
// M = CL0 / (16 pi^2 St^2 mu); a = -delta^2 y - alpha v + M x; w' = -x - eps (x^2-1) w + A a).
TEST(WakeImpactModel, VectorFieldMatchesSpecEquations)
{
    vimpact::wake_impact_parameters p;
    p.Ur = 17.3;
    p.A = 11.0;
    p.eps = 0.27;
    p.CL0 = 0.31;
    const vimpact::wake_impact m(p);
    const double pi = std::numbers::pi;
    const double d = 1.0 / (p.St * p.Ur);
    const double alpha = 2.0 * p.xi * d + p.gamma / p.mu;
    const double M = p.CL0 / (16.0 * pi * pi * p.St * p.St * p.mu);
    EXPECT_NEAR(m.delta(), d, 1e-15);
    EXPECT_NEAR(m.alpha(), alpha, 1e-15);
    EXPECT_NEAR(m.coupling_M(), M, 1e-15);
    std::mt19937 gen(7);
    for (int k = 0; k < 20; ++k) {
        const vec<4> X = random_vec<4>(gen, -2.0, 2.0);
        const double y = X[0], v = X[1], x = X[2], w = X[3];
        const double a = -d * d * y - alpha * v + M * x;
        const vec<4> F(v, a, w, -x - p.eps * (x * x - 1.0) * w + p.A * a);
        EXPECT_LE(max_abs(m.rhs(X) - F), 1e-14 * (1.0 + max_abs(F)));
        EXPECT_NEAR(m.free_acceleration(X), a, 1e-15);
    }
}

// Default parameters are the paper's (Table 2) and the paper preset's coupling is
// M = 0.05 / mu, i.e. CL0 = 0.05 * 16 pi^2 * 0.2^2 = 0.3158273408 (SPEC §1).
TEST(WakeImpactModel, PaperPresetIsDefaultWithMEqualTo005OverMu)
{
    const vimpact::wake_impact_parameters def;
    const auto paper = vimpact::wake_impact_preset("paper");
    EXPECT_EQ(paper.Ur, def.Ur);
    EXPECT_EQ(paper.sigma, def.sigma);
    EXPECT_EQ(paper.r, def.r);
    EXPECT_EQ(paper.A, def.A);
    EXPECT_EQ(paper.eps, def.eps);
    EXPECT_EQ(paper.St, def.St);
    EXPECT_EQ(paper.xi, def.xi);
    EXPECT_EQ(paper.gamma, def.gamma);
    EXPECT_EQ(paper.mu, def.mu);
    EXPECT_EQ(paper.CL0, def.CL0);
    // Table 2 of the paper.
    EXPECT_EQ(def.St, 0.2);
    EXPECT_EQ(def.xi, 0.0052);
    EXPECT_EQ(def.gamma, 0.8);
    EXPECT_EQ(def.mu, 1.19381);
    EXPECT_EQ(def.eps, 0.3);
    EXPECT_EQ(def.A, 12.0);
    EXPECT_EQ(def.r, 0.8);
    EXPECT_EQ(def.sigma, -0.150298);

    const vimpact::wake_impact m;
    EXPECT_NEAR(m.coupling_M(), 0.05 / 1.19381, 1e-15);
    EXPECT_NEAR(def.CL0, 0.3158273408, 1e-10);
}

TEST(WakeImpactModel, FacchinettiPresetHasCL0Of03)
{
    const auto f = vimpact::wake_impact_preset("facchinetti");
    const vimpact::wake_impact_parameters def;
    EXPECT_EQ(f.CL0, 0.3);
    EXPECT_EQ(f.A, def.A);
    EXPECT_EQ(f.eps, def.eps);
    EXPECT_EQ(f.mu, def.mu);
    EXPECT_EQ(f.St, def.St);
    const vimpact::wake_impact m(f);
    EXPECT_NEAR(m.coupling_M(), 0.3 / (16.0 * std::numbers::pi * std::numbers::pi * 0.04 * 1.19381), 1e-15);
}

TEST(WakeImpactModel, UnknownPresetThrowsNamingValidPresets)
{
    const std::string msg = message_of([] { (void)vimpact::wake_impact_preset("nope"); });
    EXPECT_NE(msg.find("nope"), std::string::npos) << msg;
    EXPECT_NE(msg.find("paper"), std::string::npos) << msg;
    EXPECT_NE(msg.find("facchinetti"), std::string::npos) << msg;
}

// ---- wake_impact: derivatives ---------------------------------------------------------------

// The Jacobian equals the finite-difference Jacobian of rhs (Richardson: the field is a cubic
// polynomial, so the extrapolated central difference is exact up to round-off), at random
// states and several Ur; its trace is the divergence, and both equal SPEC's
// -alpha - eps (x^2 - 1).
TEST(WakeImpactModel, JacobianMatchesFiniteDifferences)
{
    std::mt19937 gen(42);
    for (double Ur : {12.0, 16.0, 25.0}) {
        const auto m = paper_model(Ur);
        auto f = [&](const vec<4>& x) { return m.rhs(x); };
        for (int k = 0; k < 10; ++k) {
            const vec<4> X = random_vec<4>(gen, -2.0, 2.0);
            const mat<4> J = m.jacobian(X);
            const mat<4> Jfd = fd_jacobian<4>(f, X);
            EXPECT_LE(max_abs(J - Jfd), 1e-9 * (1.0 + max_abs(J))) << "Ur " << Ur << " X " << X.transpose();
            EXPECT_NEAR(m.divergence(X), J.trace(), 1e-14);
            EXPECT_NEAR(m.divergence(X), -m.alpha() - m.params().eps * (X[2] * X[2] - 1.0), 1e-14);
            // free_acceleration_gradient is the gradient of a(X).
            auto a = [&](const vec<4>& x) { return vec<4>::Constant(m.free_acceleration(x)); };
            for (int j = 0; j < 4; ++j)
                EXPECT_NEAR(m.free_acceleration_gradient(X)[j],
                            richardson_directional<4>(a, X, vec<4>::Unit(j), 1e-3)[0], 1e-10);
        }
    }
}

// D2F(X)[u, v] equals the mixed second difference of rhs (independent of the Jacobian), is
// symmetric in (u, v), and equals the directional derivative of the Jacobian: D(J u)[v].
TEST(WakeImpactModel, SecondDerivativeMatchesFiniteDifferences)
{
    std::mt19937 gen(3);
    const auto m = paper_model(19.0);
    auto f = [&](const vec<4>& x) { return m.rhs(x); };
    for (int k = 0; k < 10; ++k) {
        const vec<4> X = random_vec<4>(gen, -2.0, 2.0);
        const vec<4> u = random_vec<4>(gen, -1.0, 1.0);
        const vec<4> v = random_vec<4>(gen, -1.0, 1.0);
        const vec<4> D2 = m.second_derivative(X, u, v);
        EXPECT_LE(max_abs(D2 - fd_second<4>(f, X, u, v)), 1e-7 * (1.0 + max_abs(D2)));
        EXPECT_LE(max_abs(D2 - m.second_derivative(X, v, u)), 1e-15 * (1.0 + max_abs(D2)));
        auto Ju = [&](const vec<4>& x) { return vec<4>(m.jacobian(x) * u); };
        EXPECT_LE(max_abs(D2 - richardson_directional<4>(Ju, X, v, 1e-3)), 1e-9 * (1.0 + max_abs(D2)));
    }
}

// ---- wake_impact: reset and saltation -------------------------------------------------------

// The reset R(X) = (sigma, -r v, x, w) is linear in (v, x, w): its Jacobian equals the finite
// differences of reset, and the guard gradient is that of h = y - sigma.
TEST(WakeImpactModel, ResetJacobianMatchesFiniteDifferences)
{
    std::mt19937 gen(11);
    const auto m = paper_model(21.5);
    auto R = [&](const vec<4>& x) { return m.reset(x); };
    auto H = [&](const vec<4>& x) { return vec<4>::Constant(m.guard(x)); };
    for (int k = 0; k < 10; ++k) {
        vec<4> X = random_vec<4>(gen, -2.0, 2.0);
        X[0] = m.barrier();
        const mat<4> Rfd = fd_jacobian<4>(R, X);
        EXPECT_LE(max_abs(m.reset_jacobian(X) - Rfd), 1e-12);
        const vec<4> post = m.reset(X);
        EXPECT_EQ(post[0], m.barrier());
        EXPECT_EQ(post[1], -m.restitution() * X[1]);
        EXPECT_EQ(post[2], X[2]);
        EXPECT_EQ(post[3], X[3]);
        for (int j = 0; j < 4; ++j)
            EXPECT_NEAR(m.guard_gradient(X)[j], richardson_directional<4>(H, X, vec<4>::Unit(j), 1e-3)[0], 1e-12);
    }
}

// Saltation matrix. The general first-order form S = R' + (F+ - R' F) gradH^T / (gradH . F)
// built from the model's rhs, reset_jacobian and guard_gradient equals the paper's explicit
// Eq. 12 (SPEC §4) at pre-impact states, maps F to F+ (S F = F+), and has det S = r^2.
TEST(WakeImpactModel, SaltationFromModelMatchesEquation12)
{
    std::mt19937 gen(5);
    for (double Ur : {14.9, 16.0, 25.0}) {
        const auto m = paper_model(Ur);
        const double r = m.restitution(), A = m.params().A, d2 = m.delta() * m.delta();
        for (int k = 0; k < 8; ++k) {
            vec<4> X = random_vec<4>(gen, -2.0, 2.0);
            X[0] = m.barrier();
            X[1] = -std::abs(X[1]) - 0.05;  // v < 0: arriving at the barrier
            const vec<4> F = m.rhs(X), Fp = m.rhs(m.reset(X));
            const mat<4> Rp = m.reset_jacobian(X);
            const vec<4> gH = m.guard_gradient(X);
            const mat<4> S = Rp + (Fp - Rp * F) * gH.transpose() / gH.dot(F);
            mat<4> S12 = mat<4>::Zero();
            const double y = X[0], v = X[1], x = X[2];
            S12(0, 0) = -r;
            S12(1, 0) = (1.0 + r) * (m.coupling_M() * x - d2 * y) / v;
            S12(1, 1) = -r;
            S12(2, 2) = 1.0;
            S12(3, 0) = A * m.alpha() * (1.0 + r);
            S12(3, 3) = 1.0;
            EXPECT_LE(max_abs(S - S12), 1e-12 * (1.0 + max_abs(S12))) << "Ur " << Ur;
            EXPECT_LE(max_abs(S * F - Fp), 1e-12 * (1.0 + max_abs(Fp)));
            EXPECT_NEAR(S.determinant(), r * r, 1e-12);
        }
    }
}

// ---- wake_impact: parameter validation ------------------------------------------------------

// Each invalid value throws input_error whose message names the parameter and its range.
TEST(WakeImpactModel, InvalidParametersThrowNamingTheRange)
{
    const vimpact::wake_impact base;
    struct bad {
        const char* name;
        double value;
        const char* range;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    for (const bad& b : {bad{"r", 1.5, "[0, 1]"}, bad{"r", -0.1, "[0, 1]"}, bad{"mu", 0.0, "> 0"},
                         bad{"St", -1.0, "> 0"}, bad{"Ur", nan, "> 0"}, bad{"Ur", inf, "> 0"},
                         bad{"Ur", -inf, "> 0"}, bad{"eps", -0.1, ">= 0"}, bad{"sigma", nan, "finite"}}) {
        const std::string msg = message_of([&] { (void)base.with(b.name, b.value); });
        EXPECT_NE(msg.find(std::string("parameter ") + b.name + " "), std::string::npos)
            << b.name << " = " << b.value << ": " << msg;
        EXPECT_NE(msg.find(b.range), std::string::npos) << b.name << " = " << b.value << ": " << msg;
        // The constructor validates too.
        vimpact::wake_impact_parameters p;
        p.*(vimpact::find_parameter(vimpact::wake_impact_parameter_table(), b.name)->member) = b.value;
        EXPECT_THROW(vimpact::wake_impact{p}, vimpact::input_error) << b.name;
    }
    // Valid edge values are accepted: r = 0 and r = 1 (closed interval), eps = 0.
    EXPECT_NO_THROW((void)base.with("r", 0.0));
    EXPECT_NO_THROW((void)base.with("r", 1.0));
    EXPECT_NO_THROW((void)base.with("eps", 0.0));
    EXPECT_EQ(base.with("Ur", 20.0).delta(), 1.0 / (0.2 * 20.0));
}

// An unknown name throws, naming every valid parameter.
TEST(WakeImpactModel, UnknownParameterNameListsValidOnes)
{
    const vimpact::wake_impact base;
    const std::string msg = message_of([&] { (void)base.with("nope", 1.0); });
    EXPECT_NE(msg.find("'nope'"), std::string::npos) << msg;
    const auto valid_pos = msg.find("valid:");
    ASSERT_NE(valid_pos, std::string::npos) << msg;
    const std::string list = msg.substr(valid_pos);
    for (const char* name : {"Ur", "sigma", "r", "A", "eps", "St", "xi", "gamma", "mu", "CL0"}) {
        const std::string token = std::string(name);
        const bool found = list.find(" " + token + ",") != std::string::npos ||
                           list.find(" " + token + ")") != std::string::npos;
        EXPECT_TRUE(found) << name << " missing from: " << msg;
    }
}

// ---- forced_impact_oscillator --------------------------------------------------------------

TEST(ForcedImpactModel, DerivativesMatchFiniteDifferences)
{
    std::mt19937 gen(99);
    vimpact::forced_impact_parameters p;
    p.zeta = 0.07;
    p.F = 1.3;
    p.omega = 0.9;
    const vimpact::forced_impact_oscillator m(p);
    auto f = [&](const vec<3>& x) { return m.rhs(x); };
    for (int k = 0; k < 10; ++k) {
        const vec<3> X = random_vec<3>(gen, -3.0, 3.0);
        const mat<3> J = m.jacobian(X);
        EXPECT_LE(max_abs(J - fd_jacobian<3>(f, X)), 1e-9 * (1.0 + max_abs(J)));
        EXPECT_NEAR(m.divergence(X), J.trace(), 1e-15);
        const vec<3> u = random_vec<3>(gen, -1.0, 1.0), v = random_vec<3>(gen, -1.0, 1.0);
        const vec<3> D2 = m.second_derivative(X, u, v);
        EXPECT_LE(max_abs(D2 - fd_second<3>(f, X, u, v)), 1e-7 * (1.0 + max_abs(D2)));
        auto a = [&](const vec<3>& x) { return vec<3>::Constant(m.free_acceleration(x)); };
        for (int j = 0; j < 3; ++j)
            EXPECT_NEAR(m.free_acceleration_gradient(X)[j], richardson_directional<3>(a, X, vec<3>::Unit(j), 1e-3)[0], 1e-9);
        auto R = [&](const vec<3>& x) { return m.reset(x); };
        EXPECT_LE(max_abs(m.reset_jacobian(X) - fd_jacobian<3>(R, X)), 1e-12);
        // The rhs is the forced oscillator of the header: y'' = -y - 2 zeta y' + F cos(theta).
        EXPECT_NEAR(m.rhs(X)[1], -X[0] - 2.0 * p.zeta * X[1] + p.F * std::cos(X[2]), 1e-14);
        EXPECT_EQ(m.rhs(X)[2], p.omega);
    }
}

TEST(ForcedImpactModel, InvalidParametersThrow)
{
    auto make = [](auto set) {
        vimpact::forced_impact_parameters p;
        set(p);
        return message_of([&] { vimpact::forced_impact_oscillator m(p); (void)m; });
    };
    const std::string z = make([](auto& p) { p.zeta = 1.0; });  // [0, 1): 1 excluded
    EXPECT_NE(z.find("parameter zeta"), std::string::npos) << z;
    EXPECT_NE(z.find("[0, 1)"), std::string::npos) << z;
    const std::string w = make([](auto& p) { p.omega = 0.0; });
    EXPECT_NE(w.find("parameter omega"), std::string::npos) << w;
    const std::string r = make([](auto& p) { p.r = 1.0000001; });
    EXPECT_NE(r.find("parameter r"), std::string::npos) << r;
    EXPECT_EQ(make([](auto& p) { p.zeta = 0.0; p.r = 1.0; }), "<no exception>");
}

// ---- hybrid_flow::start admissibility -------------------------------------------------------

// The admissible region is y >= sigma; y = sigma is admissible only moving away (v > 0) or at
// rest with the free acceleration pointing into the barrier (then the flow starts sticking).
TEST(HybridFlowStart, InadmissibleInitialStateThrows)
{
    const vimpact::wake_impact m;  // sigma = -0.150298
    vimpact::flow_options o;
    vimpact::hybrid_flow<vimpact::wake_impact> flow(m, o);
    const std::string msg = message_of([&] { flow.start(0.0, vec<4>(-0.2, 0.0, 0.0, 0.1)); });
    EXPECT_NE(msg.find("barrier"), std::string::npos) << msg;
    EXPECT_NE(msg.find("-0.2"), std::string::npos) << msg;
    EXPECT_THROW(flow.start(0.0, vec<4>(m.barrier(), -0.1, 0.0, 0.0)), vimpact::input_error);
    EXPECT_THROW(flow.start(0.0, vec<4>(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0, 0.0)),
                 vimpact::input_error);
    EXPECT_NO_THROW(flow.start(0.0, vec<4>(m.barrier(), 0.1, 0.0, 0.0)));
    EXPECT_EQ(flow.mode(), vimpact::flow_mode::free);
    EXPECT_NO_THROW(flow.start(0.0, vec<4>(0.0, 0.0, 0.0, 0.1)));
    // At rest on the barrier with a = -delta^2 sigma + M x <= 0 (x negative enough): sticking.
    const double x_stick = (m.delta() * m.delta() * m.barrier()) / m.coupling_M() - 0.5;
    flow.start(0.0, vec<4>(m.barrier(), 0.0, x_stick, 0.0));
    EXPECT_EQ(flow.mode(), vimpact::flow_mode::sticking);
    // Barrier-free flows accept any finite state.
    vimpact::flow_options free_opt;
    free_opt.barrier = false;
    vimpact::hybrid_flow<vimpact::wake_impact> free_flow(m, free_opt);
    EXPECT_NO_THROW(free_flow.start(0.0, vec<4>(-0.2, 0.0, 0.0, 0.1)));
}
