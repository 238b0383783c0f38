// Tests of the impact jumps of the tangent dynamics (tangent/impact_jump.hpp): the saltation
// matrix from the general formula (Eq. 8) against the paper's closed form (Eq. 12), the
// second-order mapping in general form against the explicit form for the paper's model, and
// both against the true discontinuity map computed from accurately integrated perturbed
// trajectories: error O(h^2) for saltation, O(h^3) for the second-order map (measured slopes
// are printed; docs/stability.md quotes them).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <Eigen/LU>

#include "test_support.hpp"
#include "vimpact/analysis/floquet.hpp"
#include "vimpact/integrate/runge_kutta.hpp"
#include "vimpact/model/builtin/forced_impact_oscillator.hpp"
#include "vimpact/model/builtin/two_sided_impact_oscillator.hpp"
#include "vimpact/model/builtin/wake_impact.hpp"
#include "vimpact/model/native_model.hpp"
#include "vimpact/tangent/impact_jump.hpp"

namespace {

using vimpact::mat;
using vimpact::vec;
using vimpact::test::defaults;
using wake = vimpact::native_model<vimpact::wake_impact>;
using forced = vimpact::native_model<vimpact::forced_impact_oscillator>;
using two_sided = vimpact::native_model<vimpact::two_sided_impact_oscillator>;

template <class A>
double max_abs(const A& m)
{
    double r = 0.0;
    for (Eigen::Index i = 0; i < m.rows(); ++i)
        for (Eigen::Index j = 0; j < m.cols(); ++j) r = std::max(r, std::abs(m(i, j)));
    return r;
}

// The paper's model (paper preset) at Ur, and the parameter values the closed forms need.
struct paper_model {
    wake m;
    double sigma, r, A, eps;
};

paper_model paper(double Ur)
{
    const vimpact::model h = vimpact::test::paper(Ur);
    const auto& info = h.info();
    return {wake(h.parameters()), h.parameter(info.parameter_index("sigma")), h.parameter(info.parameter_index("r")),
            h.parameter(info.parameter_index("A")), h.parameter(info.parameter_index("eps"))};
}

// A pre-impact state of the paper's barrier: on it, moving into it with |v| >= 0.1.
vec<4> random_impact_state(const paper_model& p, std::mt19937& gen)
{
    vec<4> x = vimpact::test::random_vec<4>(gen);
    x[0] = p.sigma;
    x[1] = -0.1 - std::abs(x[1]);
    return x;
}

// ---- the saltation matrix ----------------------------------------------------------------

// Eq. 12 of the paper, written out: the library's general Eq. 8 (with the gradients and
// Jacobians from the model) must equal it.
TEST(StabilityJump, SaltationMatchesEquation12AndMapsFToFPlus)
{
    std::mt19937 gen(11);
    for (double Ur : {14.0, 16.0, 19.0, 25.0}) {
        const auto p = paper(Ur);
        const auto& def = p.m.definition();
        const double r = p.r, A = p.A, d2 = def.delta() * def.delta();
        for (int k = 0; k < 10; ++k) {
            const vec<4> x = random_impact_state(p, gen);
            const mat<4> S = vimpact::saltation_matrix(p.m, 0, x);
            mat<4> S12 = mat<4>::Zero();
            S12(0, 0) = -r;
            S12(1, 0) = (1.0 + r) * (def.coupling_M() * x[2] - d2 * x[0]) / x[1];
            S12(1, 1) = -r;
            S12(2, 2) = 1.0;
            S12(3, 0) = A * def.alpha() * (1.0 + r);
            S12(3, 3) = 1.0;
            EXPECT_LE(max_abs(S - S12), 1e-13 * (1.0 + max_abs(S12))) << "Ur " << Ur;
            const vec<4> Fp = p.m.rhs(p.m.reset(0, x));
            EXPECT_LE(max_abs(S * p.m.rhs(x) - Fp), 1e-13 * (1.0 + max_abs(Fp)));
            EXPECT_NEAR(S.determinant(), r * r, 1e-13);
        }
    }
}

// The forced oscillator's saltation matrix in closed form: at (sigma, v, theta) with
// a- = -sigma - 2 zeta v + F cos theta, a+ = -sigma + 2 zeta r v + F cos theta,
//   S = [[-r, 0, 0], [(a+ + r a-)/v, -r, 0], [0, 0, 1]]   (det r^2).
TEST(StabilityJump, ForcedOscillatorSaltationMatchesItsClosedForm)
{
    std::mt19937 gen(12);
    const auto p = defaults<vimpact::forced_impact_oscillator>();
    const forced m(p);
    const double zeta = p[0], F = p[2], sigma = p[3], r = p[4];
    for (int k = 0; k < 10; ++k) {
        vec<3> x = vimpact::test::random_vec<3>(gen, 3.0);
        x[0] = sigma;
        x[1] = -0.1 - std::abs(x[1]);
        const double am = -sigma - 2.0 * zeta * x[1] + F * std::cos(x[2]);
        const double ap = -sigma + 2.0 * zeta * r * x[1] + F * std::cos(x[2]);
        mat<3> expected;
        expected << -r, 0.0, 0.0, (ap + r * am) / x[1], -r, 0.0, 0.0, 0.0, 1.0;
        const mat<3> S = vimpact::saltation_matrix(m, 0, x);
        EXPECT_LE(max_abs(S - expected), 1e-14 * (1.0 + max_abs(expected)));
        EXPECT_LE(max_abs(S * m.rhs(x) - m.rhs(m.reset(0, x))), 1e-13);
        EXPECT_NEAR(S.determinant(), r * r, 1e-13);
    }
}

// Two stops with their own gaps d - x and x + d and the reset v -> -r v: the same closed form
// on both (the sign of the gap gradient cancels), a = -2 zeta v - x + a cos(phi) at x = +-d.
TEST(StabilityJump, TwoSidedSaltationMatchesItsClosedFormOnBothStops)
{
    std::mt19937 gen(17);
    const auto p = defaults<vimpact::two_sided_impact_oscillator>();
    const two_sided m(p);
    const double zeta = p[0], a = p[1], d = p[3], r = p[4];
    for (int surface : {0, 1}) {
        for (int k = 0; k < 10; ++k) {
            vec<3> x = vimpact::test::random_vec<3>(gen, 3.0);
            x[0] = surface == 0 ? d : -d;
            // Moving into the stop: v > 0 at the right one, v < 0 at the left.
            x[1] = (surface == 0 ? 1.0 : -1.0) * (0.1 + std::abs(x[1]));
            const double am = -2.0 * zeta * x[1] - x[0] + a * std::cos(x[2]);
            const double ap = 2.0 * zeta * r * x[1] - x[0] + a * std::cos(x[2]);
            mat<3> expected;
            expected << -r, 0.0, 0.0, (ap + r * am) / x[1], -r, 0.0, 0.0, 0.0, 1.0;
            const mat<3> S = vimpact::saltation_matrix(m, surface, x);
            EXPECT_LE(max_abs(S - expected), 1e-14 * (1.0 + max_abs(expected))) << "surface " << surface;
            EXPECT_NEAR(S.determinant(), r * r, 1e-13);
        }
    }
}

// ---- the second-order mapping: general form vs the explicit form for the paper's model ----

// The explicit map for the paper's model (b = M x - delta^2 sigma, v < 0 the impact
// velocity), written out independently of the library's general form.
vec<4> explicit_second_order(const paper_model& p, const vec<4>& x, const vec<4>& y)
{
    const auto& def = p.m.definition();
    const double r = p.r, A = p.A, eps = p.eps;
    const double d2 = def.delta() * def.delta(), M = def.coupling_M(), al = def.alpha();
    const double v = x[1], xx = x[2], w = x[3];
    const double b = M * xx - d2 * p.sigma;
    const double y1 = y[0], y2 = y[1], y3 = y[2], y4 = y[3];
    vec<4> out;
    out[0] = -r * y1 + (1 + r) * b * y1 * y1 / (2 * v * v);
    out[1] = -r * y2 + (1 + r) * (b * y1 / v + (b * (b - 2 * al * v) - M * v * w) * y1 * y1 / (2 * v * v * v) -
                                  b * y1 * y2 / (v * v) + M * y1 * y3 / v);
    out[2] = y3 + A * al * (1 + r) * y1 * y1 / (2 * v);
    out[3] = y4 + A * al * (1 + r) * y1 -
             A * (1 + r) * (al * b + al * eps * (xx * xx - 1) * v - d2 * v) * y1 * y1 / (2 * v * v);
    return out;
}

// Both are the second-order Taylor polynomial of the same map, so they agree to round-off
// for any deviation, small or not.
TEST(StabilityJump, GeneralSecondOrderMapEqualsExplicitWakeForm)
{
    std::mt19937 gen(13);
    for (double Ur : {14.0, 16.0, 25.0}) {
        const auto p = paper(Ur);
        for (int k = 0; k < 20; ++k) {
            const vec<4> x = random_impact_state(p, gen);
            for (double size : {1e-4, 1e-2, 0.3}) {
                const vec<4> y = size * vimpact::test::random_vec<4>(gen);
                const vec<4> general = vimpact::second_order_map(p.m, 0, x, y).y_plus;
                const vec<4> expl = explicit_second_order(p, x, y);
                EXPECT_LE(max_abs(general - expl), 1e-14 * (1.0 + max_abs(expl)))
                    << "Ur " << Ur << " size " << size;
            }
        }
    }
}

// The flight-time quadratic has no real root exactly when (v + y2)^2 < 2 a- y1.
TEST(StabilityJump, MissDetectionMatchesTheDiscriminant)
{
    const auto p = paper(16.0);
    const vec<4> x(p.sigma, -0.05, 0.4, 0.2);
    const double a = p.m.rhs(x)[1];
    // Decelerating towards the barrier: a perturbed orbit high enough above turns back first.
    ASSERT_GT(a, 0.0);
    const double y1_crit = x[1] * x[1] / (2.0 * a);  // y1 above this misses
    EXPECT_TRUE(vimpact::second_order_map(p.m, 0, x, vec<4>(1.01 * y1_crit, 0, 0, 0)).misses);
    EXPECT_FALSE(vimpact::second_order_map(p.m, 0, x, vec<4>(0.99 * y1_crit, 0, 0, 0)).misses);
    EXPECT_FALSE(vimpact::second_order_map(p.m, 0, x, vec<4>(-0.99 * y1_crit, 0, 0, 0)).misses);
}

// ---- against the true discontinuity map -------------------------------------------------

// The smooth flow for a short time s (either sign) by fixed DOP853 steps: for |s| <= 0.2 and
// 16 steps the truncation error is far below round-off.
template <class Model>
vec<Model::dim> flow_for(const Model& m, const vec<Model::dim>& x, double s)
{
    constexpr int N = Model::dim;
    vimpact::dop853<N> method;
    auto rhs = [&](const vec<N>& z) { return m.rhs(z); };
    vec<N> z = x, f = rhs(x), zn, fn;
    const int n = 16;
    for (int i = 0; i < n; ++i) {
        (void)method.attempt(rhs, z, f, s / n, 1e-14, 1e-14, zn, fn);
        z = zn;
        f = fn;
    }
    return z;
}

// y- -> y+ exactly (to round-off): the perturbed point x + y at the reference impact time
// flows with the smooth field to the surface (flight time d by Newton, d < 0 if it is already
// past it), is reset, and flows back by -d; y+ is its offset from R(x).
template <class Model>
vec<Model::dim> true_jump(const Model& m, int surface, const vec<Model::dim>& x, const vec<Model::dim>& y)
{
    using V = vec<Model::dim>;
    const V p = x + y;
    double d = -m.gap(surface, p) / m.gap_gradient(surface, p).dot(m.rhs(p));
    for (int it = 0; it < 30; ++it) {
        const V z = flow_for(m, p, d);
        const double step = -m.gap(surface, z) / m.gap_gradient(surface, z).dot(m.rhs(z));
        d += step;
        if (std::abs(step) <= 1e-17) break;
    }
    const V hit = flow_for(m, p, d);
    const V back = flow_for(m, V(m.reset(surface, hit)), -d);
    return back - m.reset(surface, x);
}

struct slopes {
    double saltation;
    double second_order;
};

// Least-squares slope of log(error) against log(h).
double fitted_slope(const std::vector<double>& h, const std::vector<double>& err)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double n = static_cast<double>(h.size());
    for (std::size_t i = 0; i < h.size(); ++i) {
        const double lx = std::log(h[i]), ly = std::log(err[i]);
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

template <class Model>
slopes measure_slopes(const Model& m, int surface, const vec<Model::dim>& x, const vec<Model::dim>& direction)
{
    constexpr int N = Model::dim;
    const mat<N> S = vimpact::saltation_matrix(m, surface, x);
    // Deviations from 5 % down to 0.05 % of the impact speed: the asymptotic range for the
    // slow impacts too (at Ur = 16 the impact speed is 0.044).
    const double speed = std::abs(m.gap_gradient(surface, x).dot(m.rhs(x)));
    std::vector<double> hs, e1, e2;
    for (double h = 0.05 * speed; h >= 0.99 * 5e-4 * speed; h /= std::sqrt(10.0)) {
        const vec<N> y = h * direction;
        const vec<N> truth = true_jump(m, surface, x, y);
        hs.push_back(h);
        e1.push_back((truth - S * y).norm());
        e2.push_back((truth - vimpact::second_order_map(m, surface, x, y).y_plus).norm());
    }
    return {fitted_slope(hs, e1), fitted_slope(hs, e2)};
}

template <class Model>
void check_orders(const Model& m, const std::vector<std::pair<int, vec<Model::dim>>>& states, std::mt19937& gen,
                  const char* what)
{
    constexpr int N = Model::dim;
    double lo1 = 1e9, hi1 = -1e9, lo2 = 1e9, hi2 = -1e9;
    for (const auto& [surface, x] : states) {
        for (int k = 0; k < 4; ++k) {
            const vec<N> e = vimpact::test::random_vec<N>(gen).normalized();
            const slopes s = measure_slopes(m, surface, x, e);
            EXPECT_NEAR(s.saltation, 2.0, 0.1) << what << " surface " << surface << " state " << x.transpose()
                                               << " dir " << e.transpose();
            EXPECT_NEAR(s.second_order, 3.0, 0.15) << what << " surface " << surface << " state " << x.transpose()
                                                   << " dir " << e.transpose();
            lo1 = std::min(lo1, s.saltation);
            hi1 = std::max(hi1, s.saltation);
            lo2 = std::min(lo2, s.second_order);
            hi2 = std::max(hi2, s.second_order);
        }
    }
    std::printf("[ measured ] %s, |y| = 5e-2..5e-4 |v|: saltation error slope %.3f..%.3f, "
                "second-order error slope %.3f..%.3f\n",
                what, lo1, hi1, lo2, hi2);
}

// Pre-impact states of the paper's model: the impacts of the P1 (Ur = 14) and P2 (Ur = 16)
// orbits and random transversal ones.
TEST(StabilityJump, ErrorOrdersAgainstTrueMapWakeModel)
{
    std::mt19937 gen(14);
    for (double Ur : {14.0, 16.0}) {
        const auto p = paper(Ur);
        const auto fl = vimpact::floquet(vimpact::test::paper(Ur), vimpact::test::paper_ic(), {});
        ASSERT_EQ(fl.status, vimpact::outcome::ok);
        ASSERT_GT(fl.impacts.size(), 0u);
        std::vector<std::pair<int, vec<4>>> states;
        for (std::size_t k = 0; k < fl.impacts.size(); ++k)
            states.emplace_back(fl.impacts.surface[k], vec<4>(fl.impacts.pre.x(k)));
        states.emplace_back(0, random_impact_state(p, gen));
        check_orders(p.m, states, gen, Ur == 14.0 ? "wake_impact Ur = 14" : "wake_impact Ur = 16");
    }
}

// The forced oscillator's vector field depends on the phase nonlinearly (F cos theta), so
// second-order terms in all directions are exercised.
TEST(StabilityJump, ErrorOrdersAgainstTrueMapForcedOscillator)
{
    std::mt19937 gen(15);
    const auto p = defaults<vimpact::forced_impact_oscillator>();
    const forced m(p);
    std::vector<std::pair<int, vec<3>>> states;
    for (int k = 0; k < 3; ++k) {
        vec<3> x = vimpact::test::random_vec<3>(gen);
        x[0] = p[3];
        x[1] = -0.1 - std::abs(x[1]);
        states.emplace_back(0, x);
    }
    check_orders(m, states, gen, "forced oscillator");
}

// Both stops of the two-sided oscillator (the left one's gap increases with x: the signs of
// the gap gradient and of the impact velocity differ from the paper's barrier).
TEST(StabilityJump, ErrorOrdersAgainstTrueMapOnBothStops)
{
    std::mt19937 gen(18);
    const auto p = defaults<vimpact::two_sided_impact_oscillator>();
    const two_sided m(p);
    const double d = p[3];
    std::vector<std::pair<int, vec<3>>> states;
    for (int k = 0; k < 2; ++k) {
        vec<3> x = vimpact::test::random_vec<3>(gen);
        x[0] = d;
        x[1] = 0.1 + std::abs(x[1]);
        states.emplace_back(0, x);
        x[0] = -d;
        x[1] = -x[1];
        states.emplace_back(1, x);
    }
    check_orders(m, states, gen, "two-sided oscillator");
}

// The reset Jacobian alone (no saltation correction) is wrong at first order: its error
// is O(h), as large as the deviation itself, so these slopes do catch a missing term.
TEST(StabilityJump, ResetJacobianAloneHasFirstOrderError)
{
    std::mt19937 gen(16);
    const auto p = paper(16.0);
    const vec<4> x = random_impact_state(p, gen);
    const vec<4> e = vec<4>(1.0, 0.3, -0.2, 0.5).normalized();
    std::vector<double> hs, err;
    for (double h = 1e-2; h >= 0.99e-4; h /= std::sqrt(10.0)) {
        hs.push_back(h);
        err.push_back((true_jump(p.m, 0, x, vec<4>(h * e)) - p.m.reset_jacobian(0, x) * (h * e)).norm());
    }
    EXPECT_NEAR(fitted_slope(hs, err), 1.0, 0.1);
}

}  // namespace
