// Tests of the Runge-Kutta pairs (runge_kutta.hpp), their interpolants (dense_output.hpp) and
// the step-size controller (adaptive_integrator.hpp) against analytic solutions.
//
// Reference problems with closed-form solutions:
//  * harmonic oscillator  y' = v, v' = -y            y = cos t, v = -sin t   (linear)
//  * a nonlinear limit-cycle system (polar form r' = r - r^3, phi' = 1):
//        x' = x - y - x (x^2 + y^2),  y' = x + y - y (x^2 + y^2)
//    with r(t) = 1 / sqrt(1 + (1/r0^2 - 1) e^{-2t}), phi(t) = phi0 + t.
//    Nonlinear, so it exercises all the order conditions, not only those of linear problems.
//  * a non-autonomous scalar equation written autonomously with the time as a state:
//        s' = 1, y' = y cos s                         y = exp(sin t)
//
// Each order is fitted over a range of h where the error follows its leading term (the
// pre-asymptotic range differs between problems and was chosen so) and stays far above
// round-off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include "vimpact/integrate/adaptive_integrator.hpp"
#include "vimpact/integrate/dense_output.hpp"
#include "vimpact/integrate/runge_kutta.hpp"
#include "vimpact/integrate/step_control.hpp"

namespace {

using vimpact::vec;
using V2 = vec<2>;

// ---- reference problems -------------------------------------------------------------------

struct harmonic {
    V2 operator()(const V2& x) const { return {x[1], -x[0]}; }
    static V2 exact(double t) { return {std::cos(t), -std::sin(t)}; }
    static V2 exact_rhs(double t) { return {-std::sin(t), -std::cos(t)}; }
};

struct limit_cycle {
    static constexpr double r0 = 0.5;
    V2 operator()(const V2& x) const
    {
        const double q = x[0] * x[0] + x[1] * x[1];
        return {x[0] - x[1] - x[0] * q, x[0] + x[1] - x[1] * q};
    }
    static double radius(double t)
    {
        return 1.0 / std::sqrt(1.0 + (1.0 / (r0 * r0) - 1.0) * std::exp(-2.0 * t));
    }
    static V2 exact(double t)
    {
        const double r = radius(t);
        return {r * std::cos(t), r * std::sin(t)};
    }
    // The derivative of the exact solution, written from the closed form (not from the ODE):
    // d/dt (r cos t, r sin t) = r' (cos t, sin t) + r (-sin t, cos t), r' = r - r^3.
    static V2 exact_rhs(double t)
    {
        const double r = radius(t);
        const double dr = r - r * r * r;
        return {dr * std::cos(t) - r * std::sin(t), dr * std::sin(t) + r * std::cos(t)};
    }
};

struct exp_sin {
    V2 operator()(const V2& x) const { return {1.0, x[1] * std::cos(x[0])}; }
    static V2 exact(double t) { return {t, std::exp(std::sin(t))}; }
    static V2 exact_rhs(double t) { return {1.0, std::cos(t) * std::exp(std::sin(t))}; }
};

// Least-squares slope of log(err) against log(h).
double fitted_slope(const std::vector<double>& h, const std::vector<double>& err)
{
    const std::size_t n = h.size();
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double lx = std::log(h[i]), ly = std::log(err[i]);
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
    }
    const double dn = static_cast<double>(n);
    return (dn * sxy - sx * sy) / (dn * sxx - sx * sx);
}

// The state at T after n fixed steps of size T/n taken with method.attempt() from the exact
// solution at 0.
template <template <int> class Method, class Problem, int N = 2>
vec<N> after_fixed_steps(int n, double T)
{
    Problem rhs;
    Method<N> m;
    vec<N> x = Problem::exact(0.0), f = rhs(x), xn, fn;
    const double h = T / n;
    for (int i = 0; i < n; ++i) {
        m.attempt(rhs, x, f, h, 1.0, 1.0, xn, fn);
        x = xn;
        f = fn;
    }
    return x;
}

// Global error at T after n fixed steps.
template <template <int> class Method, class Problem>
double fixed_step_global_error(int n, double T)
{
    return (after_fixed_steps<Method, Problem>(n, T) - Problem::exact(T)).cwiseAbs().maxCoeff();
}

template <template <int> class Method, class Problem>
double convergence_order(const std::vector<int>& steps, double T)
{
    std::vector<double> h, err;
    for (int n : steps) {
        h.push_back(T / n);
        err.push_back(fixed_step_global_error<Method, Problem>(n, T));
    }
    return fitted_slope(h, err);
}

}  // namespace

