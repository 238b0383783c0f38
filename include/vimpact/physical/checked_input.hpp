#pragma once
// The checks of a physical input (a diameter, a density, a flow speed, a gap...): the value
// back when it is in range, else input_error naming it, "NAME (WHAT) must be a finite number
// > 0 (got V)", so that every physical input is refused in the same words.
#include <initializer_list>
#include <utility>

namespace vimpact {

double positive_input(double v, const char* name, const char* what);      // finite, > 0
double non_negative_input(double v, const char* name, const char* what);  // finite, >= 0

// A quantity derived from inputs that are each in range but together too large or too small
// for a double (D = 1e300 squares to infinity): the value back when it is finite and, unless
// 0 (`zero_ok`), of magnitude in [2.2e-308, 1.8e308]; else input_error naming the quantity,
// the inputs it comes from with their values, and that range.
using input_value = std::pair<const char*, double>;
double derived_value(double v, const char* name, std::initializer_list<input_value> from, bool zero_ok = false);

}  // namespace vimpact
