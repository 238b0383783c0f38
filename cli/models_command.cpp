// The models command: what each built-in model (or a model file or plugin, compiled and
// loaded to check it) declares: its description, state variables, parameters with meaning,
// default, unit and valid range, surfaces, sections and presets.
#include <cmath>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "common_options.hpp"
#include "output.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/io/model_info_json.hpp"

namespace vimpact::cli {
namespace {

struct models_args {
    std::vector<std::string> models;
    bool json = false;
};

// "  name  meaning [unit]" lines, names padded to one width.
template <class Items, class Line>
std::string table(const Items& items, Line&& line)
{
    std::size_t width = 0;
    for (const auto& it : items) width = std::max(width, it.name.size());
    std::string t;
    for (const auto& it : items) {
        std::string name = it.name;
        name.resize(width, ' ');
        t += "    " + name + "  " + line(it) + "\n";
    }
    return t;
}

std::string with_unit(const std::string& meaning, const std::string& unit)
{
    if (unit.empty()) return meaning;
    return meaning + " [" + unit + "]";
}

std::string text_of(const model& m)
{
    const auto& info = m.info();
    std::string t = info.name + " (" + info.source + ")\n  " + info.description + "\n";
    t += "  state (initial";
    for (const double x : info.initial_state) t += " " + format_double(x);
    t += "):\n";
    t += table(info.state, [](const state_variable_info& v) {
        std::string s = with_unit(v.meaning, v.unit);
        if (v.period > 0.0) s += " (a phase, period " + format_double(v.period) + ")";
        return s;
    });
    t += "  parameters (default, valid range):\n";
    t += table(info.parameters, [](const parameter_info& p) {
        return format_double(p.default_value) + ", " + p.range.text() + ": " + with_unit(p.meaning, p.unit);
    });
    t += info.surfaces.empty() ? std::string("  surfaces: none\n") : std::string("  surfaces:\n");
    t += table(info.surfaces, [](const surface_info& s) {
        return s.meaning + (s.sticks ? " (sticks: contact phases)" : " (no contact phase: chattering ends a run)");
    });
    if (!info.switches.empty()) {
        t += "  switches (the field changes across them):\n";
        t += table(info.switches, [](const switch_info& s) { return s.meaning; });
    }
    t += info.sections.empty() ? std::string("  sections: none (record --section impacts)\n") : std::string("  sections:\n");
    t += table(info.sections, [](const section_info& s) { return std::string(to_string(s.direction)) + ": " + s.meaning; });
    if (!info.presets.empty()) {
        t += "  presets:\n";
        t += table(info.presets, [&](const preset_info& p) {
            std::string s = p.meaning + " (";
            for (std::size_t k = 0; k < p.values.size(); ++k) {
                if (k) s += ", ";
                s += info.parameters[static_cast<std::size_t>(p.values[k].first)].name + " = " +
                     format_double(p.values[k].second);
            }
            return s + ")";
        });
    }
    return t;
}

int run_models(const models_args& a)
{
    std::vector<model> models;
    if (a.models.empty())
        for (const auto& name : model::builtin_names()) models.push_back(model::builtin(name));
    else
        for (const auto& spec : a.models) models.push_back(load_model(spec));
    if (a.json) {
        json list = json::array();
        for (const auto& m : models) list.push_back(model_info_json(m.info()));
        std::cout << json{{"command", "models"}, {"models", list}}.dump() << '\n';
    } else {
        for (std::size_t i = 0; i < models.size(); ++i) std::cout << (i ? "\n" : "") << text_of(models[i]);
    }
    return 0;
}

}  // namespace

cli_command add_models_command(CLI::App& app)
{
    auto a = std::make_shared<models_args>();
    auto* s = app.add_subcommand("models",
                                 "The built-in models, or the given model files and plugins (compiled and loaded to check "
                                 "them): state, parameters with defaults and ranges, surfaces, sections, presets");
    s->add_option("model", a->models, "Model files (.toml, .json), shared libraries or built-in names");
    s->add_flag("--json", a->json, "Print one JSON object to stdout");
    return {s, [a] { return run_models(*a); }};
}

}  // namespace vimpact::cli