// ---- order of the fixed-step methods ------------------------------------------------------
// Global error of a p-th order method with constant step h is C h^p: the slope of
// log(error) against log(h) must be 5 for DOPRI5 and 8 for DOP853. A wrong tableau
// coefficient drops the order (typically to 1..4), which this detects.

TEST(IntegratorOrder, Dopri5IsFifthOrderOnHarmonicOscillator)
{
    const double p = convergence_order<vimpact::dopri5, harmonic>({10, 14, 20, 28, 40, 56, 80}, 4.0);
    EXPECT_NEAR(p, 5.0, 0.3);
}

TEST(IntegratorOrder, Dopri5IsFifthOrderOnNonlinearProblem)
{
    const double p = convergence_order<vimpact::dopri5, exp_sin>({45, 64, 90, 128, 180, 256}, 4.0);
    EXPECT_NEAR(p, 5.0, 0.3);
}

TEST(IntegratorOrder, Dop853IsEighthOrderOnHarmonicOscillator)
{
    const double p = convergence_order<vimpact::dop853, harmonic>({6, 8, 11, 16, 22}, 6.0);
    EXPECT_NEAR(p, 8.0, 0.3);
}

TEST(IntegratorOrder, Dop853IsEighthOrderOnNonlinearProblem)
{
    const double p = convergence_order<vimpact::dop853, limit_cycle>({16, 22, 32, 45, 64}, 6.0);
    EXPECT_NEAR(p, 8.0, 0.3);
}

// A state of more than 4 doubles takes the stage sums in a loop the compiler may vectorise, a
// state of up to 4 (the paper's model) component by component in scalar registers held apart
// (runge_kutta.hpp, stage_input_ordered), and the other sums (error estimates, the
// interpolant) as whole-vector Eigen expressions. Each component's arithmetic is the same whichever
// path runs it, so with three reference problems stacked into one 6-dimensional system, each
// block of the stacked run must equal the 2-dimensional run of its problem bit for bit (whose
// order the tests above check).
namespace {

using V6 = vec<6>;

struct stacked {
    V6 operator()(const V6& x) const
    {
        const V2 a = harmonic{}(x.segment<2>(0)), b = limit_cycle{}(x.segment<2>(2)), c = exp_sin{}(x.segment<2>(4));
        V6 f;
        f << a, b, c;
        return f;
    }
    static V6 exact(double t)
    {
        V6 x;
        x << harmonic::exact(t), limit_cycle::exact(t), exp_sin::exact(t);
        return x;
    }
};

template <template <int> class Method>
void expect_stacked_blocks_equal_small_runs(int n, double T)
{
    const V6 big = after_fixed_steps<Method, stacked, 6>(n, T);
    const V2 a = after_fixed_steps<Method, harmonic>(n, T), b = after_fixed_steps<Method, limit_cycle>(n, T),
             c = after_fixed_steps<Method, exp_sin>(n, T);
    for (int i = 0; i < 2; ++i) {
        EXPECT_EQ(big[i], a[i]) << "harmonic, component " << i;
        EXPECT_EQ(big[2 + i], b[i]) << "limit cycle, component " << i;
        EXPECT_EQ(big[4 + i], c[i]) << "exp(sin t), component " << i;
    }
}

}  // namespace

TEST(IntegratorOrder, LargeStateBlocksEqualTheSmallStateRunsBitForBit)
{
    expect_stacked_blocks_equal_small_runs<vimpact::dopri5>(200, 4.0);
    expect_stacked_blocks_equal_small_runs<vimpact::dop853>(100, 4.0);
}

// ---- dense output -------------------------------------------------------------------------

