#pragma once
// The step-size controller of the adaptive integrator, written once for a scalar type T
// (double, or lanes: core/lanes.hpp), so that a job integrated in a SIMD lane takes exactly the
// steps it takes alone.
//
// The controller (documented in docs/performance.md): after an accepted step with error
// estimate err (<= 1), the next step is h * clamp(safety * err^-a * err_old^b, factor_min,
// factor_max), a proportional-integral controller (Gustafsson; Hairer & Wanner, Solving ODEs
// II, IV.2): a = 1/k - 0.75 beta, b = beta, err_old the previous accepted step's error
// (floored at 1e-4), k the order of the error estimate. After a rejection the step shrinks by
// max(factor_min, safety * err^(-1/k)) and the step that finally passes may not grow.
//
// It takes the squared error norm err^2, as the Runge-Kutta methods return it
// (integrate/runge_kutta.hpp): the powers of err are powers of err^2 with half the exponent,
// so no square root waits between a trial and the next step's size.
//
// With a hold band b in (0, 1) (integrator_options::hold_band), an accepted step whose error
// lies in [b, 1] keeps the step size and leaves the controller's memory as it was: the step
// is near its best size, and deciding that needs one comparison, so the next trial can start
// before the logarithm and the power would have been computed (the integrator branches on it:
// a branch the processor predicts, not a chain of data the next step waits for). Boost.Odeint's
// controller does the same with b = 0.5 and no integral term.
//
// The powers are computed as 2^(c log2 err^2) by short polynomials instead of pow, log and
// exp: a step size needs a few digits, the library functions cost a quarter of a DOPRI5 step,
// and a polynomial gives the same bits in every SIMD lane as on a scalar. Their latency is the
// integrator's (the next trial starts from the step size they give), so they are short: no
// division, degree 8 and 6, errors of 1e-7 (log2, absolute) and 5e-9 (2^y, relative), which
// move a step size by less than 1e-7 of itself.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "vimpact/core/lane_ops.hpp"

