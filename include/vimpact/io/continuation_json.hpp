#pragma once
// The JSON form of a continuation and its bifurcation curves, the one representation every
// front end gives: the program's --json and run.json, and the Python module's result. Keys:
//   param, range, status, start_label, tangent_maps, plain_maps;
//   branches: one list of points per branch, each point {param, stable, multipliers [[re, im]]
//     (trivial first), period, impacts, impacts_by_surface {surface: n}, state, section_points,
//     closure, arclength};
//   branch_info: per branch {returns, parent, origin, points, end, failure};
//   bifurcations: {type, param, branch, after_point, located, bracket, state, section_points, period,
//     multipliers, section_multipliers, surface, time, sequence_before, sequence_after};
//   with curves: param2, range2, curves: {type, origin, surface, start, end_backward,
//     end_forward, failure, points: [{param, param2, state, period, impacts_by_surface,
//     multipliers, section_multipliers, closure, condition}]}.
// Non-finite numbers are null.
#include <vector>

#include <nlohmann/json.hpp>

#include "vimpact/analysis/bifurcation_curve.hpp"
#include "vimpact/analysis/continuation.hpp"

namespace vimpact {

nlohmann::json continuation_json(const model& m, const continuation_options& o, const continuation_result& r);

// The same with the curves of a second parameter (o2 their options).
nlohmann::json continuation_json(const model& m, const continuation_options& o, const continuation_result& r,
                                 const curve_options& o2, const std::vector<bifurcation_curve>& curves);

}  // namespace vimpact
