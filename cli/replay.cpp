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
#include "parse.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/core/option.hpp"
#include "vimpact/io/build_info.hpp"
#include "vimpact/model/model_file.hpp"

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
    static const std::set<std::string> names = [] {
        std::set<std::string> n{"--model", "--preset", "--set",     "--ic",    "--config", "--section",
                                "--out",   "--json",   "--threads", "--shard", "--resume", "--help"};
        for (const auto& key : protocol_keys()) n.insert(command_line_key(key));
        return n;
    }();
    return names.count(name) > 0;
}

// Why an option cannot be set in the command's table of a config file, or empty when it can.
// --threads can: how many threads this machine gives a run (its results do not depend on it).
std::string table_refusal(const std::string& name)
{
    if (name == "--threads") return {};
    if (name == "--set") return "parameters are set at the top level of the file or in [parameters]";
    if (name == "--config") return "a config file cannot name another";
    if (name == "--out" || name == "--json") return "it says where the results go: give it on the command line";
    if (name == "--shard" || name == "--resume")
        return "it says which part of a run this process does: give it on the command line";
    if (is_unrecorded(name)) {
        std::string key = name.substr(2);
        std::replace(key.begin(), key.end(), '-', '_');
        return "it is a setting of the run: write it at the top level of the file (" + key + " = ...)";
    }
    return {};
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

// One value of an option as it would be typed, checked against the option's type (CLI11's
// type name: FLOAT, INT, UINT or TEXT) so that a mistake names the file and the key.
std::string token(const toml::node& node, const CLI::Option& opt, const std::string& where)
{
    const std::string full = opt.get_type_name();  // "TEXT:{none,period}": the type, then the checks
    const std::string type = full.substr(0, full.find(':'));
    const bool integer = type == "INT" || type == "UINT";
    const auto wrong = [&](const std::string& expected) {
        return input_error(where + " must be " + expected + " (got " + toml_shown(node) + ")");
    };
    if (auto v = node.value_exact<int64_t>()) {
        if (type == "UINT" && *v < 0) throw wrong("an integer >= 0");
        return std::to_string(*v);
    }
    if (auto v = node.value_exact<double>()) {
        if (integer && !(*v == std::floor(*v) && std::abs(*v) < 1e15)) throw wrong("an integer");
        return integer ? std::to_string(static_cast<long long>(*v)) : format_double(*v);
    }
    if (auto v = node.value_exact<std::string>()) {
        if (type == "FLOAT" || integer) {
            try {
                const double x = parse_number(*v, opt.get_name());
                if (integer && x != std::floor(x)) throw wrong("an integer");
            } catch (const input_error&) {
                throw wrong(integer ? "an integer" : "a number");
            }
        }
        return *v;
    }
    if (type == "FLOAT") throw wrong("a number");
    if (integer) throw wrong("an integer");
    throw wrong("a string or a number");
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
        if (opt == nullptr || opt_name == "--help")
            throw input_error(where + " is not an option of `vimpact " + name + "` (see vimpact " + name + " --help)");
        if (const std::string why = table_refusal(opt_name); !why.empty())
            throw input_error(where + ": " + why);
        if (given(command_args, opt_name)) continue;  // the command line wins
        const bool flag = opt->get_items_expected_max() == 0;
        if (auto on = node.value_exact<bool>()) {
            if (opt->get_expected_min() != 0) throw input_error(where + " takes a value, not true or false");
            if (*on) args.push_back(opt_name);
        } else if (flag) {
            throw input_error(where + " is a flag: true or false (got " + toml_shown(node) + ")");
        } else if (const auto* list = node.as_array()) {
            if (opt->get_items_expected_max() <= 1)
                throw input_error(where + " takes one value, not a list (got " + toml_shown(node) + ")");
            for (const auto& item : *list) {
                args.push_back(opt_name);
                args.push_back(token(item, *opt, where + " (each item)"));
            }
        } else {
            args.push_back(opt_name);
            args.push_back(token(node, *opt, where));
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
    const std::string model_path =
        info.source == "built-in" ? std::string() : fs::absolute(info.source).lexically_normal().string();
    std::error_code ec;
    // A shared library runs only when named on the command line: the replay names it there.
    const bool library = c.describes_run && !model_path.empty() && fs::is_regular_file(model_path, ec) &&
                         model_file_kind_of(model_path) == model_file_kind::shared_library;
    std::ostringstream t;
    t << "# vimpact " << c.command << " " << version() << " (" << git_hash() << "): this run, replayable with\n"
      << "#   vimpact " << c.command << (library ? " --model " + toml_text(model_path) : std::string())
      << " --config config.toml --out DIR\n"
      << "# Options on the command line override the values here; [" << c.command
      << "] holds the command's own options as given.\n";
    if (c.describes_run) {  // not so for a dimension of a points file
        const auto line = [&](const std::string& key, const nlohmann::json& v) {
            t << toml_key(key) << " = " << toml_value(v) << '\n';
        };
        line("model", model_path.empty() ? info.name : model_path);
        line("model_identity", info.identity);
        if (!c.preset.empty()) line("preset", c.preset);
        line("ic", std::vector<double>(c.ic.data(), c.ic.data() + c.ic.size()));
        const nlohmann::json protocol = protocol_settings(c.protocol);
        for (const auto& [key, value] : protocol.items()) line(key, value);
        line("section", c.section_name());
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
