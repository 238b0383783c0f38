#pragma once
// Embedded explicit Runge-Kutta pairs with dense output: DOPRI5 (Dormand & Prince 5(4), with
// Shampine's 4th-order interpolant) and DOP853 (8(5,3), 7th-order interpolant). Each method
// takes a trial step, returns its squared scaled error norm, and builds its interpolant on request.
#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>
#include <utility>

#include "vimpact/core/lane_ops.hpp"
#include "vimpact/core/state.hpp"
#include "vimpact/integrate/dense_output.hpp"
#include "vimpact/integrate/dop853_tableau.hpp"

// Inline everything a Runge-Kutta step calls (see attempt()), and keep the step itself one
// function: inlined into its caller's event handling, the step's code depended on how large
// that caller was (a protocol run 1.4x slower for one model than for an identical one).
// Not under AddressSanitizer: there the instrumented, fully inlined steps take minutes and
// gigabytes to compile, and the sanitizer build is about correctness, not speed.
#if defined(__SANITIZE_ADDRESS__)
#define VIMPACT_FLATTEN
#else
#define VIMPACT_FLATTEN [[gnu::flatten, gnu::noinline]]
#endif

namespace vimpact {

enum class rk_method { dopri5, dop853 };

// The error weights atol + rtol max(|x0|, |x1|), component by component (for double with
// Eigen's vectorised max, for lanes with lane_max: the same numbers for finite states, and a
// trial that is not finite is rejected whatever its error).
template <int N, class T = double>
inline vec_t<T, N> error_scale(const vec_t<T, N>& x0, const vec_t<T, N>& x1, double rtol, double atol)
{
    if constexpr (std::is_same_v<T, double>) {
        return (atol + rtol * x0.cwiseAbs().cwiseMax(x1.cwiseAbs()).array()).matrix();
    } else {
        using std::abs;
        vec_t<T, N> sc = sized<vec_t<T, N>>(x0.size());
        for (Eigen::Index i = 0; i < x0.size(); ++i) sc[i] = atol + rtol * lane_max(T(abs(x0[i])), T(abs(x1[i])));
        return sc;
    }
}

// error_weights (below) for double, into w (sized as x0): the scale, then h times its
// reciprocal, in w itself.
template <int N>
inline void error_weights_into(const vec<N>& x0, const vec<N>& x1, double h, double rtol, double atol, vec<N>& w)
{
    w = (atol + rtol * x0.cwiseAbs().cwiseMax(x1.cwiseAbs()).array()).matrix();
    w = (h * w.array().inverse()).matrix();
}

// The weights h / (atol + rtol max(|x0|, |x1|)) of the error estimate's components (the
// estimate is h times a sum of stages): computed from the step's ends before its last stage
// is, so that the error's own chain to the controller has a multiplication where a division
// would be.
template <int N, class T>
inline vec_t<T, N> error_weights(const vec_t<T, N>& x0, const vec_t<T, N>& x1, const T& h, double rtol, double atol)
{
    // h (1 / sc_i), not h / sc_i: Eigen vectorises the reciprocal for double (a loop of
    // quotients made DOP853's step 1.3x slower), and lanes take the same two roundings.
    if constexpr (std::is_same_v<T, double>) {
        vec<N> w = sized<vec<N>>(x0.size());
        error_weights_into<N>(x0, x1, h, rtol, atol, w);
        return w;
    } else {
        const vec_t<T, N> sc = error_scale<N, T>(x0, x1, rtol, atol);
        vec_t<T, N> w = sized<vec_t<T, N>>(x0.size());
        for (Eigen::Index i = 0; i < x0.size(); ++i) w[i] = h * (T(1.0) / sc[i]);
        return w;
    }
}

// sum_i (e_i w_i)^2 in one fixed order with explicit multiply-adds (two interleaved
// accumulators, even and odd i, then their sum): the same rounding for a scalar and for a SIMD
// lane (core/lanes.hpp), whatever the compiler would contract on its own.
// The sum of q(i)^2, i < n, in that order.
template <int N, class T, class Q>
inline T ordered_square_sum(Q&& q, Eigen::Index n)
{
    using std::fma;
    if constexpr (N == 1) {
        return T(q(0) * q(0));
    } else {
        if (N == Eigen::Dynamic && n == 1) return T(q(0) * q(0));
        T even = q(0) * q(0), odd = q(1) * q(1);
        for (Eigen::Index i = 2; i < n; i += 2) even = fma(q(i), q(i), even);
        for (Eigen::Index i = 3; i < n; i += 2) odd = fma(q(i), q(i), odd);
        return T(even + odd);
    }
}

template <int N, class T>
inline T weighted_square_sum(const vec_t<T, N>& e, const vec_t<T, N>& w)
{
    // Sized at run time, each product as it is needed (the same rounding), not in a vector
    // that would be allocated on every step.
    if constexpr (N == Eigen::Dynamic) {
        return ordered_square_sum<N, T>([&](Eigen::Index i) { return T(e[i] * w[i]); }, e.size());
    } else {
        const vec_t<T, N> q = e.cwiseProduct(w);
        return ordered_square_sum<N, T>([&](Eigen::Index i) -> const T& { return q[i]; }, q.size());
    }
}

// The stage arithmetic both methods share. sum_{j < Count} Coef[j] k_j (error estimates,
// interpolants), with the coefficients known at compile time (zero entries cost nothing) and
// two interleaved accumulators, which halve the dependency chain of the additions.
namespace rk_detail {

template <double C, class State>
inline void add_term(State& acc, const State& k)
{
    if constexpr (C != 0.0) acc += C * k;
}

// The same into out, with acc as the second accumulator (both sized as the stages): states
// sized at run time keep their vectors.
template <int Count, const auto& Coef, class State, std::size_t S>
inline void combine_into(const std::array<State, S>& k, State& out, State& acc)
{
    using T = typename State::Scalar;
    [&]<int... J>(std::integer_sequence<int, J...>) {
        const Eigen::Index n = k[0].size();
        out.setConstant(n, T(0.0));
        acc.setConstant(n, T(0.0));
        (add_term<Coef[J]>(J % 2 == 0 ? out : acc, k[J]), ...);
        out += acc;
    }(std::make_integer_sequence<int, Count>{});
}

template <int Count, const auto& Coef, class State, std::size_t S>
inline State combine(const std::array<State, S>& k)
{
    using T = typename State::Scalar;
    return [&]<int... J>(std::integer_sequence<int, J...>) {
        const Eigen::Index n = k[0].size();
        State acc[2] = {State::Constant(n, T(0.0)), State::Constant(n, T(0.0))};
        (add_term<Coef[J]>(acc[J % 2], k[J]), ...);
        return State(acc[0] + acc[1]);
    }(std::make_integer_sequence<int, Count>{});
}

// acc + c k, one term of a stage input: one rounding (std::fma, or the lanes' fused
// operation) where the processor fuses multiply and add (FP_FAST_FMA: FMA3 on x86-64, every
// AArch64); a build for a processor without it (-march=x86-64) would call the library's fma
// for every term (a DOP853 trial took 4.6x as long), so there it multiplies and adds. A
// SIMD lane and a job alone of one build take the same branch, so they agree to the bit.
template <class T>
inline T stage_term(const T& acc, const T& c, const T& k)
{
#ifdef FP_FAST_FMA
    using std::fma;
    return fma(c, k, acc);
#else
    return acc + c * k;
#endif
}

// x + sum_{j < Count} (h coef[j]) k_j, the stage inputs and the new state of both methods,
// added one stage at a time from the oldest to the newest, as Odeint's steppers do, each term
// by one fused multiply-add (stage_term): a stage's input then waits for the newest stage by
// one operation, the older terms by one each before it. (Summed in two accumulators, then
// scaled by h and added to x, the older stages stood five dependent operations before the
// next input: DOP853's step took 1.2x the time of the ordered sum, DOPRI5's trial 1.3x; with a
// multiply and an add per term instead of one fused operation, DOP853's trial took 1.26x,
// DOPRI5's 1.10x: docs/performance.md.) For a small double state the sum runs component by
// component in scalar registers, so that each component of the next input waits only for the
// same component of the newest stage (and the vector field's components, computed one by one,
// are not packed into a vector register and unpacked again between the stages); the empty asm
// keeps GCC's vectoriser from packing them back. Larger states, states sized at run time and
// SIMD lanes take the same operations in the same loop. Each component accumulates in a local value, not in the result
// vector: for lanes, a sum kept in the vector went through memory at every term, and the
// lanes' engine (bench/lanes_bench.cpp) took 1.4x as long.
template <int Count, const auto& Coef, class State, std::size_t S, class H>
inline void stage_input_into(const std::array<State, S>& k, const State& x, H h, State& out)
{
    using T = typename State::Scalar;
    [&]<int... J>(std::integer_sequence<int, J...>) {
        const H hc[] = {H(h * Coef[J])...};
        out.resize(x.size());
        for (Eigen::Index i = 0; i < x.size(); ++i) {
            T acc = x[i];
            ((Coef[J] != 0.0 ? (void)(acc = stage_term<T>(acc, hc[J], k[J][i])) : (void)0), ...);
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
            if constexpr (std::is_same_v<T, double> && State::RowsAtCompileTime != Eigen::Dynamic &&
                          State::RowsAtCompileTime <= 4)
                asm("" : "+v"(acc));
#endif
            out[i] = acc;
        }
    }(std::make_integer_sequence<int, Count>{});
}

template <int Count, const auto& Coef, class State, std::size_t S, class H>
inline State stage_input_ordered(const std::array<State, S>& k, const State& x, H h)
{
    State out = sized<State>(x.size());
    stage_input_into<Count, Coef>(k, x, h, out);
    return out;
}

// F(x) into out: through the field's own `into` where it has one (free_field, for models that
// write their field in place), else assigned.
template <class F, class State>
inline void evaluate_into(F& rhs, const State& x, State& out)
{
    if constexpr (requires { rhs.into(x, out); }) rhs.into(x, out);
    else out = rhs(x);
}

// What a step on states sized at run time keeps from one step to the next instead of
// allocating: a stage's input, the new state and its field, the error weights, an
// accumulator. Nothing for fixed sizes: the methods are then their stages alone
// (integrate/fused_step.hpp).
template <int N, class T>
struct run_time_vectors {
    vec_t<T, N> input, x_new, f_new, weights, sum;
};
struct no_vectors {};
template <int N, class T>
using step_vectors = std::conditional_t<N == Eigen::Dynamic && std::is_same_v<T, double>, run_time_vectors<N, T>, no_vectors>;

}  // namespace rk_detail

// Dormand & Prince's 5(4) pair (Hairer, Norsett & Wanner, Solving ODEs I, II.5): row s of A
// gives stage s from stages 0..s-1; B the 5th-order solution; E the difference of the 5th-
// and 4th-order weights over the 7 stages (the 7th is the FSAL stage f(x_new)).
namespace dopri5_tableau {
inline constexpr int stages = 6;
inline constexpr std::array<std::array<double, 6>, 6> A = {{
    {0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0},
    {44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0},
    {19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0},
    {9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0},
}};
inline constexpr std::array<double, 6> B = {35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0,
                                            11.0 / 84.0};
inline constexpr std::array<double, 7> E = {71.0 / 57600.0,      0.0,           -71.0 / 16695.0, 71.0 / 1920.0,
                                            -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0};
// Shampine's 4th-order interpolant: its last coefficient over the 7 stages.
inline constexpr std::array<double, 7> D = {-12715105075.0 / 11282082432.0, 0.0,
                                            87487479700.0 / 32700410799.0,  -10690763975.0 / 1880347072.0,
                                            701980252875.0 / 199316789632.0, -1453857185.0 / 822651844.0,
                                            69997945.0 / 29380423.0};
}  // namespace dopri5_tableau

// The methods are written once for a scalar type T: double, or lanes (core/lanes.hpp), where
// each lane is another job's step with its own step size. The stage inputs are summed
// component by component with explicit multiply-adds (stage_input_ordered), Eigen evaluates
// the other stage sums element by element as written (vectorised across the state for
// double), and the reductions (error norms) are spelled out in one order, so a lane computes
// exactly what a scalar step computes, provided the compiler does not fuse multiplications
// and additions differently in the two: the translation units that run lanes are compiled
// with -ffp-contract=off (CMakeLists.txt).
template <int N, class T = double>
class dopri5 {
public:
    static constexpr int order = 5;
    static constexpr int error_exponent_order = 5;  // error ~ h^5 for the embedded pair
    static constexpr int dense_terms = 4;
    static constexpr int stages_per_step = 6;       // FSAL: the 7th stage is the next step's first
    static constexpr int dense_extra_stages = 0;
    // The step-size controller's hold band unless the options give one (integrator_options):
    // DOPRI5's step is so short that the controller's logarithm and power, which the next trial
    // waits for, are a fifth of it; held steps skip them. At the paper's protocol point 0.77x
    // the time for the same error, and faster at every tolerance of the work-precision
    // diagram (docs/performance.md, "The hold band").
    static constexpr double default_hold_band = 0.1;
    static constexpr const char* name = "dopri5";
    using dense_type = dense_segment<N, 4>;
    using state = vec_t<T, N>;

