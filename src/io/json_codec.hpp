#pragma once
// JSON forms of the library's values, for the journals of many-job runs: what identifies a
// run (the model and every option that changes a result) and each job's record, read back
// bit for bit (doubles in shortest round-trip form, non-finite numbers as strings).
#include <nlohmann/json.hpp>

#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/lyapunov.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/value_grid.hpp"

namespace vimpact::detail {

using json = nlohmann::json;

json number(double v);  // a finite number, or "nan", "inf", "-inf"
double number_from(const json& j);
json numbers(const std::vector<double>& v);
// A range as {"from", "to", "n"}, a list as its numbers; a mapped grid adds "map" (a list then
// goes under "values"): what a run's spec says of an axis, never its values one by one.
json to_json(const value_grid& g);
std::vector<double> numbers_from(const json& j);
json vector_json(const Eigen::VectorXd& v);
Eigen::VectorXd vector_from(const json& j);

json to_json(const model& m);  // identity and parameter values
json to_json(const integrator_options& o);
json to_json(const flow_options& o);  // the settings; events and surfaces belong to the analysis
json to_json(const section_choice& s);
json to_json(const protocol_options& o);
json to_json(const grazing_options& o);
json to_json(const floquet_options& o);
json to_json(const lyapunov_options& o);

json to_json(const impact_statistics& s);
impact_statistics statistics_from(const json& j);
json to_json(const period_label& l);
period_label label_from(const json& j);
json to_json(const state_series& s);
state_series series_from(const json& j);
outcome outcome_from(const json& j);

}  // namespace vimpact::detail
