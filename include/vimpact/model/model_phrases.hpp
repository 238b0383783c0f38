#pragma once
// What a message says when a name is not among a model's: "model e has zeta, a, w", and for
// a model without any, "model e has no parameters" (never an empty list).
#include <string>

#include "vimpact/model/model_info.hpp"

namespace vimpact {

[[nodiscard]] std::string parameters_it_has(const model_info& m);
[[nodiscard]] std::string sections_it_has(const model_info& m);
[[nodiscard]] std::string surfaces_it_has(const model_info& m);

}  // namespace vimpact