    // Trial step from (x, f = F(x)); writes x_new and f_new = F(x_new); returns the squared
    // error norm err^2 = (1/N) sum_i (e_i / sc_i)^2 of the error estimate e (the step is
    // accepted for err^2 <= 1; the controller takes the square, integrate/step_control.hpp).
    // flatten: without it GCC leaves the stage sums out of line for larger states (the
    // tangent runs), and even the 4-state step is about 20 % slower.
    template <class F>
    VIMPACT_FLATTEN T attempt(F&& rhs, const state& x, const state& f, T h, double rtol, double atol,
                              state& x_new, state& f_new)
    {
        namespace Tab = dopri5_tableau;
        m_k[0] = f;
        [&]<int... S>(std::integer_sequence<int, S...>) {
            ((m_k[S + 1] = rhs(rk_detail::stage_input_ordered<S + 1, Tab::A[S + 1]>(m_k, x, h))), ...);
        }(std::make_integer_sequence<int, Tab::stages - 1>{});
        // The new state and its field are locals, written to x_new and f_new last: computed in
        // x_new, the state went through memory before its field was (GCC packs the stored
        // vector and reads the components back), and the protocol point took 1.06x as long.
        // Written last, x_new and f_new may also be x and f themselves.
        const state xn = rk_detail::stage_input_ordered<Tab::stages, Tab::B>(m_k, x, h);
        const state fn = rhs(xn);
        m_k[Tab::stages] = fn;
        const state w = error_weights<N, T>(x, xn, h, rtol, atol);
        const T err2 = T(weighted_square_sum<N>(rk_detail::combine<Tab::stages + 1, Tab::E>(m_k), w) * (1.0 / double(x.size())));
        x_new = xn;
        f_new = fn;
        return err2;
    }

