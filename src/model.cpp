#include "vimpact/model/model.hpp"
#include "vimpact/model/model_phrases.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <mutex>

#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/model/builtin/forced_impact_oscillator.hpp"
#include "vimpact/model/builtin/two_sided_impact_oscillator.hpp"
#include "vimpact/model/builtin/wake_impact.hpp"
#include "vimpact/model/export.hpp"
#include "vimpact/model/model_file.hpp"

namespace vimpact {

namespace {

template <class Items>
int index_of(const Items& items, std::string_view name)
{
    for (std::size_t i = 0; i < items.size(); ++i)
        if (items[i].name == name) return static_cast<int>(i);
    return -1;
}

template <class Items>
std::string names_of(const Items& items)
{
    std::string s;
    for (const auto& it : items) s += (s.empty() ? "" : ", ") + it.name;
    return s;
}

std::string text_or_empty(const char* const* a, int i) { return a && a[i] ? std::string(a[i]) : std::string(); }

struct builtin_entry {
    std::string_view name;
    const vimpact_model_table& (*table)();
    native_kind native;
};

const std::array<builtin_entry, 3>& builtins()
{
    static const std::array<builtin_entry, 3> list{{
        {wake_impact::name, &definition_table<wake_impact>, native_kind::wake_impact},
        {forced_impact_oscillator::name, &definition_table<forced_impact_oscillator>,
         native_kind::forced_impact_oscillator},
        {two_sided_impact_oscillator::name, &definition_table<two_sided_impact_oscillator>,
         native_kind::two_sided_impact_oscillator},
    }};
    return list;
}

std::shared_ptr<const model_code> builtin_code(std::string_view name)
{
    for (const auto& b : builtins()) {
        if (b.name != name) continue;
        // One code object per built-in, shared by every model made from it.
        static std::array<std::shared_ptr<const model_code>, 3> cache;
        const auto k = static_cast<std::size_t>(&b - builtins().data());
        static std::once_flag once[3];
        std::call_once(once[k], [&] {
            auto c = std::make_shared<model_code>();
            c->table = &b.table();
            c->info = info_from_table(*c->table);
            c->info.source = "built-in";
            c->info.identity = std::string(b.name);
            c->native = b.native;
            cache[k] = std::move(c);
        });
        return cache[k];
    }
    std::string valid;
    for (const auto& b : builtins()) valid += (valid.empty() ? "" : ", ") + std::string(b.name);
    throw input_error("unknown model '" + std::string(name) + "' (built-in models: " + valid +
                      "; or a model file NAME.toml, or a shared library)");
}

}  // namespace

int model_info::state_index(std::string_view n) const { return index_of(state, n); }
int model_info::parameter_index(std::string_view n) const { return index_of(parameters, n); }
int model_info::surface_index(std::string_view n) const { return index_of(surfaces, n); }
int model_info::section_index(std::string_view n) const { return index_of(sections, n); }
int model_info::preset_index(std::string_view n) const { return index_of(presets, n); }
std::string model_info::state_names() const { return names_of(state); }
std::string model_info::parameter_names() const { return names_of(parameters); }
std::string model_info::surface_names() const { return names_of(surfaces); }
std::string model_info::section_names() const { return names_of(sections); }
std::string model_info::preset_names() const { return names_of(presets); }

namespace {
template <class Items>
std::string it_has(const model_info& m, const Items& items, const char* kind)
{
    return "model " + m.name + " has " + (items.empty() ? std::string("no ") + kind : names_of(items));
}
}  // namespace

std::string parameters_it_has(const model_info& m) { return it_has(m, m.parameters, "parameters"); }
std::string sections_it_has(const model_info& m) { return it_has(m, m.sections, "sections"); }
std::string surfaces_it_has(const model_info& m) { return it_has(m, m.surfaces, "surfaces"); }

int parameter_index(const model& m, const std::string& name, const std::string& what)
{
    const int i = m.info().parameter_index(name);
    if (i < 0) throw input_error("unknown parameter '" + name + "' for " + what + " (" + parameters_it_has(m.info()) + ")");
    return i;
}

int state_index(const model& m, const std::string& name, const std::string& what)
{
    const int i = m.info().state_index(name);
    if (i < 0)
        throw input_error(what + ": '" + name + "' is not one of " + m.info().state_names() + " (the state of model " +
                          m.name() + ")");
    return i;
}
bool model_info::has_angles() const
{
    return std::any_of(state.begin(), state.end(), [](const auto& s) { return s.period > 0.0; });
}

std::vector<std::string> coordinate_names(const model_info& m)
{
    std::vector<std::string> out;
    for (const auto& v : m.state) {
        if (v.period > 0.0) {
            out.push_back(v.name + "_cos");
            out.push_back(v.name + "_sin");
        } else {
            out.push_back(v.name);
        }
    }
    return out;
}

void state_coordinates(const model_info& m, const double* x, double* out)
{
    for (std::size_t k = 0; k < m.state.size(); ++k) {
        const double p = m.state[k].period;
        if (p > 0.0) {
            const double s = p / (2.0 * std::numbers::pi);
            *out++ = s * std::cos(x[k] / s);
            *out++ = s * std::sin(x[k] / s);
        } else {
            *out++ = x[k];
        }
    }
}

model_info info_from_table(const vimpact_model_table& t)
{
    model_info m;
    m.name = t.name ? t.name : "";
    m.description = t.description ? t.description : "";
    for (int i = 0; i < t.dim; ++i)
        m.state.push_back({text_or_empty(t.state_names, i), text_or_empty(t.state_meanings, i),
                           text_or_empty(t.state_units, i), t.state_periods ? t.state_periods[i] : 0.0});
    for (int i = 0; i < t.parameter_count; ++i) {
        parameter_info p;
        p.name = text_or_empty(t.parameter_names, i);
        p.meaning = text_or_empty(t.parameter_meanings, i);
        p.unit = text_or_empty(t.parameter_units, i);
        p.default_value = t.parameter_defaults[i];
        p.range.lower = t.parameter_lower[i];
        p.range.upper = t.parameter_upper[i];
        p.range.lower_inclusive = (t.parameter_bounds_closed[i] & 1) != 0;
        p.range.upper_inclusive = (t.parameter_bounds_closed[i] & 2) != 0;
        m.parameters.push_back(std::move(p));
    }
    for (int i = 0; i < t.surface_count; ++i)
        m.surfaces.push_back({text_or_empty(t.surface_names, i), text_or_empty(t.surface_meanings, i),
                              t.surface_sticks[i] != 0});
    for (int k = 0; k < t.section_count; ++k)
        m.sections.push_back({text_or_empty(t.section_names, k), text_or_empty(t.section_meanings, k),
                              static_cast<crossing>(t.section_directions[k])});
    for (int k = 0; k < t.switch_count; ++k)
        m.switches.push_back({text_or_empty(t.switch_names, k), text_or_empty(t.switch_meanings, k),
                              static_cast<crossing>(t.switch_directions[k])});
    for (int k = 0, offset = 0; k < t.preset_count; ++k) {
        preset_info p{text_or_empty(t.preset_names, k), text_or_empty(t.preset_meanings, k), {}};
        for (int j = 0; j < t.preset_sizes[k]; ++j, ++offset)
            p.values.emplace_back(t.preset_parameters[offset], t.preset_values[offset]);
        m.presets.push_back(std::move(p));
    }
    m.initial_state.assign(static_cast<std::size_t>(t.dim), 0.0);
    if (t.initial_state) m.initial_state.assign(t.initial_state, t.initial_state + t.dim);
    return m;
}

model::model() : model(builtin("wake_impact")) {}

model::model(std::shared_ptr<const model_code> code, std::vector<double> parameters)
    : m_code(std::move(code)), m_parameters(std::move(parameters))
{
    const auto& info = m_code->info;
    if (m_parameters.size() != info.parameters.size())
        throw input_error("model " + info.name + " needs " + std::to_string(info.parameters.size()) +
                          " parameter values (got " + std::to_string(m_parameters.size()) + ")");
    for (std::size_t i = 0; i < m_parameters.size(); ++i) check_parameter(info.parameters[i], m_parameters[i]);
    char error[512] = {0};
    void* ctx = m_code->table->create(m_parameters.data(), error, sizeof error);
    if (!ctx)
        throw input_error("model " + info.name + " refuses its parameters" +
                          (error[0] ? ": " + std::string(error) : std::string()));
    const auto* table = m_code->table;
    m_context = std::shared_ptr<void>(ctx, [table](void* c) { table->destroy(c); });
}

void model::check_parameter(const parameter_info& p, double value)
{
    // A subnormal value (e.g. 4.9e-324) is inside a range like (0, inf) but its reciprocals
    // overflow: the run would end in a step underflow with no word why.
    if (value != 0.0 && std::fpclassify(value) == FP_SUBNORMAL)
        throw input_error("parameter " + p.name + " = " + format_double(value) +
                          " is subnormal: give 0 or a value of magnitude >= 2.2e-308");
    if (!p.range.admits(value))
        throw input_error("parameter " + p.name + " = " + format_double(value) + " is outside its valid range " +
                          p.range.text() + (p.meaning.empty() ? std::string() : " (" + p.meaning + ")"));
}

model model::builtin(std::string_view name)
{
    return with_defaults(builtin_code(name));
}

std::vector<std::string> model::builtin_names()
{
    std::vector<std::string> v;
    for (const auto& b : builtins()) v.emplace_back(b.name);
    return v;
}

model model::from_table(const vimpact_model_table& table, std::string_view source, native_kind native)
{
    auto code = std::make_shared<model_code>();
    code->table = &table;
    code->info = info_from_table(table);
    code->info.source = std::string(source);
    code->info.identity = code->info.name + "@" + std::string(source);
    code->native = native;
    return with_defaults(std::move(code));
}

model model::from_file(const std::filesystem::path& path) { return with_defaults(load_model_code(path)); }

model model::from_toml(std::string_view text, std::string_view source)
{
    return with_defaults(compile_model_text(text, source));
}

model model::with_defaults(std::shared_ptr<const model_code> code)
{
    std::vector<double> defaults;
    for (const auto& p : code->info.parameters) defaults.push_back(p.default_value);
    return {std::move(code), std::move(defaults)};
}

Eigen::VectorXd model::initial_state() const
{
    const auto& x = m_code->info.initial_state;
    return Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()));
}