namespace {

// One step of size h from the exact solution at t0; returns the interpolant.
template <template <int> class Method, class Problem>
typename Method<2>::dense_type one_step_dense(double t0, double h, V2* x1_out = nullptr,
                                              V2* f0_out = nullptr, V2* f1_out = nullptr)
{
    Problem rhs;
    Method<2> m;
    const V2 x0 = Problem::exact(t0);
    const V2 f0 = rhs(x0);
    V2 x1, f1;
    m.attempt(rhs, x0, f0, h, 1.0, 1.0, x1, f1);
    typename Method<2>::dense_type d;
    m.build_dense(rhs, t0, h, x0, x1, d);
    if (x1_out) *x1_out = x1;
    if (f0_out) *f0_out = f0;
    if (f1_out) *f1_out = f1;
    return d;
}

// Max over interior theta of the interpolant's value error and of its derivative error.
template <template <int> class Method, class Problem>
void interpolant_errors(double t0, double h, double& value_err, double& slope_err)
{
    const auto d = one_step_dense<Method, Problem>(t0, h);
    value_err = 0.0;
    slope_err = 0.0;
    for (int j = 1; j < 40; ++j) {
        const double th = j / 40.0;
        const double t = t0 + th * h;
        V2 p, dp;
        d.value_and_slope(th, p, dp);
        value_err = std::max(value_err, (d.value_at(th) - Problem::exact(t)).cwiseAbs().maxCoeff());
        slope_err = std::max(slope_err, (dp / h - Problem::exact_rhs(t)).cwiseAbs().maxCoeff());
    }
}

template <template <int> class Method, class Problem>
void interpolant_orders(const std::vector<double>& hs, double& value_order, double& slope_order)
{
    std::vector<double> ev, es;
    for (double h : hs) {
        double a, b;
        interpolant_errors<Method, Problem>(0.3, h, a, b);
        ev.push_back(a);
        es.push_back(b);
    }
    value_order = fitted_slope(hs, ev);
    slope_order = fitted_slope(hs, es);
}

}  // namespace

// A q-th order continuous extension has local error O(h^{q+1}) inside the step, and its time
// derivative (d/dtheta divided by h) is accurate to O(h^q). DOPRI5's interpolant is 4th order
// (value slope 5, derivative slope 4); DOP853's is 7th order (8 and 7). A wrong dense
// coefficient reduces the order of the interior error even when the step end is right.
// Value and derivative orders of Method's interpolant on two problems.
template <template <int> class Method, class ProblemA, class ProblemB>
void expect_interpolant_orders(const std::vector<double>& hs, double value_order)
{
    double pv = 0.0, ps = 0.0;
    interpolant_orders<Method, ProblemA>(hs, pv, ps);
    EXPECT_NEAR(pv, value_order, 0.3) << "first problem";
    EXPECT_NEAR(ps, value_order - 1.0, 0.3) << "first problem";
    interpolant_orders<Method, ProblemB>(hs, pv, ps);
    EXPECT_NEAR(pv, value_order, 0.3) << "second problem";
    EXPECT_NEAR(ps, value_order - 1.0, 0.3) << "second problem";
}

TEST(DenseOutput, Dopri5InterpolantIsFourthOrder)
{
    expect_interpolant_orders<vimpact::dopri5, harmonic, limit_cycle>(
        {0.1, 0.08, 0.064, 0.05, 0.04, 0.032}, 5.0);
}

TEST(DenseOutput, Dop853InterpolantIsSeventhOrder)
{
    expect_interpolant_orders<vimpact::dop853, harmonic, exp_sin>(
        {0.32, 0.25, 0.2, 0.16, 0.125, 0.1}, 8.0);
}

// The interpolant passes through both step ends and is tangent to the vector field there
// (Hermite conditions of the Dormand-Prince extensions): p(0) = x0, p(1) = x1, p'(0) = h f0,
// p'(1) = h f1, to round-off. value_and_slope returns the same value as value_at.
template <template <int> class Method>
void check_end_conditions()
{
    for (double h : {0.05, 0.3, 0.9}) {
        V2 x1, f0, f1;
        const auto d = one_step_dense<Method, limit_cycle>(0.7, h, &x1, &f0, &f1);
        const V2 x0 = limit_cycle::exact(0.7);
        EXPECT_EQ(d.value_at(0.0), x0);  // x0 + 0 * s: exact
        // p(1) = x0 + (x1 - x0): one rounding of each operation, i.e. an ulp of max(|x0|, |x1|).
        for (int i = 0; i < 2; ++i) {
            const double scale = std::max(std::abs(x0[i]), std::abs(x1[i]));
            EXPECT_NEAR(d.value_at(1.0)[i], x1[i], 2.0 * std::numeric_limits<double>::epsilon() * scale)
                << "h = " << h;
        }
        V2 p, dp;
        d.value_and_slope(0.0, p, dp);
        EXPECT_EQ(p, x0);
        EXPECT_LE((dp - h * f0).cwiseAbs().maxCoeff(), 1e-14 * h) << "h = " << h;
        d.value_and_slope(1.0, p, dp);
        EXPECT_LE((dp - h * f1).cwiseAbs().maxCoeff(), 1e-14 * h) << "h = " << h;
        for (double th : {0.1, 0.5, 0.77}) {
            d.value_and_slope(th, p, dp);
            EXPECT_LE((p - d.value_at(th)).cwiseAbs().maxCoeff(), 1e-15);
        }
        EXPECT_EQ(d.t1(), d.t0 + h);
        EXPECT_DOUBLE_EQ(d.theta(0.7 + 0.5 * h), 0.5);
    }
}