    // Interpolant of the last accepted step (no extra right-hand side calls).
    template <class F>
    void build_dense(F&&, double t0, double h, const vec<N>& x0, const vec<N>& x1,
                     dense_type& out) const
    {
        out.t0 = t0;
        out.h = h;
        out.x0 = x0;
        const vec<N> dx = x1 - x0;
        const vec<N> bspl = h * m_k[0] - dx;
        out.c[0] = dx;
        out.c[1] = bspl;
        out.c[2] = dx - h * m_k[6] - bspl;
        out.c[3] = h * rk_detail::combine<7, dopri5_tableau::D>(m_k);
    }

    // The stages of the last step (what build_dense needs of it): a fused step computed
    // elsewhere (integrate/fused_step.hpp) or in a SIMD lane hands them over.
    static constexpr int stage_count = 7;
    [[nodiscard]] std::array<state, 7>& stages() { return m_k; }
    [[nodiscard]] const std::array<state, 7>& stages() const { return m_k; }

private:
    std::array<state, 7> m_k;
};

template <int N, class T = double>
class dop853 {
public:
    static constexpr int order = 8;
    static constexpr int error_exponent_order = 8;
    static constexpr int dense_terms = 7;
    static constexpr int stages_per_step = 12;
    static constexpr int dense_extra_stages = 3;
    // No hold band: with DOP853 it saves less time than it costs in accuracy
    // (docs/performance.md, "The hold band").
    static constexpr double default_hold_band = 0.0;
    static constexpr const char* name = "dop853";
    using dense_type = dense_segment<N, 7>;
    using state = vec_t<T, N>;

