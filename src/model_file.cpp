// Model files: an impacting system written as equations in a TOML file (or the same keys as
// a JSON tree), compiled to native code once and loaded as a function table (model/abi.h),
// and shared libraries that export such a table.
//
// ---- The format (docs/model-files.md is the user's version, with examples)
//
//   name = "two_sided_impact_oscillator"   required; an identifier
//   description = "..."                    optional
//   state = ["x", "v", "phi"]              required, 1 or more; each entry a name or a table
//                                          {name, meaning, unit}
//   initial_state = [0.0, 0.0, 0.0]        optional; one number per state variable (zeros)
//   [parameters]                           required, may be empty; in declared order:
//   zeta = 0.05                              name = default, or
//   d = { default = 1.0, meaning = "...", unit = "...", min = 0, max = 1, above = 0, below = 1 }
//                                            min/max closed bounds, above/below open ones (at
//                                            most one lower and one upper); the default must
//                                            lie in the range
//   [derived]                              optional: name = expression of the parameters and
//                                          other derived quantities (in any order; a cycle is
//                                          an error), computed once per parameter set; a value
//                                          that is not finite refuses the parameter set
//   [expressions]                          optional: name = expression of the state, the
//                                          parameters, derived quantities and other named
//                                          expressions, substituted where it is used
//   [derivatives]                          required: state variable = its time derivative, for
//                                          every state variable and no other name
//   [angles]                               optional: state variable = period (a constant
//                                          expression > 0, e.g. "2*pi"): the variable lives on
//                                          a circle
//   [[surfaces]]                           optional, in order: name (an identifier, unique),
//                                          meaning, gap (the motion keeps gap >= 0; an impact
//                                          when it decreases through 0), reset (required: a
//                                          table state variable = new value; the others keep
//                                          theirs), sticking (optional table: release
//                                          (required; contact ends when it crosses 0
//                                          upwards), rest (the state put at rest on the
//                                          surface, unnamed variables kept), derivatives (the
//                                          constrained field, unnamed variables keep the free
//                                          one))
//   [[sections]]                           optional: name, meaning, when (the section is where
//                                          it crosses 0), direction ("up", "down", "both";
//                                          required)
//   [presets]                              optional: name = { parameter = value, ...,
//                                          meaning = "..." }; values in range
//
// Names (state, parameters, derived, expressions) are identifiers (letters, digits, _; a
// letter first), unique across the four kinds, and neither `pi` nor a function name. Expressions: numbers (a decimal literal is the double nearest to it),
// names, pi, + - * / ^ (or **), parentheses, and the functions sin cos tan asin acos atan
// sinh cosh tanh exp log sqrt abs sgn heaviside (one argument), pow, min and max (two); abs,
// sgn, heaviside, min and max of the state in the derivatives become switches. Every
// unknown key is an error that lists the valid ones.
//
// ---- What happens
//
// 1. TOML -> nlohmann::ordered_json (toml++ iterates tables sorted by key; the keys are put
//    back in the order of their position in the text, because the order of parameters is
//    their index). compile_model_json is the one path from there; it also serves .json
//    files and Python's dicts.
// 2. describe() checks keys, types, names and ranges (model_file_describe.cpp).
// 3. generate_source() reads the expressions with GiNaC, differentiates them symbolically
//    (Jacobian, second derivatives as bilinear forms, divergence, gap gradients and
//    Hessians, reset Jacobians and second derivatives, section and release gradients) and
//    prints plain C functions and a static table (model_file_symbolic.cpp). The context of
//    a parameter set is an array: the parameters, then the derived quantities.
// 4. compile_cached() compiles it with $CXX (else c++) into the cache directory, or finds it
//    there, and loads it (model_file_compile.cpp: the cache's rules; model_file_process.cpp:
//    the compiler's process). A cancel flag given by the caller is polled by 3 and 4.
// The model's identity is a hash of its canonical description (canonical_json), so two
// files that say the same thing give equal models whatever their path or spelling.
#include "vimpact/model/model_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include <toml++/toml.h>

#include "model_file_detail.hpp"
#include "vimpact/core/input_error.hpp"