TEST(DenseOutput, Dopri5EndConditions) { check_end_conditions<vimpact::dopri5>(); }
TEST(DenseOutput, Dop853EndConditions) { check_end_conditions<vimpact::dop853>(); }

// ---- adaptive integrator ------------------------------------------------------------------

namespace {

template <template <int> class Method>
double adaptive_error_at(double tol, double t_end, std::optional<double> hold_band = 0.0)
{
    vimpact::integrator_options opt;
    opt.rtol = tol;
    opt.atol = tol;
    opt.hold_band = hold_band;
    vimpact::adaptive_integrator<2, Method> integ(opt);
    harmonic rhs;
    integ.start(rhs, 0.0, harmonic::exact(0.0));
    for (int i = 0; i < 100000 && integ.t() < t_end; ++i)
        if (integ.advance(rhs, t_end) != vimpact::step_status::ok) return INFINITY;
    return (integ.x() - harmonic::exact(t_end)).cwiseAbs().maxCoeff();
}

template <template <int> class Method>
void check_tolerance_proportionality(std::optional<double> hold_band = 0.0)
{
    std::vector<double> tols{1e-6, 1e-7, 1e-8, 1e-9, 1e-10}, errs;
    for (double tol : tols) {
        const double e = adaptive_error_at<Method>(tol, 10.0, hold_band);
        EXPECT_LT(e, 100.0 * tol) << "tol = " << tol;
        errs.push_back(e);
    }
    // Error-per-step control with local extrapolation gives global error ~ tol^1.
    const double slope = fitted_slope(tols, errs);
    EXPECT_GT(slope, 0.7);
    EXPECT_LT(slope, 1.3);
    // Over four decades of tolerance the error must fall by at least two and a half.
    EXPECT_LT(errs.back(), errs.front() * 3e-3);
}

}  // namespace

// Global error at t = 10 of the harmonic oscillator scales like the tolerance and stays
// within a modest multiple of it.
TEST(AdaptiveIntegrator, Dopri5ErrorProportionalToTolerance)
{
    check_tolerance_proportionality<vimpact::dopri5>();
}
TEST(AdaptiveIntegrator, Dop853ErrorProportionalToTolerance)
{
    check_tolerance_proportionality<vimpact::dop853>();
}
// With a hold band the steps whose error is near the tolerance keep their size: the global
// error still follows the tolerance.
TEST(AdaptiveIntegrator, ErrorProportionalToToleranceWithAHoldBand)
{
    for (const double band : {0.1, 0.3, 0.5}) {
        SCOPED_TRACE(band);
        check_tolerance_proportionality<vimpact::dopri5>(band);
        check_tolerance_proportionality<vimpact::dop853>(band);
    }
}

// The hold band holds: the fraction of accepted steps after which the step size is exactly
// the one tried (step_size() unchanged across advance(), the last, clipped step left out).
// The proportional-integral controller changes it after every step. Its steps settle where
// safety err^-(a - b) = 1, err = 0.9^(1/(a - b)) with a = 1/k - 0.75 b, b = 0.04: about 0.44
// for DOPRI5 (k = 5) and 0.15 for DOP853 (k = 8), so most steps of a smooth problem lie inside
// a band from 0.3 (DOPRI5) or 0.1 (DOP853) to 1, and few of DOP853's inside [0.3, 1].
template <template <int> class Method>
double held_fraction(std::optional<double> hold_band)
{
    vimpact::integrator_options opt;
    opt.rtol = opt.atol = 1e-9;
    opt.hold_band = hold_band;
    vimpact::adaptive_integrator<2, Method> integ(opt);
    limit_cycle rhs;
    integ.start(rhs, 0.0, limit_cycle::exact(0.0));
    const double t_stop = 40.0;
    long steps = 0, held = 0;
    while (integ.t() < t_stop && steps < 100000) {
        const double h = integ.step_size();
        const long rejected = integ.counters().rejected;
        if (integ.advance(rhs, t_stop) != vimpact::step_status::ok) return NAN;
        if (integ.t() >= t_stop) break;
        ++steps;
        if (integ.counters().rejected == rejected && integ.step_size() == h) ++held;
    }
    return static_cast<double>(held) / static_cast<double>(steps);
}

