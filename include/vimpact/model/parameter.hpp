#pragma once
// Named, range-checked model parameters. A model lists its parameters once (name, meaning,
// valid range); setting by name, validation and error messages all come from that list.
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <string_view>

#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"

namespace vimpact {

struct bound {
    double value = 0.0;
    bool inclusive = true;
    static constexpr bound none() { return {std::numeric_limits<double>::infinity(), false}; }
};

template <class Params>
struct parameter_info {
    std::string_view name;
    std::string_view meaning;
    double Params::*member;
    double lower;  // -inf for none
    bool lower_inclusive;
    double upper;  // +inf for none
    bool upper_inclusive;

    [[nodiscard]] bool admits(double v) const
    {
        if (!std::isfinite(v)) return false;
        if (lower_inclusive ? v < lower : v <= lower) return false;
        if (upper_inclusive ? v > upper : v >= upper) return false;
        return true;
    }

    [[nodiscard]] std::string range_text() const
    {
        const bool has_lo = std::isfinite(lower);
        const bool has_hi = std::isfinite(upper);
        if (has_lo && has_hi)
            return std::string(lower_inclusive ? "[" : "(") + format_double(lower) + ", " +
                   format_double(upper) + (upper_inclusive ? "]" : ")");
        if (has_lo) return std::string(lower_inclusive ? ">= " : "> ") + format_double(lower);
        if (has_hi) return std::string(upper_inclusive ? "<= " : "< ") + format_double(upper);
        return "any finite number";
    }
};

inline constexpr double unbounded = std::numeric_limits<double>::infinity();

// Throws input_error naming the first parameter outside its range.
template <class Params, std::size_t K>
void validate_parameters(const Params& p, const std::array<parameter_info<Params>, K>& table)
{
    for (const auto& info : table) {
        const double v = p.*(info.member);
        if (!info.admits(v))
            throw input_error("parameter " + std::string(info.name) + " = " + format_double(v) +
                              " is outside its valid range " + info.range_text() + " (" +
                              std::string(info.meaning) + ")");
    }
}

template <class Params, std::size_t K>
const parameter_info<Params>* find_parameter(const std::array<parameter_info<Params>, K>& table,
                                             std::string_view name)
{
    for (const auto& info : table)
        if (info.name == name) return &info;
    return nullptr;
}

template <class Params, std::size_t K>
std::string parameter_names(const std::array<parameter_info<Params>, K>& table)
{
    std::string out;
    for (const auto& info : table) {
        if (!out.empty()) out += ", ";
        out += info.name;
    }
    return out;
}

// Sets a parameter by name; the value is range-checked when the model is validated.
template <class Params, std::size_t K>
void set_parameter(Params& p, const std::array<parameter_info<Params>, K>& table,
                   std::string_view name, double value)
{
    const auto* info = find_parameter(table, name);
    if (!info)
        throw input_error("unknown parameter '" + std::string(name) +
                          "' (valid: " + parameter_names(table) + ")");
    p.*(info->member) = value;
}

}  // namespace vimpact
