#pragma once
// Options every command shares, and their resolution into a checked configuration: the
// model, then its preset, the config file, --set and --ic; each step names what it rejects.
// Names (parameters, state variables, sections, surfaces) are looked up here, once; the
// library gets indices.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/model/model.hpp"
#include "vimpact/model/model_phrases.hpp"
#include "vimpact/physical/si_units.hpp"

namespace vimpact::cli {

struct common_args {
    std::string model = "wake_impact";
    std::string preset;
    std::vector<std::string> sets;
    std::string ic;
    std::string config;
    std::string section;
    // The protocol's declared options (analysis/protocol_declaration.hpp) as given on the
    // command line, else their defaults; resolve() applies the config file between the two.
    protocol_options protocol;
    std::string out;
    bool json = false;
    bool no_plot = false;
    std::string format = "png";
    std::string si;  // --si KEY=VALUE,...: the run in SI units (physical/si_units.hpp)
    CLI::Option* model_option = nullptr;
    CLI::Option* preset_option = nullptr;
    CLI::Option* section_option = nullptr;
    const CLI::App* command = nullptr;  // the command these options belong to
};

struct run_config {
    vimpact::model model;
    std::string preset;  // empty: the model's defaults
    Eigen::VectorXd ic;  // the model's initial state unless --ic or the config file set it
    protocol_options protocol;
    std::optional<std::filesystem::path> out;
    bool json = false;
    bool plot = true;
    std::string plot_format = "png";  // the picture's file type: png, pdf or svg
    std::string command;                // for config.toml: the command and its own options
    nlohmann::json command_options;
    bool describes_run = true;          // false: no run of the model (dimension of a points file)
    bool config_sets_run = false;       // the config file set up the run (model, parameters, ...)
    // How the picture is drawn (sweep's --color-by): run.json's plot_options, which
    // `python3 -m vimpact.plot` passes to the drawing function, so a directory redraws alike.
    nlohmann::json plot_options = nlohmann::json::object();
    // --si: the engineer's inputs; `model` has the parameters they set.
    std::optional<si_input> si;

    [[nodiscard]] const model_info& info() const { return model.info(); }
    [[nodiscard]] std::string section_name() const { return section_choice_name(model, protocol.section); }
    // The effective configuration, for run.json.
    [[nodiscard]] nlohmann::json to_json() const;
};

void add_common_options(CLI::App& app, common_args& args);
// Whether the command line (its options, config.toml's top level, run.json) sets the protocol's
// declared option `key`: all but quiet_time and t_max, whose defaults every command keeps.
bool command_line_sets(std::string_view key);
// Those options' keys, in the order of the declaration.
const std::vector<std::string>& protocol_keys();
// Their values in `p` as config.toml and run.json record them, {key: value}: the hold band the
// run used (given, or its method's when that holds), so that a replay holds alike whatever the
// default then; a limit that is none (inf) left out.
nlohmann::json protocol_settings(const protocol_options& p);
// --si on the commands where SI units make sense (docs/engineering.md lists them).
void add_si_option(CLI::App& app, common_args& args);
// The warnings of the SI inputs at the model `m` (a cylinder outside the wake model's
// calibrated range), each printed once per call to stderr; returns them.
std::vector<std::string> warn_validity(const run_config& c, const std::vector<vimpact::model>& at);

// Checks --out first (nothing is computed for a bad target), then loads the model and applies
// everything else. Throws input_error for anything invalid.
run_config resolve(const common_args& args);

// --si KEY=VALUE,...: the SI inputs (physical/si_units.hpp); a mistake is "--si: ..." and the
// library's words.
si_input parse_si(const std::string& text);

// A parameter axis (--param with --range, --x, --y): a model parameter by name or, with --si,
// an SI quantity (U [m/s], gap [m]) as the model parameter it sets (physical/si_units.hpp).
// The SI values are kept for the tables' SI column (named si_name).
struct axis_values {
    int parameter = -1;
    value_grid values;     // of the model parameter (the SI values mapped, value by value)
    value_grid si_values;  // as given, when the axis is an SI quantity
    std::string si_name;   // U or gap, else empty

    [[nodiscard]] bool si() const { return !si_name.empty(); }
    // The SI value where the parameter is v: the one given for one of `values`, else converted
    // back (a continuation's points lie between them).
    [[nodiscard]] double si_at(const run_config& c, double v) const;
};
axis_values resolve_axis(const run_config& c, const std::string& name, const value_grid& given,
                         const std::string& what);

// Throws input_error unless the initial state is admissible (on the allowed side of every
// surface), naming the surface.
void check_admissible(const run_config& c);

// A TOML config file; throws input_error naming the file and the line of a syntax error.
toml::table read_config(const std::string& file);
// A config file's value as messages show it: true, 3, 'abc' (control characters as ?), a list.
std::string toml_shown(const toml::node& node);


// A model by built-in name or file (.toml, .json, shared library); a relative file name is
// taken relative to `base`.
vimpact::model load_model(const std::string& spec, const std::filesystem::path& base = {});
// The model a config file's key `model` names, a relative file taken relative to the config
// file; a shared library is refused (it is loaded only when given on the command line).
vimpact::model load_config_model(const std::string& spec, const std::string& file);

// "y, ydot, x, xdot" -> the JSON object {name: value} of a vector over the model's parameters.
nlohmann::json parameters_json(const vimpact::model& m);

}  // namespace vimpact::cli
