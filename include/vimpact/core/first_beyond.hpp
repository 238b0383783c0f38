#pragma once
// Where a floating-point difference first exceeds a span, so that a test repeated on every
// step, t - from > span, can be made once per stretch of steps as t >= first_beyond(from, span)
// with the same answer (the SIMD lanes' driver, hybrid/flow_lanes.hpp, compares a whole
// register of times at once this way).
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace vimpact {

namespace detail {

// Doubles in order as integers (-0 and +0 both 0), and back.
inline std::int64_t double_order(double x)
{
    const auto b = std::bit_cast<std::int64_t>(x);
    return b >= 0 ? b : std::numeric_limits<std::int64_t>::min() - b;
}
inline double ordered_double(std::int64_t k)
{
    return std::bit_cast<double>(k >= 0 ? k : std::numeric_limits<std::int64_t>::min() - k);
}

}  // namespace detail

// A time b such that t - from > span (rounded as doubles) is false for every t < b: the least
// t for which it is true when from, span and from + span are finite; +infinity for a finite
// from and span = +infinity (never true); otherwise -infinity (which claims nothing).
// Rounding is monotone in t, so the test is true for every t >= b.
inline double first_beyond(double from, double span)
{
    constexpr double inf = std::numeric_limits<double>::infinity();
    const double guess = from + span;
    if (std::isfinite(from) && span == inf) return inf;
    if (!std::isfinite(from) || !std::isfinite(span) || !std::isfinite(guess)) return -inf;
    const auto beyond = [&](double t) { return t - from > span; };
    // from + span is usually within an ulp or two of the answer.
    double t = guess;
    for (int k = 0; k < 4; ++k) {
        const double below = std::nextafter(t, -inf);
        if (beyond(t) && !beyond(below)) return t;
        t = beyond(t) ? below : std::nextafter(t, inf);
    }
    // Otherwise (the difference's resolution far coarser than t's, e.g. t near 0 and from
    // large): a bracket lo < answer <= hi around the guess, then bisection on the doubles in
    // order, at most 64 halvings.
    const double scale = std::ldexp(std::fmax(std::fabs(from), std::fmax(std::fabs(span), std::fabs(guess))), -50) +
                         std::numeric_limits<double>::denorm_min();
    double lo = guess, hi = guess;
    for (double d = scale; !beyond(hi); d *= 2.0) {
        hi = guess + d;
        if (!std::isfinite(hi)) return -inf;
    }
    for (double d = scale; beyond(lo); d *= 2.0) {
        lo = guess - d;
        if (!std::isfinite(lo)) return -inf;
    }
    std::int64_t a = detail::double_order(lo), b = detail::double_order(hi);
    while (static_cast<std::uint64_t>(b) - static_cast<std::uint64_t>(a) > 1) {
        const auto m = static_cast<std::int64_t>(static_cast<std::uint64_t>(a) +
                                                 (static_cast<std::uint64_t>(b) - static_cast<std::uint64_t>(a)) / 2);
        (beyond(detail::ordered_double(m)) ? b : a) = m;
    }
    return detail::ordered_double(b);
}

}  // namespace vimpact
