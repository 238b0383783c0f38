// Tests of the impact jumps of the tangent dynamics (stability/discontinuity_map.hpp):
// the saltation matrix from the general formula (Eq. 8) against the paper's closed form
// (Eq. 12), the second-order mapping in general form against the explicit form for the
// paper's model (SPEC §4), and both against the true discontinuity map computed from
// accurately integrated perturbed trajectories: error O(h^2) for saltation, O(h^3) for the
// second-order map (measured slopes are printed; docs/stability.md quotes them).
#include <gtest/gtest.h>

#include "test_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <Eigen/LU>

#include "vimpact/integrate/runge_kutta.hpp"
#include "vimpact/model/forced_impact_oscillator.hpp"
#include "vimpact/model/wake_impact.hpp"
#include "vimpact/stability/discontinuity_map.hpp"
#include "vimpact/stability/floquet.hpp"

namespace {

using vimpact::mat;
using vimpact::vec;

template <class D>
double max_abs(const Eigen::MatrixBase<D>& m)
{
    const typename D::PlainObject e = m;
    double r = 0.0;
    for (Eigen::Index i = 0; i < e.size(); ++i) r = std::max(r, std::abs(e(i)));
    return r;
}

vimpact::wake_impact paper(double Ur)
{
    vimpact::wake_impact_parameters p;
    p.Ur = Ur;
    return vimpact::wake_impact(p);
}

using vimpact::test::random_vec;

// A pre-impact state: on the barrier, moving into it with |v| >= 0.1.
template <class Model>
vec<Model::dim> random_impact_state(const Model& m, std::mt19937& gen)
{
    vec<Model::dim> x = random_vec<Model::dim>(gen, -1.0, 1.0);
    x[0] = m.barrier();
    x[1] = -0.1 - std::abs(x[1]);
    return x;
}

// ---- the saltation matrix ----------------------------------------------------------------

// Eq. 12 of the paper, written out: the library's general Eq. 8 must equal it.
TEST(StabilityJump, SaltationMatchesEquation12AndMapsFToFPlus)
{
    std::mt19937 gen(11);
    for (double Ur : {14.0, 16.0, 19.0, 25.0}) {
        const auto m = paper(Ur);
        const double r = m.restitution(), A = m.params().A, d2 = m.delta() * m.delta();
        for (int k = 0; k < 10; ++k) {
            const vec<4> x = random_impact_state(m, gen);
            const mat<4> S = vimpact::saltation_matrix(m, x);
            mat<4> S12 = mat<4>::Zero();
            S12(0, 0) = -r;
            S12(1, 0) = (1.0 + r) * (m.coupling_M() * x[2] - d2 * x[0]) / x[1];
            S12(1, 1) = -r;
            S12(2, 2) = 1.0;
            S12(3, 0) = A * m.alpha() * (1.0 + r);
            S12(3, 3) = 1.0;
            EXPECT_LE(max_abs(S - S12), 1e-13 * (1.0 + max_abs(S12))) << "Ur " << Ur;
            const vec<4> Fp = m.rhs(m.reset(x));
            EXPECT_LE(max_abs(S * m.rhs(x) - Fp), 1e-13 * (1.0 + max_abs(Fp)));
            EXPECT_NEAR(S.determinant(), r * r, 1e-13);
        }
    }
}

TEST(StabilityJump, ForcedOscillatorSaltationMapsFToFPlus)
{
    std::mt19937 gen(12);
    const vimpact::forced_impact_oscillator m{};
    for (int k = 0; k < 10; ++k) {
        const vec<3> x = random_impact_state(m, gen);
        const mat<3> S = vimpact::saltation_matrix(m, x);
        EXPECT_LE(max_abs(S * m.rhs(x) - m.rhs(m.reset(x))), 1e-13);
        EXPECT_NEAR(S.determinant(), m.restitution() * m.restitution(), 1e-13);
    }
}

// ---- the second-order mapping: general form vs the explicit form of SPEC §4 ----------------

// SPEC §4's explicit map for the paper's model (b = M x - delta^2 sigma, v < 0 the impact
// velocity), independent of the library's general form.
vec<4> explicit_second_order(const vimpact::wake_impact& m, const vec<4>& x, const vec<4>& y)
{
    const double r = m.restitution(), A = m.params().A, eps = m.params().eps;
    const double d2 = m.delta() * m.delta(), M = m.coupling_M(), al = m.alpha();
    const double v = x[1], xx = x[2], w = x[3];
    const double b = M * xx - d2 * m.barrier();
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
        const auto m = paper(Ur);
        for (int k = 0; k < 20; ++k) {
            const vec<4> x = random_impact_state(m, gen);
            for (double size : {1e-4, 1e-2, 0.3}) {
                const vec<4> y = size * random_vec<4>(gen, -1.0, 1.0);
                const vec<4> general = vimpact::second_order_map(m, x, y).y_plus;
                const vec<4> expl = explicit_second_order(m, x, y);
                EXPECT_LE(max_abs(general - expl), 1e-14 * (1.0 + max_abs(expl)))
                    << "Ur " << Ur << " size " << size;
            }
        }
    }
}

