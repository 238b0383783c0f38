#pragma once
// SIMD lanes: `lanes` holds one double per job of a batch (as many as the lanes' vector
// register holds: 8 with AVX-512 in the default build, 4 with AVX2, below), so that the same
// arithmetic runs for several jobs at once. Generic code is written once for a scalar type T,
// double or lanes, with the helpers below (select, any_of, lane_max...): every lane then goes
// through exactly the operations the scalar code does, in the same order, and gets the same
// bits. That is why functions that are not correctly rounded in IEEE arithmetic (sin, exp,
// pow...) are evaluated lane by lane with the standard library's scalar function, not with a
// vectorised approximation: a model's vector field gives the same numbers in a lane as on its
// own. +, -, *, /, sqrt, fma, min, max and abs are exact operations and run vectorised.
//
// A model definition opts in to lanes with `static constexpr bool simd_lanes = true;`
// (model/definition.hpp): its templated functions must then compile for T = lanes, i.e. call
// mathematical functions unqualified or through `using std::sin;` (argument-dependent lookup
// finds the ones below) and not branch on the value of a T.
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <immintrin.h>

#include <xsimd/xsimd.hpp>

#include <Eigen/Core>

#include "vimpact/core/lane_ops.hpp"

namespace vimpact {

// The registers the lanes use: the widest the library is compiled for, except that on a
// processor with AVX-512 they are 256-bit registers (4 lanes) unless VIMPACT_LANES_512 is
// defined (CMake's VIMPACT_LANES_512, on by default where the compiler is GCC 12 or later,
// which has -mmove-max: 8 lanes of 512 bits). The 512-bit lanes pay only when the compiler moves a 64-byte value in one
// piece: GCC's tuning for these processors copies it as two 32-byte halves, the upper half read
// back from the 512-bit store that wrote it, which waits for that store (a failed store
// forward) in every stage of a trial. Measured on the development machine
// (docs/performance.md): 8 lanes moved whole ran the lanes' engine 2.5x the speed of one job at
// a time, 4 lanes 2.0x to 2.2x, 8 lanes moved in halves 1.9x. CMake compiles the library's
// lanes (src/instances/*_lanes.cpp) with -mmove-max=512 -mstore-max=512; a program running its
// own definition in lanes should too (docs/own-model.md).
#if defined(__AVX512F__) && !defined(VIMPACT_LANES_512)
using lane_arch = xsimd::avx2;
#else
using lane_arch = xsimd::default_arch;
#endif
using lane_batch = xsimd::batch<double, lane_arch>;
// The number of lanes: 1 means no SIMD wider than one double, and the job commands run scalar.
inline constexpr int lane_width = static_cast<int>(lane_batch::size);
// Lanes are worth their bookkeeping from 4 doubles a register on (AVX2 and wider).
inline constexpr bool wide_lanes = lane_width >= 4;

struct lane_mask {
    xsimd::batch_bool<double, lane_arch> m;
    friend lane_mask operator&&(lane_mask a, lane_mask b) { return {a.m && b.m}; }
    friend lane_mask operator||(lane_mask a, lane_mask b) { return {a.m || b.m}; }
    friend lane_mask operator!(lane_mask a) { return {!a.m}; }
};

struct lanes {
    lane_batch v;
    lanes() = default;
    lanes(double d) : v(d) {}  // NOLINT: a double is the same in every lane
    lanes(lane_batch b) : v(b) {}

    static lanes load(const double* p) { return {lane_batch::load_unaligned(p)}; }
    void store(double* p) const { v.store_unaligned(p); }
    // Lane i, read where the value lies in memory. Indexing a copy of the register instead made
    // GCC store all of it and load one double back from that store, which then waits for the
    // store (a failed store forward): about 5 % of the lanes' time, where a lane's stages are
    // gathered for its interpolant (hybrid/flow_lanes.hpp). The doubles of a batch lie in lane
    // order.
    [[nodiscard]] double lane(int i) const
    {
        static_assert(sizeof(lane_batch) == sizeof(double) * lane_batch::size);
        double d;
        std::memcpy(&d, reinterpret_cast<const unsigned char*>(&v) + sizeof(double) * static_cast<std::size_t>(i),
                    sizeof d);
        return d;
    }