    // flatten: without it GCC leaves the stage sums out of line for larger states
    // (the tangent runs), and even the 4-state step is about 20 % slower.
    template <class F>
    VIMPACT_FLATTEN T attempt(F&& rhs, const state& x, const state& f, T h, double rtol, double atol,
                              state& x_new, state& f_new)
    {
        namespace Tab = dop853_tableau;
        if constexpr (N == Eigen::Dynamic && std::is_same_v<T, double>) {
            return attempt_in_place(rhs, x, f, h, rtol, atol, x_new, f_new);
        }
        m_k[0] = f;
        // Stages unrolled at compile time; zero tableau entries cost nothing.
        [&]<int... S>(std::integer_sequence<int, S...>) {
            ((m_k[S + 1] = rhs(rk_detail::stage_input_ordered<S + 1, Tab::A[S + 1]>(m_k, x, h))), ...);
        }(std::make_integer_sequence<int, Tab::stages - 1>{});
        // Locals first, as in dopri5::attempt.
        const state xn = rk_detail::stage_input_ordered<Tab::stages, Tab::B>(m_k, x, h);
        const state fn = rhs(xn);
        m_k[Tab::stages] = fn;
        // Hairer's error of DOP853, err = |h| s5 / sqrt(N (s5 + 0.01 s3)) with s5 and s3 the
        // squared sums of its 5th- and 3rd-order estimates over sc, squared: with the weights'
        // h folded into them (n5 = h^2 s5, n3 = h^2 s3), err^2 = n5^2 / (N (n5 + 0.01 n3)).
        const state w = error_weights<N, T>(x, xn, h, rtol, atol);
        const T n5 = weighted_square_sum<N>(rk_detail::combine<Tab::stages + 1, Tab::E5>(m_k), w);
        const T n3 = weighted_square_sum<N>(rk_detail::combine<Tab::stages + 1, Tab::E3>(m_k), w);
        x_new = xn;
        f_new = fn;
        // n5 = n3 = 0 (a field that vanishes): error 0, not 0/0.
        return select(n5 == T(0.0) && n3 == T(0.0), T(0.0), T(n5 * n5 / ((n5 + 0.01 * n3) * double(x.size()))));
    }