TEST(AdaptiveIntegrator, HoldBandKeepsTheStepSizeOfMostSteps)
{
    EXPECT_LT(held_fraction<vimpact::dopri5>(0.0), 0.01);
    EXPECT_LT(held_fraction<vimpact::dop853>(0.0), 0.01);
    EXPECT_GT(held_fraction<vimpact::dopri5>(0.3), 0.5);
    EXPECT_GT(held_fraction<vimpact::dop853>(0.1), 0.5);
    EXPECT_LT(held_fraction<vimpact::dop853>(0.3), 0.2);
}

// Without a band in the options each method takes its own: DOPRI5 holds most of its steps
// (they settle near err = 0.44, inside its band), DOP853 none; and either default's global
// error still follows the tolerance, against the exact solution.
TEST(AdaptiveIntegrator, EachMethodHasItsDefaultHoldBand)
{
    EXPECT_GT(held_fraction<vimpact::dopri5>(std::nullopt), 0.5);
    EXPECT_LT(held_fraction<vimpact::dop853>(std::nullopt), 0.01);
    check_tolerance_proportionality<vimpact::dopri5>(std::nullopt);
    check_tolerance_proportionality<vimpact::dop853>(std::nullopt);
}

// control_step with a hold band: inside [band, 1] the step size and the controller's memory
// stay as they were; outside it, the outcome of the controller without a band. control_step
// takes the squared error norm, and the band's lower end as its square (0.3^2 here).
TEST(AdaptiveIntegrator, HoldBandChangesOnlyTheStepsInsideIt)
{
    vimpact::controller_constants plain{0.9, 0.2, 10.0, 0.04, 5};
    vimpact::controller_constants band = plain;
    band.hold_from = 0.3 * 0.3;
    const double h = 0.01, h_cur = 0.0125, memory = -3.5;
    // Also a step cut short by the stop time (clipped) and one that passed after a rejection:
    // held, they keep the held size h_cur, not the size tried.
    for (const bool clipped : {false, true}) {
        for (const bool rejected_before : {false, true}) {
            for (const double err : {0.3, 0.5, 0.99, 1.0}) {
                const double err2 = err * err;
                const auto out = vimpact::control_step(band, err2, true, h, h_cur, clipped, rejected_before, memory);
                EXPECT_TRUE(out.accepted) << err;
                EXPECT_EQ(out.h_next, h_cur) << err;
                EXPECT_EQ(out.log2_err_old, memory) << err;
                // Without the band the controller changes both.
                const auto p = vimpact::control_step(plain, err2, true, h, h_cur, clipped, rejected_before, memory);
                EXPECT_NE(p.log2_err_old, memory) << err;
            }
            // Outside the band, and for trials that are not finite whatever their error (0.5
            // included): the controller without a band, in every output.
            for (const double err : {0.0, 1e-6, 0.29, 0.5, 1.0000001, 3.0, std::nan("")}) {
                const double err2 = err * err;
                for (const bool finite : {true, false}) {
                    if (finite && (err == 0.5 || std::isnan(err))) continue;
                    const auto a = vimpact::control_step(band, err2, finite, h, h_cur, clipped, rejected_before, memory);
                    const auto b = vimpact::control_step(plain, err2, finite, h, h_cur, clipped, rejected_before, memory);
                    EXPECT_EQ(a.accepted, b.accepted) << err;
                    EXPECT_EQ(a.h_next, b.h_next) << err << " finite " << finite;
                    EXPECT_EQ(a.log2_err_old, b.log2_err_old) << err << " finite " << finite;
                }
            }
        }
    }
}

