#pragma once
// The checks of a physical input (a diameter, a density, a flow speed, a gap...): the value
// back when it is in range, else input_error naming it, "NAME (WHAT) must be a finite number
// > 0 (got V)", so that every physical input is refused in the same words.
namespace vimpact {

double positive_input(double v, const char* name, const char* what);      // finite, > 0
double non_negative_input(double v, const char* name, const char* what);  // finite, >= 0

}  // namespace vimpact