    // Needs three extra stages, so it is built only for steps where an event or a sample
    // falls. flatten, as attempt(): GCC otherwise leaves the three stage sums out of line
    // (2.6 % of the SIMD lanes' time on bench/lanes_bench.cpp, 1.7 % of the one-job path's).
    template <class F>
    VIMPACT_FLATTEN void build_dense(F&& rhs, double t0, double h, const vec<N>& x0, const vec<N>& x1,
                                     dense_type& out)
    {
        namespace Tab = dop853_tableau;
        if constexpr (N == Eigen::Dynamic && std::is_same_v<T, double>) {
            build_dense_in_place(rhs, t0, h, x0, x1, out);
            return;
        }
        [&]<int... S>(std::integer_sequence<int, S...>) {
            ((m_k[Tab::stages + 1 + S] = rhs(rk_detail::stage_input_ordered<Tab::stages + 1 + S, Tab::A[Tab::stages + 1 + S]>(m_k, x0, h))), ...);
        }(std::make_integer_sequence<int, Tab::stages_extended - Tab::stages - 1>{});
        out.t0 = t0;
        out.h = h;
        out.x0 = x0;
        const vec<N> dx = x1 - x0;
        out.c[0] = dx;
        out.c[1] = h * m_k[0] - dx;
        out.c[2] = 2.0 * dx - h * (m_k[Tab::stages] + m_k[0]);
        out.c[3] = h * rk_detail::combine<Tab::stages_extended, Tab::D[0]>(m_k);
        out.c[4] = h * rk_detail::combine<Tab::stages_extended, Tab::D[1]>(m_k);
        out.c[5] = h * rk_detail::combine<Tab::stages_extended, Tab::D[2]>(m_k);
        out.c[6] = h * rk_detail::combine<Tab::stages_extended, Tab::D[3]>(m_k);
    }

