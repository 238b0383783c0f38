#pragma once
// What a message says when a name is not among a model's: "model e has zeta, a, w", and for
// a model without any, "model e has no parameters" (never an empty list).
#include <string>

#include "vimpact/model/model_info.hpp"

namespace vimpact {

class model;

[[nodiscard]] std::string parameters_it_has(const model_info& m);
[[nodiscard]] std::string sections_it_has(const model_info& m);
[[nodiscard]] std::string surfaces_it_has(const model_info& m);

// A front end's name of a parameter or state variable of m as its index, or input_error
// "unknown parameter 'q' for WHAT (model e has zeta, a, w)", "WHAT: 'q' is not one of x, v, phi
// (the state of model e)", WHAT the input as its user writes it (--param, param).
[[nodiscard]] int parameter_index(const model& m, const std::string& name, const std::string& what);
[[nodiscard]] int state_index(const model& m, const std::string& name, const std::string& what);

}  // namespace vimpact
