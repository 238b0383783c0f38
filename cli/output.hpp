#pragma once
// What every command shares when it reports: JSON pieces, the run record, CSV writers for
// section points and impacts, the PNG made by python/vimpact/plot.py, stdout printing.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common_options.hpp"
#include "vimpact/analysis/job_points.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/io/staged_output.hpp"

namespace vimpact::cli {

using json = nlohmann::json;

json stats_json(const run_stats& s);

// A JSON number, or null when it is not finite (JSON has no NaN or infinity).
json finite_or_null(double v);

// Calls f.template operator()<Method>() for the configured integrator (validated by resolve()).
template <class F>
decltype(auto) with_method(const std::string& method, F&& f)
{
    return with_integration_method(parse_integration_method(method, input_spelling::cli), std::forward<F>(f));
}

json record_header(const char* command, const run_config& c);
void write_json(const std::filesystem::path& p, const json& j);
void write_points(const std::filesystem::path& p, const std::vector<timed_state<4>>& pts);
void write_impacts(const std::filesystem::path& p, const std::vector<impact_event<4>>& imps);

// Runs `python3 -m vimpact.plot KIND DIR`. A missing matplotlib is reported, not fatal: the
// numbers are the result, the picture is a view of them.
bool make_plot(const char* kind, const std::filesystem::path& dir);

// Writes run.json, makes the PNG (unless --no-plot) and commits the staged directory.
void finish_output(staged_output& out, const char* kind, const run_config& c, json& record);

// --json: the summary object on one line; otherwise the text.
void print(const run_config& c, const json& summary, const std::string& text);

}  // namespace vimpact::cli