// The flight-time quadratic has no real root exactly when (v + y2)^2 < 2 a- y1 (SPEC §4).
TEST(StabilityJump, MissDetectionMatchesTheDiscriminant)
{
    const auto m = paper(16.0);
    vec<4> x(m.barrier(), -0.05, 0.4, 0.2);
    const double a = m.rhs(x)[1];
    // Decelerating towards the barrier: a perturbed orbit high enough above turns back first.
    ASSERT_GT(a, 0.0);
    const double y1_crit = x[1] * x[1] / (2.0 * a);  // y1 above this misses
    EXPECT_TRUE(vimpact::second_order_map(m, x, vec<4>(1.01 * y1_crit, 0, 0, 0)).misses);
    EXPECT_FALSE(vimpact::second_order_map(m, x, vec<4>(0.99 * y1_crit, 0, 0, 0)).misses);
    EXPECT_FALSE(vimpact::second_order_map(m, x, vec<4>(-0.99 * y1_crit, 0, 0, 0)).misses);
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
// flows with the smooth field to the guard (flight time d by Newton, d < 0 if it is already
// past it), is reset, and flows back by -d; y+ is its offset from R(x).
template <class Model>
vec<Model::dim> true_jump(const Model& m, const vec<Model::dim>& x, const vec<Model::dim>& y)
{
    const vec<Model::dim> p = x + y;
    double d = -m.guard(p) / m.guard_gradient(p).dot(m.rhs(p));
    for (int it = 0; it < 30; ++it) {
        const vec<Model::dim> z = flow_for(m, p, d);
        const double step = -m.guard(z) / m.guard_gradient(z).dot(m.rhs(z));
        d += step;
        if (std::abs(step) <= 1e-17) break;
    }
    const vec<Model::dim> hit = flow_for(m, p, d);
    const vec<Model::dim> back = flow_for(m, vec<Model::dim>(m.reset(hit)), -d);
    return back - m.reset(x);
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
slopes measure_slopes(const Model& m, const vec<Model::dim>& x, const vec<Model::dim>& direction)
{
    constexpr int N = Model::dim;
    const mat<N> S = vimpact::saltation_matrix(m, x);
    // Deviations from 5 % down to 0.05 % of the impact speed: the asymptotic range for the
    // slow impacts too (at Ur = 16 the impact speed is 0.044).
    const double speed = std::abs(m.guard_gradient(x).dot(m.rhs(x)));
    std::vector<double> hs, e1, e2;
    for (double h = 0.05 * speed; h >= 0.99 * 5e-4 * speed; h /= std::sqrt(10.0)) {
        const vec<N> y = h * direction;
        const vec<N> truth = true_jump(m, x, y);
        hs.push_back(h);
        e1.push_back((truth - S * y).norm());
        e2.push_back((truth - vimpact::second_order_map(m, x, y).y_plus).norm());
    }
    return {fitted_slope(hs, e1), fitted_slope(hs, e2)};
}

template <class Model>
void check_orders(const Model& m, const std::vector<vec<Model::dim>>& states, std::mt19937& gen,
                  const char* what)
{
    double lo1 = 1e9, hi1 = -1e9, lo2 = 1e9, hi2 = -1e9;
    for (const auto& x : states) {
        for (int k = 0; k < 4; ++k) {
            const vec<Model::dim> e = random_vec<Model::dim>(gen, -1.0, 1.0).normalized();
            const slopes s = measure_slopes(m, x, e);
            EXPECT_NEAR(s.saltation, 2.0, 0.1) << what << " state " << x.transpose() << " dir " << e.transpose();
            EXPECT_NEAR(s.second_order, 3.0, 0.15) << what << " state " << x.transpose() << " dir " << e.transpose();
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
        const auto m = paper(Ur);
        const auto fl = vimpact::floquet_analysis(m, vec<4>(0, 0, 0, 0.1));
        ASSERT_EQ(fl.status, vimpact::floquet_status::ok);
        std::vector<vec<4>> states;
        for (const auto& e : fl.impacts) states.push_back(e.pre);
        states.push_back(random_impact_state(m, gen));
        check_orders(m, states, gen, Ur == 14.0 ? "wake_impact Ur = 14" : "wake_impact Ur = 16");
    }
}

// The forced oscillator's vector field depends on the phase nonlinearly (F cos theta), so
// second-order terms in all directions are exercised.
TEST(StabilityJump, ErrorOrdersAgainstTrueMapForcedOscillator)
{
    std::mt19937 gen(15);
    const vimpact::forced_impact_oscillator m{};
    std::vector<vec<3>> states;
    for (int k = 0; k < 3; ++k) states.push_back(random_impact_state(m, gen));
    check_orders(m, states, gen, "forced oscillator");
}

// The reset Jacobian alone (no saltation correction) is wrong at first order: its error
// is O(h), as large as the deviation itself, so these slopes do catch a missing term.
TEST(StabilityJump, ResetJacobianAloneHasFirstOrderError)
{
    std::mt19937 gen(16);
    const auto m = paper(16.0);
    const vec<4> x = random_impact_state(m, gen);
    const vec<4> e = vec<4>(1.0, 0.3, -0.2, 0.5).normalized();
    std::vector<double> hs, err;
    for (double h = 1e-2; h >= 0.99e-4; h /= std::sqrt(10.0)) {
        hs.push_back(h);
        err.push_back((true_jump(m, x, vec<4>(h * e)) - m.reset_jacobian(x) * (h * e)).norm());
    }
    EXPECT_NEAR(fitted_slope(hs, err), 1.0, 0.1);
}

}  // namespace