namespace vimpact {

namespace {

using json = nlohmann::ordered_json;
namespace fs = std::filesystem;
namespace mf = model_file_detail;

std::string join(const std::string& path, std::string_view key)
{
    return path.empty() ? std::string(key) : path + "." + std::string(key);
}

// Where a key was written: its own position, or its value's for a table made implicitly.
std::pair<std::uint32_t, std::uint32_t> position(const toml::key& k, const toml::node& v)
{
    const auto& s = k.source().begin.line > 0 ? k.source().begin : v.source().begin;
    return {s.line, s.column};
}

json to_json(const toml::node& node, const std::string& path, const std::string& where)
{
    switch (node.type()) {
        case toml::node_type::table: {
            std::vector<std::pair<const toml::key*, const toml::node*>> items;
            for (auto&& [k, v] : *node.as_table()) items.emplace_back(&k, &v);
            std::stable_sort(items.begin(), items.end(), [](const auto& a, const auto& b) {
                return position(*a.first, *a.second) < position(*b.first, *b.second);
            });
            json j = json::object();
            for (const auto& [k, v] : items) {
                const std::string key(k->str());
                j[key] = to_json(*v, join(path, key), where);
            }
            return j;
        }
        case toml::node_type::array: {
            json j = json::array();
            std::size_t i = 0;
            for (const auto& v : *node.as_array()) j.push_back(to_json(v, path + "[" + std::to_string(i++) + "]", where));
            return j;
        }
        case toml::node_type::string: return std::string(node.as_string()->get());
        case toml::node_type::integer: return node.as_integer()->get();
        case toml::node_type::floating_point: return node.as_floating_point()->get();
        case toml::node_type::boolean: return node.as_boolean()->get();
        default:
            throw input_error(where + ": " + (path.empty() ? std::string("value") : path) +
                              ": dates and times have no meaning in a model file");
    }
}

std::string read_file(const fs::path& path, const std::string& what)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) throw input_error("cannot read " + what + " " + path.string() + ": " + std::strerror(errno));
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

bool is_elf(const fs::path& path)
{
    std::ifstream in(path, std::ios::binary);
    char magic[4] = {};
    in.read(magic, 4);
    return in.gcount() == 4 && magic[0] == 0x7f && magic[1] == 'E' && magic[2] == 'L' && magic[3] == 'F';
}

std::shared_ptr<const model_code> make_code(const mf::loaded_library& lib, std::string source, std::string identity)
{
    auto code = std::make_shared<model_code>();
    code->table = lib.table;
    code->info = info_from_table(*lib.table);
    code->info.source = std::move(source);
    code->info.identity = std::move(identity);
    code->native = native_kind::none;
    code->library = lib.handle;
    return code;
}

}  // namespace

std::shared_ptr<const model_code> compile_model_json(const json& description, std::string_view source,
                                                     const std::atomic<bool>* cancel)
{
    const std::string where = "model file " + std::string(source);
    const mf::description d = mf::describe(description, where);
    const std::string identity = d.name + "-" + mf::hex64(mf::fnv1a(mf::canonical_json(d).dump()));
    const std::string code = mf::generate_source(d, where, cancel);
    const mf::loaded_library lib = mf::compile_cached(code, d.name, where, cancel);
    check_engine_dimension(lib.table->dim, where);
    return make_code(lib, std::string(source), identity);
}

std::shared_ptr<const model_code> compile_model_text(std::string_view text, std::string_view source,
                                                     const std::atomic<bool>* cancel)
{
    const std::string where = "model file " + std::string(source);
    toml::table table;
    try {
        table = toml::parse(text, source);
    } catch (const toml::parse_error& e) {
        throw input_error(where + ": line " + std::to_string(e.source().begin.line) + ": " +
                          std::string(e.description()));
    }
    return compile_model_json(to_json(table, "", where), source, cancel);
}

std::shared_ptr<const model_code> load_model_library(const fs::path& path)
{
    const std::string what = "model library " + path.string();
    const std::string bytes = read_file(path, "model library");
    const mf::loaded_library lib = mf::open_library(path, what);
    check_engine_dimension(lib.table->dim, what);
    const std::string name = lib.table->name ? lib.table->name : "";
    return make_code(lib, path.string(), name + "-" + mf::hex64(mf::fnv1a(bytes)));
}

model_file_kind model_file_kind_of(const fs::path& path)
{
    std::error_code ec;
    if (!fs::exists(path, ec)) throw input_error("model file " + path.string() + " does not exist");
    if (fs::is_directory(path, ec)) throw input_error("model file " + path.string() + " is a directory");
    const std::string ext = path.extension().string();
    if (ext == ".toml") return model_file_kind::model_text;
    if (ext == ".json") return model_file_kind::model_json;
    if (ext == ".so" || is_elf(path)) return model_file_kind::shared_library;
    throw input_error("cannot load a model from " + path.string() +
                      ": expected a model file (NAME.toml) or a shared library (NAME.so)");
}

std::shared_ptr<const model_code> load_model_code(const fs::path& path, const std::atomic<bool>* cancel)
{
    switch (model_file_kind_of(path)) {
        case model_file_kind::model_text:
            return compile_model_text(read_file(path, "model file"), path.string(), cancel);
        case model_file_kind::model_json: {
            json tree;
            try {
                tree = json::parse(read_file(path, "model file"));
            } catch (const json::parse_error& e) {
                throw input_error("model file " + path.string() + ": " + e.what());
            }
            return compile_model_json(tree, path.string(), cancel);
        }
        case model_file_kind::shared_library: return load_model_library(path);
    }
    throw std::logic_error("unknown model file kind");
}

}  // namespace vimpact
