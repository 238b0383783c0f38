#include "vimpact/physical/checked_input.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"

namespace vimpact {

namespace {

[[noreturn]] void refuse(double v, const char* name, const char* what, const char* range)
{
    throw input_error(std::string(name) + " (" + what + ") must be a finite number " + range + " (got " +
                      format_double(v) + ")");
}

}  // namespace

double positive_input(double v, const char* name, const char* what)
{
    if (!(v > 0.0) || !std::isfinite(v)) refuse(v, name, what, "> 0");
    return v;
}

double non_negative_input(double v, const char* name, const char* what)
{
    if (!(v >= 0.0) || !std::isfinite(v)) refuse(v, name, what, ">= 0");
    return v;
}

double derived_value(double v, const char* name, std::initializer_list<input_value> from, bool zero_ok)
{
    const double a = std::abs(v);
    const bool zero = v == 0.0;
    if (std::isfinite(v) && (zero ? zero_ok : a >= std::numeric_limits<double>::min())) return v;
    std::string inputs;
    for (const auto& [n, x] : from) inputs += (inputs.empty() ? "" : ", ") + std::string(n) + " = " + format_double(x);
    throw input_error(std::string(name) + " = " + format_double(v) + " from " + inputs +
                      " is outside the range of a double: the inputs must keep its magnitude in [" +
                      format_double(std::numeric_limits<double>::min()) + ", " +
                      format_double(std::numeric_limits<double>::max()) + "]" + (zero_ok ? " or 0" : ""));
}

}  // namespace vimpact
