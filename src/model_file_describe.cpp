// Model files, stage 1: the JSON tree of a model file -> a checked description. Every key is
// checked here (unknown keys, types, names, ranges, presets); expressions are only collected,
// with the key they were written under, and read by the symbolic stage
// (model_file_symbolic.cpp). The format is described in src/model_file.cpp.
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <map>

#include "model_file_detail.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/model/model.hpp"

namespace vimpact::model_file_detail {

namespace {

using json = nlohmann::ordered_json;

std::string type_name(const json& v)
{
    switch (v.type()) {
        case json::value_t::object: return "a table";
        case json::value_t::array: return "an array";
        case json::value_t::string: return "a string";
        case json::value_t::boolean: return "a boolean";
        case json::value_t::number_integer:
        case json::value_t::number_unsigned:
        case json::value_t::number_float: return "a number";
        case json::value_t::null: return "nothing";
        default: return "a value of another type";
    }
}

std::string join(const std::string& path, std::string_view key)
{
    return path.empty() ? std::string(key) : path + "." + std::string(key);
}

std::string item(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

bool is_identifier(std::string_view s)
{
    if (s.empty()) return false;
    const auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
    if (!letter(s[0])) return false;
    return std::all_of(s.begin(), s.end(), [&](char c) { return letter(c) || c == '_' || (c >= '0' && c <= '9'); });
}

template <class List>
std::string comma_list(const List& items)
{
    std::string s;
    for (const auto& it : items) s += (s.empty() ? "" : ", ") + std::string(it);
    return s;
}

class reader {
public:
    explicit reader(const std::string& where) : m_where(where) {}

    [[noreturn]] void fail(const std::string& path, const std::string& message) const
    {
        throw input_error(m_where + ": " + path + ": " + message);
    }
    [[noreturn]] void fail(const std::string& message) const { throw input_error(m_where + ": " + message); }

    const json& object(const json& v, const std::string& path) const
    {
        if (!v.is_object()) fail(path, "expected a table, got " + type_name(v));
        return v;
    }
    const json& array(const json& v, const std::string& path) const
    {
        if (!v.is_array()) fail(path, "expected an array, got " + type_name(v));
        return v;
    }
    std::string string(const json& v, const std::string& path) const
    {
        if (!v.is_string()) fail(path, "expected a string, got " + type_name(v));
        std::string s = v.get<std::string>();
        // The generated code holds strings as C strings, which would end at the NUL.
        if (s.find('\0') != std::string::npos) fail(path, "the string contains a NUL character (\\u0000)");
        return s;
    }
    double number(const json& v, const std::string& path) const
    {
        if (!v.is_number()) fail(path, "expected a number, got " + type_name(v));
        const double d = v.get<double>();
        if (!std::isfinite(d)) fail(path, "expected a finite number, got " + format_double(d));
        return d;
    }
    std::string name(const json& v, const std::string& path) const
    {
        std::string s = string(v, path);
        if (!is_identifier(s))
            fail(path, "'" + s + "' is not a valid name (letters, digits and _, starting with a letter)");
        return s;
    }
    expression_text expression(const json& v, const std::string& path) const
    {
        if (v.is_string()) {
            std::string s = string(v, path);
            if (s.find_first_not_of(" \t\r\n") == std::string::npos) fail(path, "empty expression");
            return {path, std::move(s)};
        }
        if (v.is_number_integer() && !v.is_number_unsigned()) return {path, std::to_string(v.get<std::int64_t>())};
        if (v.is_number_unsigned()) return {path, std::to_string(v.get<std::uint64_t>())};
        if (v.is_number_float()) return {path, number_text(number(v, path))};
        fail(path, "expected an expression (a string such as \"-r*v\", or a number), got " + type_name(v));
    }

    // Every key of `obj` must be one of `valid`.
    void keys(const json& obj, const std::string& path, std::initializer_list<std::string_view> valid) const
    {
        for (auto it = obj.begin(); it != obj.end(); ++it)
            if (std::find(valid.begin(), valid.end(), it.key()) == valid.end())
                fail("unknown key '" + join(path, it.key()) + "' (valid: " + comma_list(valid) + ")");
    }
    static const json* find(const json& obj, std::string_view key)
    {
        const auto it = obj.find(std::string(key));
        return it == obj.end() ? nullptr : &*it;
    }
    const json& require(const json& obj, const std::string& path, std::string_view key) const
    {
        const json* v = find(obj, key);
        if (!v) fail("missing key '" + join(path, key) + "'");
        return *v;
    }
    std::string optional_string(const json& obj, const std::string& path, std::string_view key) const
    {
        const json* v = find(obj, key);
        return v ? string(*v, join(path, key)) : std::string();
    }

private:
    const std::string& m_where;
};

// The names of state variables, parameters, derived quantities, named expressions and
// switches share one space: an expression must know what each name means.
class name_space {
public:
    explicit name_space(const reader& r) : m_r(r) {}
    void add(const std::string& path, const std::string& name, const char* kind)
    {
        if (is_reserved_name(name))
            m_r.fail(path, "'" + name + "' is reserved (pi and the function names " + function_list() +
                               " cannot name anything else)");
        if (const auto it = m_kinds.find(name); it != m_kinds.end())
            m_r.fail(path, "the name '" + name + "' is already used for " + it->second);
        m_kinds.emplace(name, kind);
    }

private:
    const reader& m_r;
    std::map<std::string, std::string, std::less<>> m_kinds;
};

int state_index(const description& d, std::string_view name)
{
    for (std::size_t j = 0; j < d.state.size(); ++j)
        if (d.state[j].name == name) return static_cast<int>(j);
    return -1;
}

std::string state_list(const description& d)
{
    std::vector<std::string> names;
    for (const auto& s : d.state) names.push_back(s.name);
    return comma_list(names);
}

std::string parameter_list(const description& d)
{
    std::vector<std::string> names;
    for (const auto& p : d.parameters) names.push_back(p.name);
    return names.empty() ? std::string("none") : comma_list(names);
}

// name = "expression" for each state variable named; the others keep their value.
std::vector<assignment> read_assignments(const reader& r, const description& d, const json& v, const std::string& path)
{
    std::vector<assignment> out;
    for (auto it = r.object(v, path).begin(); it != v.end(); ++it) {
        const std::string key = join(path, it.key());
        const int j = state_index(d, it.key());
        if (j < 0) r.fail(key, "'" + it.key() + "' is not a state variable (state: " + state_list(d) + ")");
        out.push_back({j, r.expression(it.value(), key)});
    }
    return out;
}

void read_state(const reader& r, name_space& names, description& d, const json& tree)
{
    const json& state = r.array(r.require(tree, "", "state"), "state");
    if (state.empty()) r.fail("state", "needs at least one state variable");
    for (std::size_t j = 0; j < state.size(); ++j) {
        const std::string path = item("state", j);
        const json& v = state[j];
        state_decl s;
        if (v.is_string()) {
            s.name = r.name(v, path);
            names.add(path, s.name, "a state variable");
        } else if (v.is_object()) {
            r.keys(v, path, {"name", "meaning", "unit"});
            s.name = r.name(r.require(v, path, "name"), join(path, "name"));
            names.add(join(path, "name"), s.name, "a state variable");
            s.meaning = r.optional_string(v, path, "meaning");
            s.unit = r.optional_string(v, path, "unit");
        } else {
            r.fail(path, "expected a name or a table {name, meaning, unit}, got " + type_name(v));
        }
        d.state.push_back(std::move(s));
    }
}

void read_parameters(const reader& r, name_space& names, description& d, const json& tree)
{
    const json& params = r.object(r.require(tree, "", "parameters"), "parameters");
    for (auto it = params.begin(); it != params.end(); ++it) {
        const std::string path = join("parameters", it.key());
        parameter_decl p;
        if (!is_identifier(it.key()))
            r.fail(path, "'" + it.key() + "' is not a valid name (letters, digits and _, starting with a letter)");
        p.name = it.key();
        names.add(path, p.name, "a parameter");
        const json& v = it.value();
        if (v.is_number()) {
            p.default_value = r.number(v, path);
        } else if (v.is_object()) {
            r.keys(v, path, {"default", "meaning", "unit", "min", "max", "above", "below"});
            p.default_value = r.number(r.require(v, path, "default"), join(path, "default"));
            p.meaning = r.optional_string(v, path, "meaning");
            p.unit = r.optional_string(v, path, "unit");
            const json* min = reader::find(v, "min");
            const json* above = reader::find(v, "above");
            const json* max = reader::find(v, "max");
            const json* below = reader::find(v, "below");
            if (min && above) r.fail(path, "give min (a closed bound) or above (an open one), not both");
            if (max && below) r.fail(path, "give max (a closed bound) or below (an open one), not both");
            if (min) p.range.lower = r.number(*min, join(path, "min")), p.range.lower_inclusive = true;
            if (above) p.range.lower = r.number(*above, join(path, "above"));
            if (max) p.range.upper = r.number(*max, join(path, "max")), p.range.upper_inclusive = true;
            if (below) p.range.upper = r.number(*below, join(path, "below"));
            const bool empty = p.range.lower > p.range.upper ||
                               (p.range.lower == p.range.upper && !(p.range.lower_inclusive && p.range.upper_inclusive));
            if (empty) r.fail(path, "the range " + p.range.text() + " is empty");
        } else {
            r.fail(path, "expected a default value or a table {default, meaning, unit, min, max, above, below}, got " +
                             type_name(v));
        }
        if (!p.range.admits(p.default_value))
            r.fail(path, "the default " + format_double(p.default_value) + " is outside the range " + p.range.text());
        d.parameters.push_back(std::move(p));
    }
}

std::vector<named_expression> read_named(const reader& r, name_space& names, const json& tree, std::string_view key,
                                         const char* kind)
{
    std::vector<named_expression> out;
    const json* v = reader::find(tree, key);
    if (!v) return out;
    const std::string section(key);
    for (auto it = r.object(*v, section).begin(); it != v->end(); ++it) {
        const std::string path = join(section, it.key());
        if (!is_identifier(it.key()))
            r.fail(path, "'" + it.key() + "' is not a valid name (letters, digits and _, starting with a letter)");
        names.add(path, it.key(), kind);
        out.push_back({it.key(), r.expression(it.value(), path)});
    }
    return out;
}

void read_derivatives(const reader& r, description& d, const json& tree)
{
    const json& eqs = r.object(r.require(tree, "", "derivatives"), "derivatives");
    std::vector<std::optional<expression_text>> by_state(d.state.size());
    for (auto it = eqs.begin(); it != eqs.end(); ++it) {
        const std::string path = join("derivatives", it.key());
        const int j = state_index(d, it.key());
        if (j < 0) r.fail(path, "'" + it.key() + "' is not a state variable (state: " + state_list(d) + ")");
        by_state[static_cast<std::size_t>(j)] = r.expression(it.value(), path);
    }
    for (std::size_t j = 0; j < d.state.size(); ++j) {
        if (!by_state[j]) r.fail("derivatives", "no equation for state variable '" + d.state[j].name + "'");
        d.derivatives.push_back(std::move(*by_state[j]));
    }
}

void read_angles(const reader& r, description& d, const json& tree)
{
    const json* angles = reader::find(tree, "angles");
    if (!angles) return;
    for (auto it = r.object(*angles, "angles").begin(); it != angles->end(); ++it) {
        const std::string path = join("angles", it.key());
        const int j = state_index(d, it.key());
        if (j < 0) r.fail(path, "'" + it.key() + "' is not a state variable (state: " + state_list(d) + ")");
        d.state[static_cast<std::size_t>(j)].period = r.expression(it.value(), path);
    }
}

void read_initial_state(const reader& r, description& d, const json& tree)
{
    d.initial_state.assign(d.state.size(), 0.0);
    const json* init = reader::find(tree, "initial_state");
    if (!init) return;
    const json& a = r.array(*init, "initial_state");
    if (a.size() != d.state.size())
        r.fail("initial_state", "needs " + std::to_string(d.state.size()) + " numbers (" + state_list(d) + "), got " +
                                    std::to_string(a.size()));
    for (std::size_t j = 0; j < a.size(); ++j) d.initial_state[j] = r.number(a[j], item("initial_state", j));
}

void read_surfaces(const reader& r, description& d, const json& tree)
{
    const json* surfaces = reader::find(tree, "surfaces");
    if (!surfaces) return;
    const json& a = r.array(*surfaces, "surfaces");
    for (std::size_t i = 0; i < a.size(); ++i) {
        const std::string path = item("surfaces", i);
        const json& v = r.object(a[i], path);
        r.keys(v, path, {"name", "meaning", "gap", "reset", "sticking"});
        surface_decl s;
        s.name = r.name(r.require(v, path, "name"), join(path, "name"));
        for (const auto& other : d.surfaces)
            if (other.name == s.name) r.fail(join(path, "name"), "a surface named '" + s.name + "' is already declared");
        s.meaning = r.optional_string(v, path, "meaning");
        s.gap = r.expression(r.require(v, path, "gap"), join(path, "gap"));
        s.reset = read_assignments(r, d, r.require(v, path, "reset"), join(path, "reset"));
        if (const json* st = reader::find(v, "sticking")) {
            const std::string sp = join(path, "sticking");
            r.keys(r.object(*st, sp), sp, {"rest", "derivatives", "release"});
            sticking_decl k;
            if (const json* rest = reader::find(*st, "rest")) k.rest = read_assignments(r, d, *rest, join(sp, "rest"));
            if (const json* f = reader::find(*st, "derivatives"))
                k.derivatives = read_assignments(r, d, *f, join(sp, "derivatives"));
            k.release = r.expression(r.require(*st, sp, "release"), join(sp, "release"));
            s.sticking = std::move(k);
        }
        d.surfaces.push_back(std::move(s));
    }
}

crossing read_direction(const reader& r, const json& v, const std::string& path)
{
    const std::string dir = r.string(v, path);
    if (dir == "down") return crossing::down;
    if (dir == "up") return crossing::up;
    if (dir == "both") return crossing::both;
    r.fail(path, "'" + dir + "' is not a direction (valid: up, down, both)");
}

void read_switches(const reader& r, name_space& names, description& d, const json& tree)
{
    const json* switches = reader::find(tree, "switches");
    if (!switches) return;
    const json& a = r.array(*switches, "switches");
    for (std::size_t k = 0; k < a.size(); ++k) {
        const std::string path = item("switches", k);
        const json& v = r.object(a[k], path);
        r.keys(v, path, {"name", "meaning", "when", "reset", "direction"});
        switch_decl s;
        s.name = r.name(r.require(v, path, "name"), join(path, "name"));
        names.add(join(path, "name"), s.name, "a switch");
        s.meaning = r.optional_string(v, path, "meaning");
        s.when = r.expression(r.require(v, path, "when"), join(path, "when"));
        if (const json* reset = reader::find(v, "reset")) s.reset = read_assignments(r, d, *reset, join(path, "reset"));
        if (const json* dir = reader::find(v, "direction")) s.direction = read_direction(r, *dir, join(path, "direction"));
        d.switches.push_back(std::move(s));
    }
    if (d.switches.size() > 64) r.fail("switches", "at most 64 switches, got " + std::to_string(d.switches.size()));
}

void read_sections(const reader& r, description& d, const json& tree)
{
    const json* sections = reader::find(tree, "sections");
    if (!sections) return;
    const json& a = r.array(*sections, "sections");
    for (std::size_t k = 0; k < a.size(); ++k) {
        const std::string path = item("sections", k);
        const json& v = r.object(a[k], path);
        r.keys(v, path, {"name", "meaning", "when", "direction"});
        section_decl s;
        s.name = r.name(r.require(v, path, "name"), join(path, "name"));
        for (const auto& other : d.sections)
            if (other.name == s.name) r.fail(join(path, "name"), "a section named '" + s.name + "' is already declared");
        s.meaning = r.optional_string(v, path, "meaning");
        s.when = r.expression(r.require(v, path, "when"), join(path, "when"));
        s.direction = read_direction(r, r.require(v, path, "direction"), join(path, "direction"));
        d.sections.push_back(std::move(s));
    }
}

void read_presets(const reader& r, description& d, const json& tree)
{
    const json* presets = reader::find(tree, "presets");
    if (!presets) return;
    for (auto it = r.object(*presets, "presets").begin(); it != presets->end(); ++it) {
        const std::string path = join("presets", it.key());
        if (!is_identifier(it.key()))
            r.fail(path, "'" + it.key() + "' is not a valid name (letters, digits and _, starting with a letter)");
        preset_decl p;
        p.name = it.key();
        for (auto kv = r.object(it.value(), path).begin(); kv != it.value().end(); ++kv) {
            const std::string key = join(path, kv.key());
            if (kv.key() == "meaning" && kv.value().is_string()) {
                p.meaning = kv.value().get<std::string>();
                continue;
            }
            const auto q = std::find_if(d.parameters.begin(), d.parameters.end(),
                                        [&](const parameter_decl& x) { return x.name == kv.key(); });
            if (q == d.parameters.end())
                r.fail(key, "'" + kv.key() + "' is not a parameter (parameters: " + parameter_list(d) +
                                "; or meaning = \"...\")");
            const double value = r.number(kv.value(), key);
            if (!q->range.admits(value))
                r.fail(key, format_double(value) + " is outside the range of " + q->name + " (" + q->range.text() + ")");
            p.values.emplace_back(static_cast<int>(q - d.parameters.begin()), value);
        }
        d.presets.push_back(std::move(p));
    }
}

json range_json(const value_range& r)
{
    json j = json::object();
    if (std::isfinite(r.lower)) j[r.lower_inclusive ? "min" : "above"] = r.lower;
    if (std::isfinite(r.upper)) j[r.upper_inclusive ? "max" : "below"] = r.upper;
    return j;
}

json assignments_json(const description& d, const std::vector<assignment>& a)
{
    // In state order, so that the order of the keys in the file does not matter.
    std::vector<assignment> sorted = a;
    std::sort(sorted.begin(), sorted.end(), [](const assignment& x, const assignment& y) { return x.index < y.index; });
    json j = json::object();
    for (const auto& s : sorted) j[d.state[static_cast<std::size_t>(s.index)].name] = s.expr.text;
    return j;
}

}  // namespace

description describe(const json& tree, const std::string& where)
{
    const reader r(where);
    if (!tree.is_object()) r.fail("expected a table of keys (name, state, parameters, derivatives, ...), got " +
                                  type_name(tree));
    r.keys(tree, "", {"name", "description", "state", "initial_state", "parameters", "derived", "expressions",
                      "derivatives", "angles", "surfaces", "sections", "switches", "presets"});
    description d;
    d.name = r.name(r.require(tree, "", "name"), "name");
    d.description = r.optional_string(tree, "", "description");

    name_space names(r);
    read_state(r, names, d, tree);
    check_engine_dimension(static_cast<int>(d.state.size()), where);
    read_parameters(r, names, d, tree);
    d.derived = read_named(r, names, tree, "derived", "a derived quantity");
    d.expressions = read_named(r, names, tree, "expressions", "a named expression");
    read_derivatives(r, d, tree);
    read_angles(r, d, tree);
    read_initial_state(r, d, tree);
    read_surfaces(r, d, tree);
    read_sections(r, d, tree);
    read_switches(r, names, d, tree);
    read_presets(r, d, tree);
    return d;
}

json canonical_json(const description& d)
{
    json j = json::object();
    j["name"] = d.name;
    j["description"] = d.description;
    json state = json::array();
    for (const auto& s : d.state) {
        json v = {{"name", s.name}, {"meaning", s.meaning}, {"unit", s.unit}};
        if (s.period) v["period"] = s.period->text;
        state.push_back(std::move(v));
    }
    j["state"] = std::move(state);
    j["initial_state"] = d.initial_state;
    json params = json::array();
    for (const auto& p : d.parameters)
        params.push_back({{"name", p.name},
                          {"meaning", p.meaning},
                          {"unit", p.unit},
                          {"default", p.default_value},
                          {"range", range_json(p.range)}});
    j["parameters"] = std::move(params);
    json derived = json::array();
    for (const auto& n : d.derived) derived.push_back({n.name, n.expr.text});
    j["derived"] = std::move(derived);
    json expressions = json::array();
    for (const auto& n : d.expressions) expressions.push_back({n.name, n.expr.text});
    j["expressions"] = std::move(expressions);
    json derivatives = json::array();
    for (const auto& e : d.derivatives) derivatives.push_back(e.text);
    j["derivatives"] = std::move(derivatives);
    json surfaces = json::array();
    for (const auto& s : d.surfaces) {
        json v = {{"name", s.name}, {"meaning", s.meaning}, {"gap", s.gap.text}, {"reset", assignments_json(d, s.reset)}};
        if (s.sticking)
            v["sticking"] = {{"rest", assignments_json(d, s.sticking->rest)},
                             {"derivatives", assignments_json(d, s.sticking->derivatives)},
                             {"release", s.sticking->release.text}};
        surfaces.push_back(std::move(v));
    }
    j["surfaces"] = std::move(surfaces);
    json sections = json::array();
    for (const auto& s : d.sections)
        sections.push_back({{"name", s.name},
                            {"meaning", s.meaning},
                            {"when", s.when.text},
                            {"direction", std::string(to_string(s.direction))}});
    j["sections"] = std::move(sections);
    // Only when there are switches: the models without keep the identity they had.
    if (!d.switches.empty()) {
        json switches = json::array();
        for (const auto& s : d.switches)
            switches.push_back({{"name", s.name},
                                {"meaning", s.meaning},
                                {"when", s.when.text},
                                {"reset", assignments_json(d, s.reset)},
                                {"direction", std::string(to_string(s.direction))}});
        j["switches"] = std::move(switches);
    }
    json presets = json::array();
    for (const auto& p : d.presets) {
        json values = json::array();
        for (const auto& [i, v] : p.values) values.push_back({i, v});
        presets.push_back({{"name", p.name}, {"meaning", p.meaning}, {"values", std::move(values)}});
    }
    j["presets"] = std::move(presets);
    return j;
}

}  // namespace vimpact::model_file_detail