// The controller's factors against pow: after an accepted step with error err (given as err^2)
// and memory err_old, safety err^-(1/k - 0.75 beta) err_old^beta, clamped; after a rejection,
// max(factor_min, safety err^(-1/k)); the memory becomes log2 max(err, 1e-4). To the
// polynomials' accuracy (a relative 1e-7), whatever the squares do to the rounding.
TEST(AdaptiveIntegrator, ControllerFactorsArePowersOfTheErrorNorm)
{
    const vimpact::controller_constants c{0.9, 0.2, 10.0, 0.04, 5};
    const double a = 1.0 / 5 - 0.75 * 0.04, h = 0.01;
    for (const double err_old : {1e-6, 1e-3, 0.4, 1.0}) {
        const double memory = std::log2(std::max(err_old, 1e-4));
        for (const double err : {1e-9, 1e-3, 0.05, 0.44, 0.9, 1.0, 1.5, 40.0, 1e6}) {
            const auto out = vimpact::control_step(c, err * err, true, h, h, false, false, memory);
            ASSERT_EQ(out.accepted, err <= 1.0) << err;
            const double expected =
                err <= 1.0 ? std::clamp(0.9 * std::pow(std::max(err, 1e-14), -a) * std::pow(std::max(err_old, 1e-4), 0.04), 0.2, 10.0)
                           : std::max(0.2, 0.9 * std::pow(err, -1.0 / 5));
            EXPECT_NEAR(out.h_next / h, expected, 1e-7 * expected) << "err " << err << " err_old " << err_old;
            if (err <= 1.0) {
                EXPECT_NEAR(out.log2_err_old, std::log2(std::max(err, 1e-4)), 1e-7) << err;
            }
        }
    }
}

// What attempt() returns: the squared RMS norm of the embedded error estimate over the
// weights atol + rtol max(|x0|, |x1|). For DOPRI5 against the difference of its 5th-order
// solution and the 4th-order one of Dormand & Prince's published weights (Hairer, Norsett &
// Wanner, Solving ODEs I, Table II.5.2), from the same stages.
TEST(AdaptiveIntegrator, Dopri5ErrorIsTheSquaredNormOfTheEmbeddedDifference)
{
    constexpr double b4[7] = {5179.0 / 57600.0, 0.0, 7571.0 / 16695.0, 393.0 / 640.0, -92097.0 / 339200.0,
                              187.0 / 2100.0, 1.0 / 40.0};
    limit_cycle rhs;
    for (const double h : {0.05, 0.1, 0.2}) {
        for (const double tol : {1e-9, 1e-6}) {
            vimpact::dopri5<2> m;
            const V2 x0 = limit_cycle::exact(0.3), f0 = rhs(x0);
            V2 x1, f1;
            const double err2 = m.attempt(rhs, x0, f0, h, 10.0 * tol, tol, x1, f1);
            V2 x4 = x0;
            for (int i = 0; i < 7; ++i) x4 += h * b4[i] * m.stages()[static_cast<std::size_t>(i)];
            const V2 sc = (tol + 10.0 * tol * x0.cwiseAbs().cwiseMax(x1.cwiseAbs()).array()).matrix();
            const double expected = (x1 - x4).cwiseQuotient(sc).squaredNorm() / 2.0;
            EXPECT_NEAR(err2, expected, 1e-6 * expected) << "h " << h << " tol " << tol;
        }
    }
}

// For DOP853 against Hairer's error formula as his code writes it, err = |h| s5 /
// sqrt(N (s5 + 0.01 s3)), s5 and s3 the sums of the squared 5th- and 3rd-order estimates
// (the tableau's E5 and E3 over the stages) divided by the weights: the constants N and 0.01
// and the place of h, which the slope below cannot see.
TEST(AdaptiveIntegrator, Dop853ErrorIsTheSquareOfHairersNorm)
{
    namespace tab = vimpact::dop853_tableau;
    limit_cycle rhs;
    for (const double h : {0.05, 0.2, 0.4}) {
        vimpact::dop853<2> m;
        const V2 x0 = limit_cycle::exact(0.3), f0 = rhs(x0);
        V2 x1, f1;
        const double err2 = m.attempt(rhs, x0, f0, h, 1e-9, 1e-9, x1, f1);
        V2 e5 = V2::Zero(), e3 = V2::Zero();
        for (std::size_t i = 0; i < tab::E5.size(); ++i) {
            e5 += tab::E5[i] * m.stages()[i];
            e3 += tab::E3[i] * m.stages()[i];
        }
        const V2 sc = (1e-9 + 1e-9 * x0.cwiseAbs().cwiseMax(x1.cwiseAbs()).array()).matrix();
        const double s5 = e5.cwiseQuotient(sc).squaredNorm(), s3 = e3.cwiseQuotient(sc).squaredNorm();
        const double err = std::abs(h) * s5 / std::sqrt(2.0 * (s5 + 0.01 * s3));
        // The estimates are small sums of O(1) stages: summed in another order, their
        // cancellation leaves a relative 5e-6 at h = 0.05. A wrong constant (N, 0.01, a power
        // of h) is off by a factor.
        EXPECT_NEAR(err2, err * err, 1e-4 * err * err) << "h " << h;
    }
}

