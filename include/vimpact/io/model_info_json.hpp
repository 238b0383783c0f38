#pragma once
// What a model says about itself (model/model_info.hpp) as JSON, the one form every front end
// gives: the program's `models --json` and Python's Model.info. Keys: name, description,
// source, identity; state [{name, meaning, unit, period (null unless a phase)}]; initial_state;
// parameters [{name, meaning, unit, default, range {lower, upper (null when infinite),
// lower_inclusive, upper_inclusive, text}}]; surfaces [{name, meaning, sticks}]; sections
// [{name, meaning, direction}]; switches [{name, meaning, direction}]; presets [{name, meaning,
// values {parameter: value}}].
#include <nlohmann/json.hpp>

#include "vimpact/model/model_info.hpp"

namespace vimpact {

nlohmann::json model_info_json(const model_info& info);

}  // namespace vimpact