    // The stages of the last step (what build_dense needs of it): a fused step computed
    // elsewhere (integrate/fused_step.hpp) or in a SIMD lane hands them over.
    static constexpr int stage_count = dop853_tableau::stages_extended;
    [[nodiscard]] std::array<state, dop853_tableau::stages_extended>& stages() { return m_k; }
    [[nodiscard]] const std::array<state, dop853_tableau::stages_extended>& stages() const { return m_k; }

private:
    // attempt() and build_dense() on states sized at run time: the same operations in the same
    // order, every vector kept in m_k and m_vectors, so that a step allocates nothing.
    template <class F>
    T attempt_in_place(F& rhs, const state& x, const state& f, T h, double rtol, double atol, state& x_new,
                       state& f_new)
    {
        namespace Tab = dop853_tableau;
        auto& v = m_vectors;
        m_k[0] = f;
        [&]<int... S>(std::integer_sequence<int, S...>) {
            ((rk_detail::stage_input_into<S + 1, Tab::A[S + 1]>(m_k, x, h, v.input),
              rk_detail::evaluate_into(rhs, v.input, m_k[S + 1])),
             ...);
        }(std::make_integer_sequence<int, Tab::stages - 1>{});
        rk_detail::stage_input_into<Tab::stages, Tab::B>(m_k, x, h, v.x_new);
        rk_detail::evaluate_into(rhs, v.x_new, v.f_new);
        m_k[Tab::stages] = v.f_new;
        error_weights_into<N>(x, v.x_new, h, rtol, atol, v.weights);
        rk_detail::combine_into<Tab::stages + 1, Tab::E5>(m_k, v.input, v.sum);
        const T n5 = weighted_square_sum<N>(v.input, v.weights);
        rk_detail::combine_into<Tab::stages + 1, Tab::E3>(m_k, v.input, v.sum);
        const T n3 = weighted_square_sum<N>(v.input, v.weights);
        x_new = v.x_new;
        f_new = v.f_new;
        return select(n5 == T(0.0) && n3 == T(0.0), T(0.0), T(n5 * n5 / ((n5 + 0.01 * n3) * double(x.size()))));
    }

    template <class F>
    void build_dense_in_place(F& rhs, double t0, double h, const vec<N>& x0, const vec<N>& x1, dense_type& out)
    {
        namespace Tab = dop853_tableau;
        auto& v = m_vectors;
        [&]<int... S>(std::integer_sequence<int, S...>) {
            ((rk_detail::stage_input_into<Tab::stages + 1 + S, Tab::A[Tab::stages + 1 + S]>(m_k, x0, h, v.input),
              rk_detail::evaluate_into(rhs, v.input, m_k[Tab::stages + 1 + S])),
             ...);
        }(std::make_integer_sequence<int, Tab::stages_extended - Tab::stages - 1>{});
        out.t0 = t0;
        out.h = h;
        out.x0 = x0;
        vec<N>& dx = v.input;
        dx = x1 - x0;
        out.c[0] = dx;
        out.c[1] = h * m_k[0] - dx;
        out.c[2] = 2.0 * dx - h * (m_k[Tab::stages] + m_k[0]);
        // h times each sum, as h * combine(): the product commutes, so the same bits.
        [&]<int... J>(std::integer_sequence<int, J...>) {
            ((rk_detail::combine_into<Tab::stages_extended, Tab::D[J]>(m_k, out.c[3 + J], v.sum), out.c[3 + J] *= h),
             ...);
        }(std::make_integer_sequence<int, 4>{});
    }

    std::array<state, dop853_tableau::stages_extended> m_k;
    [[no_unique_address]] rk_detail::step_vectors<N, T> m_vectors;
};

}  // namespace vimpact
