#include "common_options.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <toml++/toml.h>

#include "interrupts.hpp"
#include "output.hpp"
#include "parse.hpp"
#include "declared_options.hpp"
#include "replay.hpp"
#include "vimpact/analysis/protocol_declaration.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/core/names.hpp"
#include "vimpact/io/staged_output.hpp"
#include "vimpact/model/model_file.hpp"
#include "vimpact/model/model_phrases.hpp"

namespace fs = std::filesystem;

namespace vimpact::cli {

namespace {

std::string joined(const std::vector<std::string>& v)
{
    std::string s;
    for (const auto& x : v) {
        if (!s.empty()) s += ", ";
        s += x;
    }
    return s;
}

}  // namespace

// The protocol's time limits stay at their defaults on the command line: a run that needs
// longer is given a longer transient or record, and grazing's --t-max is its own run's.
bool command_line_sets(std::string_view key) { return key != "quiet_time" && key != "t_max"; }

const std::vector<std::string>& protocol_keys()
{
    static const std::vector<std::string> keys = [] {
        std::vector<std::string> k;
        const auto collect = [&k](const option& o, const auto&...) {
            if (command_line_sets(o.key)) k.emplace_back(o.key);
        };
        const protocol_options defaults{};
        declare(collect, defaults);
        return k;
    }();
    return keys;
}

nlohmann::json protocol_settings(const protocol_options& p)
{
    protocol_options shown = p;
    const double band = effective_hold_band(p.flow.integration, p.method);
    if (p.flow.integration.hold_band || band > 0.0) shown.flow.integration.hold_band = band;
    return declared_settings(shown, command_line_sets);
}

void add_common_options(CLI::App& app, common_args& a)
{
    a.model_option = app.add_option("--model", a.model,
                                    "The model: a built-in name (default wake_impact; `vimpact models` lists them), a "
                                    "model file NAME.toml or a shared library");
    a.preset_option = app.add_option("--preset", a.preset, "A parameter preset of the model");
    app.add_option("--set", a.sets, "Set a parameter of the model, KEY=VALUE (repeatable)")->allow_extra_args(false);
    app.add_option("--ic", a.ic, "Initial state: the model's state variables in order, comma-separated");
    a.command = &app;
    app.add_option("--config", a.config,
                   "TOML file with the same settings: model, preset, parameters by name (or in a table "
                   "[parameters]), ic = [..], " + joined(protocol_keys()) + ", section, and the command's own "
                   "options in a table named after it; every --out directory holds one (config.toml) that "
                   "replays the run");
    detail::option_adder adder{app};
    const auto add = [&](const option& o, auto&... member) {
        if (command_line_sets(o.key)) adder(o, member...);
    };
    declare(add, a.protocol);
    a.section_option = app.add_option("--section", a.section,
                                      "Where points are recorded: a section of the model (default its first), impacts "
                                      "(after every impact) or impacts:SURFACE");
    app.add_option("--out", a.out, "Write CSV files, run.json and a picture (--format) to this directory");
    app.add_flag("--json", a.json, "Print one JSON object to stdout");
    app.add_flag("--no-plot", a.no_plot, "With --out: skip the picture");
    app.add_option("--format", a.format, "With --out: the picture's format, png (default), pdf or svg");
}

void add_si_option(CLI::App& app, common_args& a)
{
    app.add_option("--si", a.si,
                   "The run in SI units: a cylinder in a flow D=..,m=..,fn=..,zeta=..,rho=.. [m, kg/m, Hz, -, kg/m^3] "
                   "(mstar=.. mass ratio for m, k=.. stiffness per length [N/m^2] for fn; CM, St, nu, CL0 optional) for "
                   "the wake model, or length=..,time=..[,mass=..] (one model unit in m, s, kg) for any model; U=.. "
                   "(flow speed, m/s) and gap=.. (m, rest state to the surface) set Ur and the gap parameter; results "
                   "also in SI (docs/engineering.md)");
}

si_input parse_si(const std::string& text)
{
    const auto pairs = parse_pairs(text, "--si");
    try {
        return si_from_pairs(pairs);
    } catch (const input_error& e) {
        throw input_error(std::string("--si: ") + e.what());
    }
}

axis_values resolve_axis(const run_config& c, const std::string& name, const value_grid& given,
                         const std::string& what)
{
    axis_values a;
    if (c.si && (name == "U" || name == "gap")) {
        a.parameter = si_parameter(*c.si, c.model, name);
        a.si_name = name;
        a.si_values = given;
        a.values = si_parameter_grid(*c.si, c.model, name, given);
        return a;
    }
    a.parameter = parameter_index(c.model, name, what);
    a.values = given;
    return a;
}

double axis_values::si_at(const run_config& c, double v) const
{
    // A range of U or gap maps to monotone parameter values: found by bisection, not by a
    // scan of the axis for every row of a long sweep.
    const std::size_t n = values.size();
    if (n > 0) {
        const bool rising = values[n - 1] >= values[0];
        std::size_t lo = 0, hi = n - 1;
        while (lo < hi) {
            const std::size_t mid = lo + (hi - lo) / 2;
            if (values[mid] != v && (values[mid] < v) == rising) lo = mid + 1;
            else hi = mid;
        }
        if (values[lo] == v) return si_values[lo];
        if (!values.is_range())
            for (std::size_t i = 0; i < n; ++i)
                if (values[i] == v) return si_values[i];
    }
    return si_quantity_value(*c.si, c.model, si_name, v);
}

std::vector<std::string> warn_validity(const run_config& c, const std::vector<vimpact::model>& at)
{
    std::vector<std::string> out;
    if (!c.si) return out;
    for (const auto& m : at)
        for (const auto& w : validity_warnings(*c.si, m))
            if (std::find(out.begin(), out.end(), w) == out.end()) out.push_back(w);
    for (const auto& w : out) std::cerr << "vimpact: warning: " << w << '\n';
    return out;
}

namespace {

bool is_builtin(const std::string& name)
{
    const auto names = model::builtin_names();
    return std::find(names.begin(), names.end(), name) != names.end();
}

section_choice parse_section(const model& m, const std::string& s)
{
    if (const auto choice = section_choice_named(m, s)) return *choice;
    throw input_error("--section '" + s + "' is not one of " + section_choice_names(m) + " (model " + m.name() + ")");
}

std::string config_where(const std::string& file) { return "config " + file; }

}  // namespace

std::string toml_shown(const toml::node& node)
{
    if (const auto v = node.value_exact<bool>()) return *v ? "true" : "false";
    if (const auto v = node.value_exact<int64_t>()) return std::to_string(*v);
    if (const auto v = node.value_exact<double>()) return format_double(*v);
    if (const auto v = node.value_exact<std::string>()) {
        std::string shown;
        for (const char ch : *v) shown += static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f ? '?' : ch;
        return "'" + shown + "'";
    }
    if (node.is_array()) return "a list";
    if (node.is_table()) return "a table";
    return "a date or time";
}

namespace {

double toml_number(const toml::node& node, const std::string& key, const std::string& file)
{
    // Exact types: toml++ would read true as 1.
    if (auto v = node.value_exact<double>()) return *v;
    if (auto v = node.value_exact<int64_t>()) return static_cast<double>(*v);
    throw input_error(config_where(file) + ": key '" + key + "' must be a number (got " + toml_shown(node) + ")");
}

long toml_integer(const toml::node& node, const std::string& key, const std::string& file)
{
    if (auto v = node.value_exact<int64_t>()) return static_cast<long>(*v);
    if (auto v = node.value_exact<double>(); v && *v == std::floor(*v) && std::abs(*v) < 1e15)
        return static_cast<long>(*v);
    throw input_error(config_where(file) + ": key '" + key + "' must be an integer (got " + toml_shown(node) + ")");
}

std::string toml_string(const toml::node& node, const std::string& key, const std::string& file)
{
    if (auto v = node.value_exact<std::string>()) return *v;
    throw input_error(config_where(file) + ": key '" + key + "' must be a string (got " + toml_shown(node) + ")");
}

// The keys a config file may have besides the model's parameters.
std::vector<std::string> setting_keys()
{
    std::vector<std::string> keys{"model", "model_identity", "preset", "ic"};
    keys.insert(keys.end(), protocol_keys().begin(), protocol_keys().end());
    keys.insert(keys.end(), {"section", "[parameters]"});
    return keys;
}

// The protocol's options from a config file's top level, each checked against its declared
// range where it is read, so that a mistake names the file (even one the command line
// overrides); an option given on the command line wins (its value is already in the options).
struct protocol_config_reader {
    const toml::table& cfg;
    const CLI::App& command;
    const std::string& file;