model model::with_parameter(int index, double value) const
{
    if (index < 0 || index >= static_cast<int>(m_parameters.size()))
        throw input_error("parameter index " + std::to_string(index) + " is out of range for model " + name());
    std::vector<double> p = m_parameters;
    p[static_cast<std::size_t>(index)] = value;
    return {m_code, std::move(p)};
}

model model::with_parameters(std::span<const double> values) const
{
    return {m_code, std::vector<double>(values.begin(), values.end())};
}

model model::with_preset(int preset) const
{
    const auto& info = m_code->info;
    if (preset < 0 || preset >= static_cast<int>(info.presets.size()))
        throw input_error("preset index " + std::to_string(preset) + " is out of range for model " + name());
    std::vector<double> p;
    for (const auto& q : info.parameters) p.push_back(q.default_value);
    for (const auto& [i, v] : info.presets[static_cast<std::size_t>(preset)].values) p[static_cast<std::size_t>(i)] = v;
    return {m_code, std::move(p)};
}

bool operator==(const model& a, const model& b)
{
    return a.m_code->info.identity == b.m_code->info.identity && a.m_parameters == b.m_parameters;
}

const std::vector<int>& engine_dimensions()
{
    static const std::vector<int> dims{VIMPACT_MODEL_DIMS};
    return dims;
}

void check_engine_dimension(int dim, std::string_view what)
{
    if (dim >= 1 && dim <= max_model_dimension) return;
    throw input_error(std::string(what) + " has " + std::to_string(dim) + " state variables; vimpact runs models with 1 to " +
                      std::to_string(max_model_dimension) + " (a tangent run carries N + N^2 numbers per state)");
}

int violated_surface(const model& m, const Eigen::VectorXd& x)
{
    const auto& t = m.table();
    Eigen::VectorXd f(m.dim()), n(m.dim());
    t.rhs(m.context(), x.data(), f.data());
    for (int i = 0; i < m.surface_count(); ++i) {
        const double g = t.gap(m.context(), i, x.data());
        if (g > 0.0) continue;
        t.gap_gradient(m.context(), i, x.data(), n.data());
        if (g < 0.0 || n.dot(f) < 0.0) return i;
    }
    return -1;
}

void check_state_size(const model& m, Eigen::Index size, std::string_view what)
{
    if (size != m.dim())
        throw input_error(std::string(what) + " needs " + std::to_string(m.dim()) + " numbers (" +
                          m.info().state_names() + "), got " + std::to_string(size));
}

}  // namespace vimpact