namespace vimpact {


// log2(x) for finite x >= the smallest normal double; absolute error below 1e-7.
template <class T>
[[gnu::always_inline]] inline T fast_log2(const T& x)
{
    using B = lane_bits_ops<T>;
    const auto b = B::bits(x);
    using I = std::decay_t<decltype(b)>;
    // x = m 2^e with m in [sqrt(1/2), sqrt(2)): the bits of x less those of sqrt(1/2) carry
    // into the exponent field exactly where m would leave that range (integer operations, no
    // comparison).
    constexpr std::int64_t sqrt_half = 0x3fe6a09e667f3bcdLL, exponent_field = ~0x000fffffffffffffLL;
    const I k = b - I(sqrt_half);
    const T e = B::to_double(k >> 52);
    const T t = B::from_bits(b - (k & I(exponent_field))) - 1.0;
    // log2(1 + t) = t q(t) (scripts/gen_controller_polynomials.py), q by Estrin's scheme:
    // pairs joined by t^2 and t^4, depth 3 instead of a chain of 7 multiply-adds.
    constexpr double c[8] = {1.442694994893047,   -0.7213529313629857,  0.4809167080001993,
                             -0.36022518246065766, 0.2872888823750311,  -0.24927182208104065,
                             0.23265257881234003,  -0.14275973432399872};
    using std::fma;
    const T t2 = t * t;
    const T t4 = t2 * t2;
    const T q01 = fma(t, T(c[1]), T(c[0])), q23 = fma(t, T(c[3]), T(c[2])), q45 = fma(t, T(c[5]), T(c[4])),
            q67 = fma(t, T(c[7]), T(c[6]));
    const T q03 = fma(t2, q23, q01), q47 = fma(t2, q67, q45);
    return fma(t, fma(t4, q47, q03), e);
}

// 2^y for y in [-1020, 1020]; relative error below 5e-9.
template <class T>
[[gnu::always_inline]] inline T fast_exp2(const T& y)
{
    using B = lane_bits_ops<T>;
    // y + 1.5 2^52 rounds y to the nearest integer n, held in the low bits of its mantissa.
    constexpr double round_shift = 6755399441055744.0;
    const T shifted = y + round_shift;
    const T g = y - (shifted - round_shift);  // in [-1/2, 1/2]
    // 2^g = 1 + g p(g) (scripts/gen_controller_polynomials.py), p by Estrin's scheme.
    constexpr double c[6] = {0.6931471880262284,   0.24022650760568226,   0.05550357114219106,
                             0.009618082557271741, 0.0013390863364681129, 0.00015453162946382396};
    using std::fma;
    const T g2 = g * g;
    const T g4 = g2 * g2;
    const T p01 = fma(g, T(c[1]), T(c[0])), p23 = fma(g, T(c[3]), T(c[2])), p45 = fma(g, T(c[5]), T(c[4]));
    const T p = fma(g4, p45, fma(g2, p23, p01));
    const auto n = B::bits(shifted);
    using I = std::decay_t<decltype(n)>;
    return fma(g, p, T(1.0)) * B::from_bits(((n + I(1023)) & I(0x7ff)) << 52);
}

// The step a trial tries from t with the held step size h_held: at most h_max, cut short to
// end at t_stop; underflow when it is not cut short and not above 16 ulps of t.
template <class T, class Mask>
struct trial_plan {
    T h;
    Mask clipped;
    Mask underflow;
    T h_floor;
};

template <class T>
auto plan_trial(const T& t, const T& h_held, double h_max, double t_stop)
{
    using std::abs;
    using Mask = decltype(t < t);
    T h = lane_min(h_held, T(h_max));
    const Mask clipped = t + h >= T(t_stop);
    h = select(clipped, T(t_stop - t), h);
    const T h_floor = (16.0 * std::numeric_limits<double>::epsilon()) * lane_max(T(1.0), T(abs(t)));
    return trial_plan<T, Mask>{h, clipped, !(h > h_floor) && !clipped, h_floor};
}

struct controller_constants {
    double safety, factor_min, factor_max, beta;
    int order;  // of the error estimate
    // The lower end of the hold band for the squared error norm, b^2; infinity: no hold.
    double hold_from = std::numeric_limits<double>::infinity();
};

// Whether an accepted trial (accepted: finite, err^2 <= 1) keeps the step size: the one rule
// of the hold band, for control_step and for the integrator's shortcut around it.
template <class T, class Mask>
Mask step_held(const controller_constants& c, const T& err2, Mask accepted)
{
    return accepted && err2 >= T(c.hold_from);
}

// log2 of the error floor of the integral term (Hairer's 1e-4).
inline constexpr double log2_err_floor = -13.287712379549449;

// One trial's outcome: whether it is accepted, the next step size, and the controller's memory.
template <class T, class Mask>
struct trial_outcome {
    Mask accepted;
    T h_next;
    T log2_err_old;
};

// err2: the trial's squared error norm; finite: the trial produced finite numbers; h: the
// step tried; h_cur: the step size held before the trial (kept after a step cut short by the
// stop time); clipped: the step was cut short to end at the stop time; rejected_before: an
// earlier trial of this step was rejected.
template <class T, class Mask>
trial_outcome<T, Mask> control_step(const controller_constants& c, const T& err2, Mask finite, const T& h,
                                    const T& h_cur, Mask clipped, Mask rejected_before, const T& log2_err_old)
{
    const Mask accepted = finite && err2 <= T(1.0);
    // One logarithm and one power: the PI factor where the trial is accepted, the shrinking
    // one (err^(-1/k)) where it is not. The exponents of err are halved for err^2, and the
    // floor 1e-14 of err is 1e-28 of err^2. The power's argument stays inside fast_exp2's
    // range for any err2, a NaN included: |log_e2| <= 1026, so |y| <= 1026 / (2 k) + 1.
    const T log_e2 = fast_log2(lane_max(err2, T(1e-28)));
    const double a = 1.0 / c.order - 0.75 * c.beta;
    using std::fma;
    const T power = c.safety * fast_exp2(select(accepted, T(fma(T(-0.5 * a), log_e2, T(c.beta * log2_err_old))),
                                                  T(log_e2 * (-0.5 / c.order))));
    T factor_ok = lane_min(lane_max(power, T(c.factor_min)), T(c.factor_max));
    factor_ok = select(rejected_before, lane_min(factor_ok, T(1.0)), factor_ok);
    const T factor_bad = select(finite, lane_max(T(c.factor_min), power), T(c.factor_min));
    // A step cut short by the stop time says nothing about the achievable size.
    const T h_ok = select(!clipped || factor_ok < T(1.0), T(h * factor_ok), h_cur);
    const Mask held = step_held(c, err2, accepted);
    return {accepted, select(held, h_cur, select(accepted, h_ok, T(h * factor_bad))),
            select(accepted && !held, lane_max(T(0.5 * log_e2), T(log2_err_floor)), log2_err_old)};
}

}  // namespace vimpact
