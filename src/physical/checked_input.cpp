#include "vimpact/physical/checked_input.hpp"

#include <cmath>
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

}  // namespace vimpact
