#pragma once
// An interval of admissible values of a number a user gives: a model's parameter
// (model/spec.hpp), an analysis' option (core/option.hpp).
#include <cmath>
#include <limits>
#include <string>

#include "vimpact/core/format.hpp"

namespace vimpact {

inline constexpr double unbounded = std::numeric_limits<double>::infinity();

// An interval of admissible values; every bound optional, open or closed. Only finite numbers,
// unless the upper end is +inf and closed (or_infinite): a limit that may be none admits +inf.
struct value_range {
    double lower = -unbounded;
    double upper = unbounded;
    bool lower_inclusive = false;
    bool upper_inclusive = false;

    [[nodiscard]] bool admits(double v) const
    {
        if (v == unbounded && upper == unbounded && upper_inclusive) return true;
        if (!std::isfinite(v)) return false;
        if (lower_inclusive ? v < lower : v <= lower) return false;
        if (upper_inclusive ? v > upper : v >= upper) return false;
        return true;
    }

    // Whether either end is finite (an interval worth stating).
    [[nodiscard]] bool bounded() const { return std::isfinite(lower) || std::isfinite(upper); }

    // "(0, 1)", "> 0", "(0, inf]": the interval as every front end's message writes it.
    [[nodiscard]] std::string text() const
    {
        const bool has_lo = std::isfinite(lower);
        const bool has_hi = std::isfinite(upper);
        if (upper == unbounded && upper_inclusive)
            return std::string(lower_inclusive ? "[" : "(") + format_double(lower) + ", inf]";
        if (has_lo && has_hi)
            return std::string(lower_inclusive ? "[" : "(") + format_double(lower) + ", " + format_double(upper) +
                   (upper_inclusive ? "]" : ")");
        if (has_lo) return std::string(lower_inclusive ? ">= " : "> ") + format_double(lower);
        if (has_hi) return std::string(upper_inclusive ? "<= " : "< ") + format_double(upper);
        return "any finite number";
    }
};

constexpr value_range any_value() { return {}; }
constexpr value_range above(double a) { return {a, unbounded, false, false}; }
constexpr value_range at_least(double a) { return {a, unbounded, true, false}; }
constexpr value_range below(double b) { return {-unbounded, b, false, false}; }
constexpr value_range at_most(double b) { return {-unbounded, b, false, true}; }
constexpr value_range between(double a, double b) { return {a, b, true, true}; }  // closed
constexpr value_range inside(double a, double b) { return {a, b, false, false}; }   // open
// r with +inf admitted: (a, inf] for a limit whose default, +inf, means none.
constexpr value_range or_infinite(value_range r)
{
    r.upper = unbounded;
    r.upper_inclusive = true;
    return r;
}

}  // namespace vimpact
