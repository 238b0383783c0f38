#include "common_options.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <toml++/toml.h>

#include "vimpact/core/format.hpp"
#include "vimpact/analysis/job_points.hpp"
#include "vimpact/core/input_error.hpp"

namespace vimpact::cli {

double parse_number(const std::string& text, const std::string& what)
{
    double v = 0.0;
    const char* b = text.data();
    const char* e = b + text.size();
    while (b < e && *b == ' ') ++b;
    if (b < e && *b == '+') ++b;
    auto [p, ec] = std::from_chars(b, e, v);
    if (ec != std::errc() || p != e || b == e)
        throw input_error("malformed number '" + text + "' for " + what);
    if (!std::isfinite(v)) throw input_error(what + " must be finite (got '" + text + "')");
    return v;
}

void add_common_options(CLI::App& app, common_args& a)
{
    a.preset_option = app.add_option("--preset", a.preset,
                                     "Parameter preset: paper (M = 0.05/mu, default) or facchinetti (CL0 = 0.3)");
    app.add_option("--set", a.sets,
                   "Override a parameter, KEY=VALUE (repeatable); keys: Ur, sigma, r, A, eps, St, xi, gamma, mu, CL0")
        ->allow_extra_args(false);
    app.add_option("--ic", a.ic, "Initial state y,ydot,x,xdot (default 0,0,0,0.1)");
    app.add_option("--config", a.config, "TOML file with the same keys (parameters, ic, rtol, atol, transient, record, method, section, preset)");
    a.rtol_option = app.add_option("--rtol", a.rtol, "Relative tolerance (default 1e-10)");
    a.atol_option = app.add_option("--atol", a.atol, "Absolute tolerance (default 1e-10)");
    a.transient_option = app.add_option("--transient", a.transient, "Impacts discarded before recording (default 500)");
    a.record_option = app.add_option("--record", a.record, "Section points kept (default " + std::to_string(a.record) + ")");
    a.method_option = app.add_option("--method", a.method, "Integrator: dop853 (default) or dopri5");
    a.section_option = app.add_option("--section", a.section, "Section: maxima (default, the paper's Sigma), minima or impacts");
    app.add_option("--out", a.out, "Write CSV, a JSON record and a PNG to this directory");
    app.add_flag("--json", a.json, "Print one JSON object to stdout");
    app.add_flag("--no-plot", a.no_plot, "With --out: skip the PNG");
}

namespace {

void set_model_key(run_config& c, const std::string& key, double value)
{
    set_parameter(c.params, wake_impact_parameter_table(), key, value);
}

vec<4> parse_ic(const std::string& text)
{
    vec<4> x;
    std::size_t start = 0;
    int n = 0;
    for (;;) {
        const std::size_t comma = text.find(',', start);
        const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (n >= 4) throw input_error("--ic needs 4 comma-separated numbers y,ydot,x,xdot (got '" + text + "')");
        x[n++] = parse_number(item, "--ic");
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    if (n != 4) throw input_error("--ic needs 4 comma-separated numbers y,ydot,x,xdot (got '" + text + "')");
    return x;
}

section_choice parse_section(const std::string& s) { return parse_section_choice(s, input_spelling::cli); }

double toml_number(const toml::node& node, const std::string& key, const std::string& file)
{
    if (auto v = node.value<double>()) return *v;
    throw input_error("config " + file + ": key '" + key + "' must be a number");
}

long toml_integer(const toml::node& node, const std::string& key, const std::string& file)
{
    if (auto v = node.value<int64_t>()) return static_cast<long>(*v);
    throw input_error("config " + file + ": key '" + key + "' must be an integer");
}

void apply_config(run_config& c, const common_args& a)
{
    toml::table tbl;
    {
        std::ifstream probe(a.config);
        if (!probe) throw input_error("cannot read config file '" + a.config + "'");
    }
    try {
        tbl = toml::parse_file(a.config);
    } catch (const toml::parse_error& e) {
        throw input_error("config " + a.config + ": " + std::string(e.description()) + " (line " +
                          std::to_string(e.source().begin.line) + ")");
    }
    if (auto p = tbl["preset"].value<std::string>(); p && a.preset_option->count() == 0) {
        c.preset = *p;
        c.params = wake_impact_preset(*p);
    }
    for (const auto& [k, node] : tbl) {
        const std::string key(k.str());
        if (key == "preset") {
            if (!node.is_string()) throw input_error("config " + a.config + ": key 'preset' must be a string");
        } else if (find_parameter(wake_impact_parameter_table(), key)) {
            set_model_key(c, key, toml_number(node, key, a.config));
        } else if (key == "ic") {
            const auto* arr = node.as_array();
            if (!arr || arr->size() != 4) throw input_error("config " + a.config + ": 'ic' must be an array of 4 numbers");
            for (std::size_t i = 0; i < 4; ++i) c.ic[static_cast<int>(i)] = toml_number(*arr->get(i), "ic", a.config);
        } else if (key == "rtol") {
            c.rtol = toml_number(node, key, a.config);
        } else if (key == "atol") {
            c.atol = toml_number(node, key, a.config);
        } else if (key == "transient") {
            c.transient = toml_integer(node, key, a.config);
        } else if (key == "record") {
            c.record = toml_integer(node, key, a.config);
        } else if (key == "method") {
            if (!node.is_string()) throw input_error("config " + a.config + ": 'method' must be a string");
            c.method = *node.value<std::string>();
        } else if (key == "section") {
            if (!node.is_string()) throw input_error("config " + a.config + ": 'section' must be a string");
            c.section = parse_section(*node.value<std::string>());
        } else {
            throw input_error("config " + a.config + ": unknown key '" + key + "' (valid: " +
                              parameter_names(wake_impact_parameter_table()) +
                              ", preset, ic, rtol, atol, transient, record, method, section)");
        }
    }
}

}  // namespace

run_config resolve(const common_args& a)
{
    run_config c;
    c.preset = a.preset;
    c.params = wake_impact_preset(a.preset);
    c.section = parse_section(a.section);
    c.record = a.record;  // the command's default; the config file and --record override it
    if (!a.config.empty()) apply_config(c, a);
    // Command-line values override the config file.
    if (a.rtol_option->count()) c.rtol = a.rtol;
    if (a.atol_option->count()) c.atol = a.atol;
    if (a.transient_option->count()) c.transient = a.transient;
    if (a.record_option->count()) c.record = a.record;
    if (a.method_option->count()) c.method = a.method;
    if (a.section_option->count()) c.section = parse_section(a.section);
    for (const auto& s : a.sets) {
        const auto eq = s.find('=');
        if (eq == std::string::npos || eq == 0)
            throw input_error("--set expects KEY=VALUE (got '" + s + "')");
        const std::string key = s.substr(0, eq);
        if (!find_parameter(wake_impact_parameter_table(), key))
            throw input_error("unknown parameter '" + key + "' in --set (valid: " +
                              parameter_names(wake_impact_parameter_table()) + ")");
        set_model_key(c, key, parse_number(s.substr(eq + 1), "--set " + key));
    }
    if (!a.ic.empty()) c.ic = parse_ic(a.ic);
    (void)parse_integration_method(c.method, input_spelling::cli);  // validates
    if (!a.out.empty()) c.out = a.out;
    c.json = a.json;
    c.plot = !a.no_plot;

    (void)c.model();      // validates the parameters
    validate(c.protocol());  // validates tolerances and counts
    if (c.ic[0] < c.params.sigma || (c.ic[0] == c.params.sigma && c.ic[1] < 0.0))
        throw input_error("initial state y = " + format_double(c.ic[0]) +
                          " is below the barrier sigma = " + format_double(c.params.sigma) +
                          " (the admissible region is y >= sigma)");
    return c;
}

protocol_options run_config::protocol() const
{
    protocol_options p;
    p.transient_impacts = transient;
    p.record_points = record;
    p.section = section;
    p.flow.integration.rtol = rtol;
    p.flow.integration.atol = atol;
    return p;
}

nlohmann::json run_config::to_json() const
{
    nlohmann::json j;
    j["model"] = "wake_impact";
    j["preset"] = preset;
    nlohmann::json pj;
    for (const auto& info : wake_impact_parameter_table()) pj[std::string(info.name)] = params.*(info.member);
    j["parameters"] = pj;
    const wake_impact m(params);
    j["derived"] = {{"delta", m.delta()}, {"alpha", m.alpha()}, {"M", m.coupling_M()}};
    j["ic"] = {ic[0], ic[1], ic[2], ic[3]};
    j["rtol"] = rtol;
    j["atol"] = atol;
    j["method"] = method;
    j["transient"] = transient;
    j["record"] = record;
    j["section"] = std::string(to_string(section));
    return j;
}

}  // namespace vimpact::cli
