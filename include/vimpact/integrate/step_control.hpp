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
// With a hold band b in (0, 1) (integrator_options::hold_band), an accepted step whose error
// lies in [b, 1] keeps the step size and leaves the controller's memory as it was: the step
// is near its best size, and deciding that needs one comparison, so the next trial can start
// before the logarithm and the power would have been computed (the integrator branches on it:
// a branch the processor predicts, not a chain of data the next step waits for). Boost.Odeint's
// controller does the same with b = 0.5 and no integral term.
//
// The powers are computed as 2^(c log2 err) by short polynomials (relative error below 1e-10)
// instead of pow, log and exp: a step size needs a few digits, the library functions cost a
// quarter of a DOPRI5 step, and a polynomial gives the same bits in every SIMD lane as on a
// scalar.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "vimpact/core/lane_ops.hpp"

namespace vimpact {


// log2(x) for finite x >= the smallest normal double; relative error below 1e-10.
template <class T>
T fast_log2(const T& x)
{
    using B = lane_bits_ops<T>;
    constexpr std::int64_t mantissa = 0x000fffffffffffffLL, one = 0x3ff0000000000000LL;
    const auto b = B::bits(x);
    using I = std::decay_t<decltype(b)>;
    // x = m 2^e with m in [1, 2), then m in [sqrt(1/2), sqrt(2)) so that s below is small.
    T e = B::to_double((b >> 52) - I(1023));
    T m = B::from_bits((b & I(mantissa)) | I(one));
    const auto big = m > T(1.4142135623730951);
    m = select(big, T(0.5 * m), m);
    e = select(big, T(e + 1.0), e);
    // ln m = 2 atanh(s), s = (m - 1)/(m + 1) in [-0.172, 0.172]:
    //   atanh(s) / s = 1 + s^2/3 + s^4/5 + ... + s^12/13,
    // evaluated by Estrin's scheme (products of powers of s^2 beside each other rather than
    // one chain of 6 multiply-adds: the controller's result starts the next step, so its
    // latency is the integrator's).
    using std::fma;
    const T s = (m - 1.0) / (m + 1.0);
    const T s2 = s * s;
    const T s4 = s2 * s2;
    const T s8 = s4 * s4;
    const T q01 = fma(s2, T(1.0 / 3), T(1.0));
    const T q23 = fma(s2, T(1.0 / 7), T(1.0 / 5));
    const T q45 = fma(s2, T(1.0 / 11), T(1.0 / 9));
    const T q03 = fma(s4, q23, q01);
    const T q46 = fma(s4, T(1.0 / 13), q45);
    const T p = fma(s8, q46, q03);
    return fma(T(2.0 * 1.4426950408889634), T(s * p), e);
}

// 2^y for y in [-1020, 1020] (clamped there); relative error below 1e-12.
template <class T>
T fast_exp2(const T& y_in)
{
    using B = lane_bits_ops<T>;
    const T y = lane_min(lane_max(y_in, T(-1020.0)), T(1020.0));
    const T n = B::round(y);
    using std::fma;
    const T g = (y - n) * 0.6931471805599453;  // in [-0.347, 0.347]
    // e^g by its Taylor polynomial to degree 11 (explicit multiply-adds: the same bits in
    // lanes), by Estrin's scheme: pairs c_k + c_{k+1} g, joined with g^2, g^4, g^8 (depth 5
    // instead of a chain of 11).
    const T g2 = g * g;
    const T g4 = g2 * g2;
    const T g8 = g4 * g4;
    constexpr double c[12] = {1.0,       1.0,        0.5,         1.0 / 6,       1.0 / 24,       1.0 / 120,
                              1.0 / 720, 1.0 / 5040, 1.0 / 40320, 1.0 / 362880, 1.0 / 3628800, 1.0 / 39916800};
    const T p01 = fma(g, T(c[1]), T(c[0])), p23 = fma(g, T(c[3]), T(c[2])), p45 = fma(g, T(c[5]), T(c[4])),
            p67 = fma(g, T(c[7]), T(c[6])), p89 = fma(g, T(c[9]), T(c[8])), pab = fma(g, T(c[11]), T(c[10]));
    const T p03 = fma(g2, p23, p01), p47 = fma(g2, p67, p45), p8b = fma(g2, pab, p89);
    const T p07 = fma(g4, p47, p03);
    const T p = fma(g8, p8b, p07);
    return p * B::from_bits(B::exponent_bits(n) << 52);
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
    // The lower end of the hold band; infinity: no hold.
    double hold_from = std::numeric_limits<double>::infinity();
};

// Whether an accepted trial (accepted: finite, error <= 1) keeps the step size: the one rule
// of the hold band, for control_step and for the integrator's shortcut around it.
template <class T, class Mask>
Mask step_held(const controller_constants& c, const T& err, Mask accepted)
{
    return accepted && err >= T(c.hold_from);
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

// err: the trial's error norm; finite: the trial produced finite numbers; h: the step tried;
// h_cur: the step size held before the trial (kept after a step cut short by the stop time);
// clipped: the step was cut short to end at the stop time; rejected_before: an earlier trial
// of this step was rejected.
template <class T, class Mask>
trial_outcome<T, Mask> control_step(const controller_constants& c, const T& err, Mask finite, const T& h,
                                    const T& h_cur, Mask clipped, Mask rejected_before, const T& log2_err_old)
{
    const Mask accepted = finite && err <= T(1.0);
    // One logarithm and one power: the PI factor where the trial is accepted, the shrinking
    // one (err^(-1/k)) where it is not.
    const T log_e = fast_log2(lane_max(err, T(1e-14)));
    const double a = 1.0 / c.order - 0.75 * c.beta;
    using std::fma;
    const T power = c.safety * fast_exp2(select(accepted, T(fma(T(-a), log_e, T(c.beta * log2_err_old))),
                                                  T(log_e * (-1.0 / c.order))));
    T factor_ok = lane_min(lane_max(power, T(c.factor_min)), T(c.factor_max));
    factor_ok = select(rejected_before, lane_min(factor_ok, T(1.0)), factor_ok);
    const T factor_bad = select(finite, lane_max(T(c.factor_min), power), T(c.factor_min));
    // A step cut short by the stop time says nothing about the achievable size.
    const T h_ok = select(!clipped || factor_ok < T(1.0), T(h * factor_ok), h_cur);
    const Mask held = step_held(c, err, accepted);
    return {accepted, select(held, h_cur, select(accepted, h_ok, T(h * factor_bad))),
            select(accepted && !held, lane_max(log_e, T(log2_err_floor)), log2_err_old)};
}

}  // namespace vimpact