    lanes& operator+=(const lanes& o) { v += o.v; return *this; }
    lanes& operator-=(const lanes& o) { v -= o.v; return *this; }
    lanes& operator*=(const lanes& o) { v *= o.v; return *this; }
    lanes& operator/=(const lanes& o) { v /= o.v; return *this; }
    friend lanes operator+(const lanes& a, const lanes& b) { return {a.v + b.v}; }
    friend lanes operator-(const lanes& a, const lanes& b) { return {a.v - b.v}; }
    friend lanes operator*(const lanes& a, const lanes& b) { return {a.v * b.v}; }
    friend lanes operator/(const lanes& a, const lanes& b) { return {a.v / b.v}; }
    friend lanes operator-(const lanes& a) { return {-a.v}; }
    friend lanes operator+(const lanes& a) { return a; }
    friend lane_mask operator<(const lanes& a, const lanes& b) { return {a.v < b.v}; }
    friend lane_mask operator<=(const lanes& a, const lanes& b) { return {a.v <= b.v}; }
    friend lane_mask operator>(const lanes& a, const lanes& b) { return {a.v > b.v}; }
    friend lane_mask operator>=(const lanes& a, const lanes& b) { return {a.v >= b.v}; }
    friend lane_mask operator==(const lanes& a, const lanes& b) { return {a.v == b.v}; }
    friend lane_mask operator!=(const lanes& a, const lanes& b) { return {a.v != b.v}; }
};

// ---- the lanes side of the helpers of generic code (core/lane_ops.hpp) ----------------------
inline lanes select(lane_mask m, const lanes& a, const lanes& b) { return {xsimd::select(m.m, a.v, b.v)}; }
inline bool any_of(lane_mask m) { return xsimd::any(m.m); }
inline bool all_of(lane_mask m) { return xsimd::all(m.m); }
// Bit i set when lane i is true: the mask register itself where the instruction set has one.
inline unsigned lane_bits(lane_mask m)
{
#if defined(__AVX512F__) && defined(VIMPACT_LANES_512)
    return static_cast<unsigned>(static_cast<__mmask8>(m.m));
#elif defined(__AVX__)
    if constexpr (lane_width == 4) return static_cast<unsigned>(_mm256_movemask_pd(m.m));
#endif
    alignas(64) std::array<double, lane_width> a;
    xsimd::select(m.m, lane_batch(1.0), lane_batch(0.0)).store_aligned(a.data());
    unsigned bits = 0;
    for (int i = 0; i < lane_width; ++i)
        if (a[static_cast<std::size_t>(i)] != 0.0) bits |= 1U << static_cast<unsigned>(i);
    return bits;
}
inline lanes lane_max(const lanes& a, const lanes& b) { return select(a < b, b, a); }
inline lanes lane_min(const lanes& a, const lanes& b) { return select(b < a, b, a); }
inline lane_mask is_finite(const lanes& l) { return {xsimd::isfinite(l.v)}; }

template <>
struct lane_bits_ops<lanes> {
    using ints = xsimd::batch<std::int64_t, lane_arch>;
    static ints bits(const lanes& x) { return xsimd::bitwise_cast<ints>(x.v); }
    static lanes from_bits(const ints& b) { return {xsimd::bitwise_cast<lane_batch>(b)}; }
    // Exact for the exponents fast_log2 converts (|i| < 2^53). xsimd 8.1 has no AVX-512 DQ
    // conversion: its fallback copies through memory, which GCC vectorises as two 256-bit
    // halves read back as one 512-bit value, waiting for both stores (a failed store forward)
    // in every trial's controller. AVX-512 DQ converts all eight in one instruction.
    static lanes to_double(const ints& i)
    {
#if defined(__AVX512DQ__) && defined(VIMPACT_LANES_512)
        return {lane_batch(_mm512_cvtepi64_pd(i))};
#else
        return {xsimd::batch_cast<double>(i)};
#endif
    }
};

// ---- exact operations, vectorised ------------------------------------------------------------
inline lanes sqrt(const lanes& a) { return {xsimd::sqrt(a.v)}; }
inline lanes abs(const lanes& a) { return {xsimd::abs(a.v)}; }
inline lanes fabs(const lanes& a) { return {xsimd::abs(a.v)}; }
// Fused in one rounding, as std::fma: xsimd 8 has no fused kernel for AVX-512 (it multiplies,
// then adds), so the instruction is named here.
inline lanes fma(const lanes& a, const lanes& b, const lanes& c)
{
#if defined(__AVX512F__) && defined(VIMPACT_LANES_512)
    static_assert(lane_width == 8);
    return {lane_batch(_mm512_fmadd_pd(a.v, b.v, c.v))};
#elif defined(__AVX__) && defined(__FMA__)
    static_assert(lane_width == 4);
    return {lane_batch(_mm256_fmadd_pd(a.v, b.v, c.v))};
#else
    alignas(64) std::array<double, lane_width> x, y, z;
    a.v.store_aligned(x.data());
    b.v.store_aligned(y.data());
    c.v.store_aligned(z.data());
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::fma(x[i], y[i], z[i]);
    return {lane_batch::load_aligned(x.data())};
#endif
}

// ---- everything else lane by lane, with the scalar function ----------------------------------
namespace detail {
template <class F>
lanes per_lane(F&& f, const lanes& a)
{
    alignas(64) std::array<double, lane_width> x;
    a.v.store_aligned(x.data());
    for (auto& e : x) e = f(e);
    return {lane_batch::load_aligned(x.data())};
}
template <class F>
lanes per_lane(F&& f, const lanes& a, const lanes& b)
{
    alignas(64) std::array<double, lane_width> x, y;
    a.v.store_aligned(x.data());
    b.v.store_aligned(y.data());
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = f(x[i], y[i]);
    return {lane_batch::load_aligned(x.data())};
}
}  // namespace detail

#define VIMPACT_LANES_UNARY(fn)                                                                  \
    inline lanes fn(const lanes& a) { return detail::per_lane([](double x) { return std::fn(x); }, a); }
VIMPACT_LANES_UNARY(sin)
VIMPACT_LANES_UNARY(cos)
VIMPACT_LANES_UNARY(tan)
VIMPACT_LANES_UNARY(asin)
VIMPACT_LANES_UNARY(acos)
VIMPACT_LANES_UNARY(atan)
VIMPACT_LANES_UNARY(sinh)
VIMPACT_LANES_UNARY(cosh)
VIMPACT_LANES_UNARY(tanh)
VIMPACT_LANES_UNARY(exp)
VIMPACT_LANES_UNARY(expm1)
VIMPACT_LANES_UNARY(log)
VIMPACT_LANES_UNARY(log1p)
VIMPACT_LANES_UNARY(cbrt)
#undef VIMPACT_LANES_UNARY
inline lanes pow(const lanes& a, const lanes& b)
{
    return detail::per_lane([](double x, double y) { return std::pow(x, y); }, a, b);
}
inline lanes atan2(const lanes& a, const lanes& b)
{
    return detail::per_lane([](double x, double y) { return std::atan2(x, y); }, a, b);
}
inline lanes hypot(const lanes& a, const lanes& b)
{
    return detail::per_lane([](double x, double y) { return std::hypot(x, y); }, a, b);
}

}  // namespace vimpact

// Eigen holds lanes in its fixed-size vectors (a model's vec_t<lanes, N>): element-wise
// arithmetic only, no vectorisation of its own across them.
namespace Eigen {
template <>
struct NumTraits<vimpact::lanes> : GenericNumTraits<double> {
    using Real = vimpact::lanes;
    using NonInteger = vimpact::lanes;
    using Literal = double;
    using Nested = vimpact::lanes;
    enum { IsComplex = 0, IsInteger = 0, IsSigned = 1, RequireInitialization = 0, ReadCost = 1, AddCost = 1, MulCost = 1 };
};
template <>
struct ScalarBinaryOpTraits<vimpact::lanes, double> {
    using ReturnType = vimpact::lanes;
};
template <>
struct ScalarBinaryOpTraits<double, vimpact::lanes> {
    using ReturnType = vimpact::lanes;
};
}  // namespace Eigen