// The error estimates' orders: err^2 of one step falls like h^(2 k), k = 5 for DOPRI5's
// estimate and 8 for DOP853's (its 5th-order estimate, damped by the 3rd-order one as
// h^8 for small h: Hairer's formula).
template <template <int> class Method>
double error_norm_slope()
{
    limit_cycle rhs;
    const V2 x0 = limit_cycle::exact(0.3), f0 = rhs(x0);
    std::vector<double> hs, errs;
    for (double h = 0.02; h < 0.17; h *= 1.25) {
        Method<2> m;
        V2 x1, f1;
        hs.push_back(h);
        errs.push_back(m.attempt(rhs, x0, f0, h, 1e-8, 1e-8, x1, f1));
    }
    return fitted_slope(hs, errs);
}

TEST(AdaptiveIntegrator, SquaredErrorNormFallsWithTwiceTheEstimatesOrder)
{
    EXPECT_NEAR(error_norm_slope<vimpact::dopri5>(), 10.0, 0.5);
    EXPECT_NEAR(error_norm_slope<vimpact::dop853>(), 16.0, 0.8);
}

// The integrator's shortcut for a held step, on a step cut short by the stop time: the step
// size held before the step is kept (not the shorter size the step was cut to), as
// control_step decides. Free steps let the step size settle; after each, one step is cut to
// 0.97 of the held size, so that its error (about 0.97^6 of a full step's) mostly still lies
// inside the band. (Keeping the size tried instead fails about half of these steps.)
TEST(AdaptiveIntegrator, HeldStepCutShortKeepsTheHeldSize)
{
    vimpact::integrator_options opt;
    opt.rtol = opt.atol = 1e-9;
    opt.hold_band = 0.1;
    vimpact::adaptive_integrator<2, vimpact::dopri5> integ(opt);
    limit_cycle rhs;
    integ.start(rhs, 0.0, limit_cycle::exact(0.0));
    const double far = 1e9;
    for (int k = 0; k < 50; ++k) ASSERT_EQ(integ.advance(rhs, far), vimpact::step_status::ok);
    long cut = 0, kept = 0;
    for (int k = 0; k < 400; ++k) {
        ASSERT_EQ(integ.advance(rhs, far), vimpact::step_status::ok);
        const double h = integ.step_size();
        const double t_stop = integ.t() + 0.97 * h;
        const long rejected = integ.counters().rejected;
        ASSERT_EQ(integ.advance(rhs, t_stop), vimpact::step_status::ok);
        if (integ.counters().rejected != rejected) continue;
        ASSERT_EQ(integ.t(), t_stop);
        ++cut;
        EXPECT_NE(integ.step_size(), integ.last_step()) << "step " << k;
        if (integ.step_size() == h) ++kept;
    }
    EXPECT_GT(cut, 300);
    EXPECT_GT(kept, 9 * cut / 10);
}

// Counters: the reported number of vector-field evaluations equals the number actually made
// (counted independently by the right-hand side), and equals the count implied by the method:
// 1 at start (+1 for the initial-step estimate) + stages per trial step + extra interpolant
// stages per interpolant built (built lazily: once per step however often it is requested).
template <template <int> class Method>
void check_counters(double h_init)
{
    using M = Method<2>;
    long calls = 0;
    auto rhs = [&calls](const V2& x) {
        ++calls;
        return limit_cycle{}(x);
    };
    vimpact::integrator_options opt;
    opt.rtol = opt.atol = 1e-9;
    opt.h_init = h_init;
    vimpact::adaptive_integrator<2, Method> integ(opt);
    integ.start(rhs, 0.0, limit_cycle::exact(0.0));
    long dense_builds = 0, accepted = 0;
    double h_lo = std::numeric_limits<double>::infinity(), h_hi = 0.0;
    const double t_stop = 7.3;
    int guard = 0;
    while (integ.t() < t_stop && ++guard < 100000) {
        const double t_before = integ.t();
        ASSERT_EQ(integ.advance(rhs, t_stop), vimpact::step_status::ok);
        ++accepted;
        h_lo = std::min(h_lo, integ.t() - t_before);
        h_hi = std::max(h_hi, integ.t() - t_before);
        if (integ.counters().steps % 3 == 0) {
            (void)integ.dense(rhs);
            (void)integ.dense(rhs);  // cached: no new stages
            ++dense_builds;
        }
    }
    const auto& c = integ.counters();
    EXPECT_EQ(c.steps, accepted);
    // A first step far beyond what the tolerance allows must be rejected, and counted.
    if (h_init > 0.0) {
        EXPECT_GT(c.rejected, 0);
    }
    EXPECT_EQ(c.rhs_calls, calls);
    const long expected = 1 + (h_init > 0.0 ? 0 : 1) + M::stages_per_step * (c.steps + c.rejected) +
                          M::dense_extra_stages * dense_builds;
    EXPECT_EQ(c.rhs_calls, expected);
    // The extreme step sizes are those of the steps actually taken (t advanced by h; the
    // clipped last step included). t + h rounds, so equality holds to an ulp of t_stop.
    const double ulp = 4.0 * std::numeric_limits<double>::epsilon() * t_stop;
    EXPECT_NEAR(c.h_min, h_lo, ulp);
    EXPECT_NEAR(c.h_max, h_hi, ulp);
}

