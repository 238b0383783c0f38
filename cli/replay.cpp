#include "replay.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <cctype>
#include <toml++/toml.h>

#include "common_options.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/io/build_info.hpp"

namespace fs = std::filesystem;

namespace vimpact::cli {

namespace {

const CLI::App* subcommand_named(const CLI::App& app, const std::string& name)
{
    for (const CLI::App* s : app.get_subcommands([](const CLI::App*) { return true; }))
        if (s->get_name() == name) return s;
    return nullptr;
}

// Options that are the run's settings (written resolved, at the top level of config.toml) or
// that only choose where and how to run; none of them belongs in the command's table.
bool is_unrecorded(const std::string& name)
{
    static const std::set<std::string> names{"--model", "--preset", "--set",   "--ic",     "--config", "--rtol",
                                             "--atol",  "--hold-band", "--max-step", "--transient", "--record", "--method", "--section",
                                             "--out",   "--json",   "--threads", "--shard",  "--resume", "--help"};
    return names.count(name) > 0;
}

// Options naming a file: recorded absolute, so that the config replays from any directory.
bool is_path_option(const std::string& name) { return name == "--points"; }

// "1000" -> 1000, "1e-5" -> 1e-5, "12:25:131" stays text: numbers read as numbers in the
// file, and each one converts back to a string that parses to the same value.
nlohmann::json typed(const std::string& s)
{
    const char* end = s.data() + s.size();
    long long i = 0;
    if (auto [p, ec] = std::from_chars(s.data(), end, i); ec == std::errc() && p == end) return i;
    double d = 0.0;
    if (auto [p, ec] = std::from_chars(s.data(), end, d); ec == std::errc() && p == end && std::isfinite(d)) return d;
    return s;
}

std::string option_name(const std::string& key) { return "--" + key; }

bool given(const std::vector<std::string>& args, const std::string& name)
{
    return std::any_of(args.begin(), args.end(),
                       [&](const std::string& a) { return a == name || a.rfind(name + "=", 0) == 0; });
}

std::string token(const toml::node& node, const std::string& where)
{
    if (auto v = node.value_exact<int64_t>()) return std::to_string(*v);
    if (auto v = node.value_exact<double>()) return format_double(*v);
    if (auto v = node.value_exact<std::string>()) return *v;
    throw input_error(where + " must be a string or a number");
}

// The value of --config among a command's arguments, or empty.
std::string config_argument(const std::vector<std::string>& args)
{
    for (std::size_t i = 0; i < args.size(); ++i) {
        if (args[i] == "--config" && i + 1 < args.size()) return args[i + 1];
        if (args[i].rfind("--config=", 0) == 0) return args[i].substr(9);
    }
    return {};
}

}  // namespace

std::vector<std::string> arguments_with_config(const CLI::App& app, int argc, char** argv)
{
    std::vector<std::string> args(argv + 1, argv + argc);
    // The command is the first word: the program itself has only flags (--help, --version).
    const auto first = std::find_if(args.begin(), args.end(), [](const std::string& a) { return a.rfind('-', 0) != 0; });
    if (first == args.end()) return args;
    const CLI::App* command = subcommand_named(app, *first);
    if (command == nullptr) return args;
    const std::vector<std::string> command_args(first + 1, args.end());
    const std::string file = config_argument(command_args);
    if (file.empty()) return args;

    const toml::table cfg = read_config(file);
    const std::string name = command->get_name();
    for (const auto& [k, node] : cfg) {
        const std::string key(k.str());
        if (!node.is_table() || key == "parameters" || key == name) continue;
        if (subcommand_named(app, key) != nullptr)
            throw input_error("config " + file + " holds the options of `vimpact " + key + "` ([" + key +
                              "]); this is `vimpact " + name + "`");
    }
    const toml::table* own = cfg.get_as<toml::table>(name);
    if (own == nullptr) return args;
    for (const auto& [k, node] : *own) {
        const std::string key(k.str());
        const std::string opt_name = option_name(key);
        const std::string where = "config " + file + ": [" + name + "] " + key;
        const CLI::Option* opt = command->get_option_no_throw(opt_name);
        if (opt == nullptr || is_unrecorded(opt_name))
            throw input_error(where + " is not an option of `vimpact " + name + "` (see vimpact " + name + " --help)");
        if (given(command_args, opt_name)) continue;  // the command line wins
        if (auto flag = node.value_exact<bool>()) {
            if (opt->get_expected_min() != 0) throw input_error(where + " takes a value, not true or false");
            if (*flag) args.push_back(opt_name);
        } else if (const auto* list = node.as_array()) {
            args.push_back(opt_name);
            for (const auto& item : *list) args.push_back(token(item, where + " (each item)"));
        } else {
            args.push_back(opt_name);
            args.push_back(token(node, where));
        }
    }
    return args;
}

nlohmann::json recorded_options(const CLI::App& command)
{
    nlohmann::json j = nlohmann::json::object();
    for (const CLI::Option* opt : command.get_options()) {
        const std::string& name = opt->get_name();
        if (opt->count() == 0 || is_unrecorded(name) || name.rfind("--", 0) != 0) continue;
        const std::string key = name.substr(2);
        std::vector<std::string> values = opt->results();
        values.erase(std::remove(values.begin(), values.end(), std::string()), values.end());
        if (opt->get_expected_max() == 0 || values.empty()) {
            j[key] = true;  // a flag, or an option whose value is optional and was left out
            continue;
        }
        if (is_path_option(name))
            for (auto& v : values) v = fs::absolute(v).lexically_normal().string();
        if (values.size() == 1) {
            j[key] = typed(values.front());
        } else {
            j[key] = nlohmann::json::array();
            for (const auto& v : values) j[key].push_back(typed(v));
        }
    }
    return j;
}

namespace {

// TOML text by hand rather than toml++'s writer, which gives every double 17 digits
// (0.10000000000000001): the shortest text that reads back to the same double.
std::string toml_number(double x)
{
    std::string s = format_double(x);
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // stays a float
    return s;
}

std::string toml_text(const std::string& s)
{
    std::ostringstream o;
    o << toml::value<std::string>(s);
    return o.str();
}

std::string toml_key(const std::string& k)
{
    const bool bare = !k.empty() && std::all_of(k.begin(), k.end(), [](char ch) {
        return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-';
    });
    return bare ? k : toml_text(k);
}

std::string toml_value(const nlohmann::json& v)
{
    if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
    if (v.is_number_integer()) return std::to_string(v.get<int64_t>());
    if (v.is_number()) return toml_number(v.get<double>());
    if (v.is_array()) {
        std::string s = "[";
        for (const auto& item : v) s += (s.size() > 1 ? ", " : "") + toml_value(item);
        return s + "]";
    }
    return toml_text(v.get<std::string>());
}

}  // namespace

void write_replay_config(const fs::path& path, const run_config& c)
{
    const model_info& info = c.info();
    std::ostringstream t;
    t << "# vimpact " << c.command << " " << version() << " (" << git_hash() << "): this run, replayable with\n"
      << "#   vimpact " << c.command << " --config config.toml --out DIR\n"
      << "# Options on the command line override the values here; [" << c.command
      << "] holds the command's own options as given.\n";
    if (c.describes_run) {  // not so for a dimension of a points file
        const auto line = [&](const std::string& key, const nlohmann::json& v) {
            t << toml_key(key) << " = " << toml_value(v) << '\n';
        };
        line("model", info.source == "built-in" ? info.name : fs::absolute(info.source).lexically_normal().string());
        line("model_identity", info.identity);
        if (!c.preset.empty()) line("preset", c.preset);
        line("ic", std::vector<double>(c.ic.data(), c.ic.data() + c.ic.size()));
        line("rtol", c.protocol.flow.integration.rtol);
        line("atol", c.protocol.flow.integration.atol);
        // The band the run used, so the replay holds alike whatever the default then.
        const double band = effective_hold_band(c.protocol.flow.integration, c.protocol.method);
        if (c.protocol.flow.integration.hold_band || band > 0.0) line("hold_band", band);
        if (std::isfinite(c.protocol.flow.integration.h_max)) line("max_step", c.protocol.flow.integration.h_max);
        line("method", std::string(to_string(c.protocol.method)));
        line("section", c.section_name());
        line("transient", static_cast<int64_t>(c.protocol.transient_impacts));
        line("record", static_cast<int64_t>(c.protocol.record_points));
        t << "\n[parameters]\n";
        for (std::size_t i = 0; i < info.parameters.size(); ++i) line(info.parameters[i].name, c.model.parameters()[i]);
    }
    t << "\n[" << c.command << "]\n";
    for (const auto& [key, value] : c.command_options.items()) t << toml_key(key) << " = " << toml_value(value) << '\n';

    std::ofstream out(path);
    out << t.str();
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace vimpact::cli
