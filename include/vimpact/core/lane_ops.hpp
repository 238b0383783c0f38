#pragma once
// The scalar side of generic code written once for double and for SIMD lanes (core/lanes.hpp):
// select, lane_max, lane_min, is_finite on doubles, and the bit-level helpers the step-size
// controller's polynomials use (integrate/step_control.hpp). No SIMD library here: the
// integrators include this, and a model file is compiled with them.
#include <bit>
#include <cmath>
#include <cstdint>

namespace vimpact {

struct lanes;  // core/lanes.hpp

inline double select(bool m, double a, double b) { return m ? a : b; }
inline bool any_of(bool m) { return m; }
inline bool all_of(bool m) { return m; }
// max/min with the comparison spelled out, so that NaN and signed zeros go the same way in a
// lane as on a scalar (a < b ? b : a).
inline double lane_max(double a, double b) { return a < b ? b : a; }
inline double lane_min(double a, double b) { return b < a ? b : a; }
inline bool is_finite(double d) { return std::isfinite(d); }

// The bit-level operations of T (double here; lanes in core/lanes.hpp).
template <class T>
struct lane_bits_ops;
template <>
struct lane_bits_ops<double> {
    static std::int64_t bits(double x) { return std::bit_cast<std::int64_t>(x); }
    static double from_bits(std::int64_t b) { return std::bit_cast<double>(b); }
    static double to_double(std::int64_t i) { return static_cast<double>(i); }
};

}  // namespace vimpact