TEST(AdaptiveIntegrator, Dopri5CountersMatchActualCalls)
{
    check_counters<vimpact::dopri5>(0.0);
    check_counters<vimpact::dopri5>(0.5);  // a too-large first step: rejections counted too
}
TEST(AdaptiveIntegrator, Dop853CountersMatchActualCalls)
{
    check_counters<vimpact::dop853>(0.0);
    check_counters<vimpact::dop853>(2.0);
}

// The last step is clipped so that the integration ends exactly (bit for bit) at t_stop, never
// beyond, including for a t_stop that is not a round number.
template <template <int> class Method>
void check_lands_on_t_stop(double t_stop)
{
    vimpact::adaptive_integrator<2, Method> integ;
    harmonic rhs;
    integ.start(rhs, 0.0, harmonic::exact(0.0));
    int guard = 0;
    while (integ.t() < t_stop && ++guard < 100000) {
        ASSERT_EQ(integ.advance(rhs, t_stop), vimpact::step_status::ok);
        ASSERT_LE(integ.t(), t_stop);
    }
    EXPECT_EQ(integ.t(), t_stop);
    EXPECT_LT((integ.x() - harmonic::exact(t_stop)).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(AdaptiveIntegrator, ClippedFinalStepLandsExactlyOnTStop)
{
    for (double t_stop : {10.0, 0.1 * 3.0, 7.0 / 3.0, 1e-3}) {
        check_lands_on_t_stop<vimpact::dopri5>(t_stop);
        check_lands_on_t_stop<vimpact::dop853>(t_stop);
    }
}

// Finite-time blow-up: y' = y^2, y(0) = 1 has y = 1/(1 - t), singular at t = 1. Integrating
// towards t = 2 must end with step_underflow or non_finite close to t = 1, in a bounded number
// of steps, and must not step across the singularity by more than its own accumulated error
// (the numerical blow-up time is 1 + O(tol); measured within 1e-10 of 1). Before failing, the solution is
// followed accurately (checked at t = 0.9).
template <template <int> class Method>
void check_blow_up()
{
    using V1 = vec<1>;
    auto rhs = [](const V1& y) { return V1(y[0] * y[0]); };
    vimpact::adaptive_integrator<1, Method> integ;
    integ.start(rhs, 0.0, V1(1.0));
    vimpact::step_status st = vimpact::step_status::ok;
    long n = 0;
    bool checked_09 = false;
    while (st == vimpact::step_status::ok && n < 200000 && integ.t() < 2.0) {
        const double target = checked_09 ? 2.0 : 0.9;
        st = integ.advance(rhs, target);
        ++n;
        if (!checked_09 && integ.t() == 0.9) {
            EXPECT_NEAR(integ.x()[0], 10.0, 1e-7);
            checked_09 = true;
        }
    }
    EXPECT_TRUE(checked_09);
    EXPECT_TRUE(st == vimpact::step_status::step_underflow || st == vimpact::step_status::non_finite)
        << "status " << static_cast<int>(st) << " at t = " << integ.t() << " after " << n << " steps";
    EXPECT_LT(n, 200000);
    EXPECT_LE(integ.t(), 1.0 + 1e-8);
    EXPECT_GT(integ.t(), 1.0 - 1e-8);
}

TEST(AdaptiveIntegrator, FiniteTimeBlowUpIsReported)
{
    check_blow_up<vimpact::dopri5>();
    check_blow_up<vimpact::dop853>();
}