    [[nodiscard]] const toml::node* node(const option& o) const
    {
        return command_line_sets(o.key) ? cfg.get(o.key) : nullptr;
    }
    template <class T>
    void set(const option& o, T& member, const T& value) const
    {
        try {
            check_option(o, value);
        } catch (const input_error& e) {
            throw input_error(config_where(file) + ": " + e.what());
        }
        if (command.get_option(command_line_key(o.key))->count() == 0) member = value;
    }
    template <class T>
    void operator()(const option& o, T& member) const
    {
        if (const toml::node* n = node(o)) {
            const std::string key(o.key);
            if constexpr (std::is_integral_v<T>) set(o, member, static_cast<T>(toml_integer(*n, key, file)));
            else set(o, member, T(toml_number(*n, key, file)));
        }
    }
    template <class E, std::size_t K>
    void operator()(const option& o, E& member, const std::array<E, K>& all) const
    {
        if (const toml::node* n = node(o)) {
            const std::string key(o.key);
            const std::string name = toml_string(*n, key, file);
            try {
                set(o, member, parse_name(name, all, key));
            } catch (const input_error& e) {
                throw input_error(config_where(file) + ": " + e.what());
            }
        }
    }
};

}  // namespace

toml::table read_config(const std::string& file)
{
    std::error_code ec;
    if (fs::is_directory(file, ec)) throw input_error("cannot read config file '" + file + "': it is a directory");
    if (!fs::exists(file, ec) || ::access(file.c_str(), R_OK) != 0)
        throw input_error("cannot read config file '" + file + "'");
    try {
        return toml::parse_file(file);
    } catch (const toml::parse_error& e) {
        throw input_error(config_where(file) + ": " + std::string(e.description()) + " (line " +
                          std::to_string(e.source().begin.line) + ")");
    }
}

model load_model(const std::string& spec, const fs::path& base)
{
    if (spec.empty()) throw input_error("--model needs a model name or file");
    if (is_builtin(spec)) return model::builtin(spec);
    fs::path path(spec);
    std::error_code ec;
    const bool file_like = spec.find('/') != std::string::npos || path.has_extension() || fs::exists(path, ec);
    if (!file_like) return model::builtin(spec);  // the message lists the built-ins
    if (path.is_relative() && !base.empty()) path = base / path;
    // Ctrl-C stops a model file's compilation at once (exit 130, nothing left in the cache).
    return model::with_defaults(load_model_code(path, &interrupt_flag()));
}

model load_config_model(const std::string& spec, const std::string& file)
{
    const fs::path base = fs::path(file).parent_path();
    fs::path path(spec);
    if (path.is_relative() && !base.empty()) path = base / path;
    std::error_code ec;
    // A config file may come from anywhere (a results directory, a download): naming a
    // library there would run its code unasked.
    if (!spec.empty() && !is_builtin(spec) && fs::exists(path, ec) && !fs::is_directory(path, ec) &&
        model_file_kind_of(path) == model_file_kind::shared_library)
        throw input_error(config_where(file) + ": key 'model' names a shared library (" + path.string() +
                          "): a shared library is loaded only when given on the command line (--model " +
                          path.string() + "), never from a config file");
    return load_model(spec, base);
}

nlohmann::json parameters_json(const model& m)
{
    nlohmann::json j = nlohmann::json::object();
    const auto& params = m.info().parameters;
    for (std::size_t i = 0; i < params.size(); ++i) j[params[i].name] = m.parameters()[i];
    return j;
}

run_config resolve(const common_args& a)
{
    if (!a.out.empty()) check_output_target(a.out);

    std::optional<toml::table> cfg;
    if (!a.config.empty()) cfg = read_config(a.config);
    const toml::node* cfg_model = cfg ? cfg->get("model") : nullptr;
    model m = a.model_option->count() > 0 || !cfg_model ? load_model(a.model)
                                                         : load_config_model(toml_string(*cfg_model, "model", a.config),
                                                                             a.config);
    const model_info& info = m.info();
    // The config's model, or the same file named on the command line (a shared library, which
    // a config cannot load): it must be the model the run had.
    const auto same_file = [&] {
        if (!cfg_model || !cfg_model->is_string() || info.source == "built-in") return false;
        std::error_code ec;
        const fs::path named = fs::path(a.config).parent_path() / cfg_model->as_string()->get();
        return fs::equivalent(named, info.source, ec);
    };
    if (cfg && cfg->contains("model_identity") && (a.model_option->count() == 0 || same_file())) {
        const std::string expected = toml_string(*cfg->get("model_identity"), "model_identity", a.config);
        if (expected != info.identity)
            throw input_error(config_where(a.config) + ": the model " + info.source + " is not the one of the run (" +
                              "identity " + info.identity + ", the config expects " + expected +
                              "): it has changed since; remove model_identity to run it anyway");
    }

    run_config c;
    c.command = a.command->get_name();
    c.command_options = recorded_options(*a.command);
    c.preset = a.preset;
    if (a.preset_option->count() == 0 && cfg && cfg->contains("preset"))
        c.preset = toml_string(*cfg->get("preset"), "preset", a.config);
    if (!c.preset.empty()) {
        const int p = info.preset_index(c.preset);
        if (p < 0)
            throw input_error(info.presets.empty() ? "model " + m.name() + " has no presets (--preset " + c.preset + ")"
                                                   : "unknown preset '" + c.preset + "' (model " + m.name() + " has " +
                                                         info.preset_names() + ")");
        m = m.with_preset(p);
    }
    std::vector<double> values = m.parameters();
    c.ic = m.initial_state();
    c.protocol = a.protocol;  // the command line's values, else the defaults; the config file's below
    c.protocol.flow.cancel = &interrupt_flag();  // Ctrl-C ends a run with the outcome `interrupted`
    std::string section;

    if (cfg) {
        const std::string& file = a.config;
        // A value out of its range names the file: the library's check, on that value alone.
        const auto in_file = [&](const auto& check) {
            try {
                check();
            } catch (const input_error& e) {
                throw input_error(config_where(file) + ": " + e.what());
            }
        };
        const auto set_parameter = [&](const std::string& key, const toml::node& node) {
            const int i = info.parameter_index(key);
            if (i < 0) return false;
            const double v = toml_number(node, key, file);
            in_file([&] { model::check_parameter(info.parameters[static_cast<std::size_t>(i)], v); });
            values[static_cast<std::size_t>(i)] = v;
            return true;
        };
        for (const auto& [k, node] : *cfg) {
            const std::string key(k.str());
            if (key == c.command && node.is_table()) continue;  // the command's options: applied when parsing
            c.config_sets_run = true;
            if (key == "parameters" && node.is_table()) {
                for (const auto& [pk, pnode] : *node.as_table())
                    if (!set_parameter(std::string(pk.str()), pnode))
                        throw input_error(config_where(file) + ": unknown parameter '" + std::string(pk.str()) +
                                          "' in [parameters] (" + parameters_it_has(info) + ")");
            } else if (key == "model" || key == "preset" || key == "model_identity") {
                (void)toml_string(node, key, file);
            } else if (key == "ic") {
                const auto* arr = node.as_array();
                if (!arr || static_cast<int>(arr->size()) != m.dim())
                    throw input_error(config_where(file) + ": 'ic' must be an array of " + std::to_string(m.dim()) +
                                      " numbers (" + info.state_names() + ")");
                for (std::size_t i = 0; i < arr->size(); ++i)
                    c.ic[static_cast<Eigen::Index>(i)] = toml_number(*arr->get(i), "ic", file);
            } else if (std::find(protocol_keys().begin(), protocol_keys().end(), key) != protocol_keys().end()) {
                // read by protocol_config_reader below
            } else if (key == "section") {
                section = toml_string(node, key, file);
            } else if (set_parameter(key, node)) {
            } else {
                throw input_error(config_where(file) + ": unknown key '" + key + "' (valid: " + joined(setting_keys()) +
                                  ", and the parameters: " + parameters_it_has(info) + ")");
            }
        }
    }
    if (cfg) {
        const protocol_config_reader read{*cfg, *a.command, a.config};
        declare(read, c.protocol);
    }
    // Command-line values override the config file.
    if (a.section_option->count()) section = a.section;

    std::map<int, std::string> set_by;
    for (const auto& s : a.sets) {
        const auto eq = s.find('=');
        if (eq == std::string::npos || eq == 0) throw input_error("--set expects KEY=VALUE (got '" + s + "')");
        const std::string key = s.substr(0, eq);
        const int i = info.parameter_index(key);
        if (i < 0)
            throw input_error("unknown parameter '" + key + "' in --set (" + parameters_it_has(info) + ")");
        if (const auto [it, fresh] = set_by.emplace(i, s); !fresh)
            throw input_error("--set " + key + " is given twice (" + it->second + " and " + s + ")");
        values[static_cast<std::size_t>(i)] = parse_number(s.substr(eq + 1), "--set " + key);
    }
    m = m.with_parameters(values);  // checks every value against its range
    if (!a.si.empty()) {
        c.si = parse_si(a.si);
        for (const auto& [i, v] : si_parameters(m, *c.si))
            if (const auto it = set_by.find(i); it != set_by.end())
                throw input_error("--set " + it->second + " and --si both set " +
                                  info.parameters[static_cast<std::size_t>(i)].name + "; give it once");
        m = apply_si(m, *c.si);
    }

    if (!a.ic.empty()) {
        const auto x = parse_numbers(a.ic, "--ic");
        check_state_size(m, static_cast<Eigen::Index>(x.size()), "--ic");
        c.ic = Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()));
    }
    c.protocol.section = section.empty() ? default_section(m) : parse_section(m, section);
    validate(c.protocol);
    validate(m, c.protocol.section);
    c.model = std::move(m);
    if (!a.out.empty()) c.out = fs::path(a.out);
    c.json = a.json;
    c.plot = !a.no_plot;
    if (a.format != "png" && a.format != "pdf" && a.format != "svg")
        throw input_error("--format '" + a.format + "' is not one of png, pdf, svg");
    c.plot_format = a.format;
    return c;
}

void check_admissible(const run_config& c)
{
    const int s = violated_surface(c.model, c.ic);
    if (s < 0) return;
    const auto& info = c.info();
    std::string state;
    for (Eigen::Index k = 0; k < c.ic.size(); ++k) {
        if (k) state += ", ";
        state += format_double(c.ic[k]);
    }
    const auto& surf = info.surfaces[static_cast<std::size_t>(s)];
    throw input_error("the initial state (" + info.state_names() + ") = (" + state + ") lies beyond surface " +
                      surf.name + (surf.meaning.empty() ? std::string() : " (" + surf.meaning + ")") +
                      ": it must start on the admissible side");
}

nlohmann::json run_config::to_json() const
{
    nlohmann::json j;
    j["model"] = model.name();
    j["preset"] = preset.empty() ? nlohmann::json(nullptr) : nlohmann::json(preset);
    j["parameters"] = parameters_json(model);
    j["ic"] = std::vector<double>(ic.data(), ic.data() + ic.size());
    j.update(protocol_settings(protocol));
    j["section"] = section_name();
    if (si) j["si"] = si_json(*si, model);
    return j;
}

}  // namespace vimpact::cli
