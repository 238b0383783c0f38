#pragma once
// The function table (model/abi.h) of a C++ model definition (model/definition.hpp): how a
// definition becomes a runtime model (model::from_definition<D>()) and how a shared library
// makes its model loadable by the command line and Python:
//
//   // my_model.cpp, built with add_library(my_model MODULE my_model.cpp)
//   #include <vimpact/model/export.hpp>
//   struct my_model { ... };
//   VIMPACT_EXPORT_MODEL(my_model)
//
//   vimpact period --model ./libmy_model.so
#include <algorithm>
#include <cstring>
#include <deque>
#include <exception>
#include <string>
#include <vector>

#include "vimpact/integrate/fused_step.hpp"
#include "vimpact/model/abi.h"
#include "vimpact/model/model.hpp"
#include "vimpact/model/native_model.hpp"

namespace vimpact {

namespace detail {

template <model_definition D>
class definition_table {
public:
    static constexpr int N = definition_dim<D>;
    using model_type = native_model<D>;

    definition_table()
    {
        m_table.abi_version = VIMPACT_MODEL_ABI_VERSION;
        m_table.dim = N;
        m_table.parameter_count = static_cast<int>(D::parameters.size());
        m_table.surface_count = static_cast<int>(D::surfaces.size());
        m_table.section_count = static_cast<int>(D::sections.size());
        m_table.name = keep(D::name);
        m_table.description = keep(D::description);
        for (const auto& s : D::state) {
            m_state_names.push_back(keep(s.name));
            m_state_meanings.push_back(keep(s.meaning));
            m_state_units.push_back(keep(s.unit));
            m_state_periods.push_back(s.period);
        }
        if constexpr (requires { D::initial_state; })
            m_initial.assign(D::initial_state.begin(), D::initial_state.end());
        else
            m_initial.assign(N, 0.0);
        for (const auto& p : D::parameters) {
            m_parameter_names.push_back(keep(p.name));
            m_parameter_meanings.push_back(keep(p.meaning));
            m_parameter_units.push_back(keep(p.unit));
            m_defaults.push_back(p.default_value);
            m_lower.push_back(p.range.lower);
            m_upper.push_back(p.range.upper);
            m_closed.push_back((p.range.lower_inclusive ? 1 : 0) | (p.range.upper_inclusive ? 2 : 0));
        }
        for (const auto& s : D::surfaces) {
            m_surface_names.push_back(keep(s.name));
            m_surface_meanings.push_back(keep(s.meaning));
            m_sticks.push_back(s.sticks ? 1 : 0);
            m_surface_affine.push_back(s.affine ? 1 : 0);
        }
        for (const auto& s : D::sections) {
            m_section_names.push_back(keep(s.name));
            m_section_meanings.push_back(keep(s.meaning));
            m_directions.push_back(static_cast<int>(s.direction));
            m_section_affine.push_back(s.affine ? 1 : 0);
        }
        if constexpr (requires { D::presets; }) {
            for (const auto& pr : D::presets) {
                m_preset_names.push_back(keep(pr.name));
                m_preset_meanings.push_back(keep(pr.meaning));
                int size = 0;
                for (const auto& v : pr.values) {
                    const auto it = std::find_if(D::parameters.begin(), D::parameters.end(),
                                                 [&](const parameter& p) { return p.name == v.parameter; });
                    if (it == D::parameters.end()) continue;
                    m_preset_parameters.push_back(static_cast<int>(it - D::parameters.begin()));
                    m_preset_values.push_back(v.value);
                    ++size;
                }
                m_preset_sizes.push_back(size);
            }
        }
        m_table.preset_count = static_cast<int>(m_preset_names.size());

        m_table.state_names = m_state_names.data();
        m_table.state_meanings = m_state_meanings.data();
        m_table.state_units = m_state_units.data();
        m_table.state_periods = m_state_periods.data();
        m_table.initial_state = m_initial.data();
        m_table.parameter_names = m_parameter_names.data();
        m_table.parameter_meanings = m_parameter_meanings.data();
        m_table.parameter_units = m_parameter_units.data();
        m_table.parameter_defaults = m_defaults.data();
        m_table.parameter_lower = m_lower.data();
        m_table.parameter_upper = m_upper.data();
        m_table.parameter_bounds_closed = m_closed.data();
        m_table.surface_names = m_surface_names.data();
        m_table.surface_meanings = m_surface_meanings.data();
        m_table.surface_sticks = m_sticks.data();
        m_table.section_names = m_section_names.data();
        m_table.section_meanings = m_section_meanings.data();
        m_table.section_directions = m_directions.data();
        m_table.surface_affine = m_surface_affine.data();
        m_table.section_affine = m_section_affine.data();
        m_table.preset_names = m_preset_names.data();
        m_table.preset_meanings = m_preset_meanings.data();
        m_table.preset_sizes = m_preset_sizes.data();
        m_table.preset_parameters = m_preset_parameters.data();
        m_table.preset_values = m_preset_values.data();

        m_table.create = &create;
        m_table.destroy = &destroy;
        m_table.rhs = [](const void* c, const double* x, double* f) { out(f) = m(c).rhs(in(x)); };
        m_table.jacobian = [](const void* c, const double* x, double* J) { matrix_out(J) = m(c).jacobian(in(x)); };
        m_table.second_derivative = [](const void* c, const double* x, const double* u, const double* w, double* o) {
            out(o) = m(c).second_derivative(in(x), in(u), in(w));
        };
        m_table.divergence = [](const void* c, const double* x) { return m(c).divergence(in(x)); };
        m_table.gap = [](const void* c, int i, const double* x) { return m(c).gap(i, in(x)); };
        m_table.gap_gradient = [](const void* c, int i, const double* x, double* o) { out(o) = m(c).gap_gradient(i, in(x)); };
        m_table.gap_hessian = [](const void* c, int i, const double* x, double* o) {
            matrix_out(o) = m(c).gap_hessian(i, in(x));
        };
        m_table.reset = [](const void* c, int i, const double* x, double* o) { out(o) = m(c).reset(i, in(x)); };
        m_table.reset_jacobian = [](const void* c, int i, const double* x, double* o) {
            matrix_out(o) = m(c).reset_jacobian(i, in(x));
        };
        m_table.reset_second_derivative = [](const void* c, int i, const double* x, const double* u, const double* w,
                                             double* o) {
            out(o) = m(c).reset_second_derivative(i, in(x), in(u), in(w));
        };
        m_table.section = [](const void* c, int k, const double* x) { return m(c).section(k, in(x)); };
        m_table.section_gradient = [](const void* c, int k, const double* x, double* o) {
            out(o) = m(c).section_gradient(k, in(x));
        };
        m_table.sticking_rhs = [](const void* c, int i, const double* x, double* o) { out(o) = m(c).sticking_rhs(i, in(x)); };
        m_table.release = [](const void* c, int i, const double* x) { return m(c).release(i, in(x)); };
        m_table.release_gradient = [](const void* c, int i, const double* x, double* o) {
            out(o) = m(c).release_gradient(i, in(x));
        };
        m_table.rest = [](const void* c, int i, const double* x, double* o) { out(o) = m(c).rest(i, in(x)); };
        if constexpr (model_type::switches > 0) add_switches();
        m_table.step = &fused_step_entry<N, field>;
        m_table.dense = &fused_dense_entry<N, field>;
        m_table.samples = [](const void* c, const double* x, const double* f, double* gaps, double* sections) {
            const auto& mm = m(c);
            for (int i = 0; i < model_type::surface_count(); ++i) {
                gaps[2 * i] = mm.gap(i, in(x));
                gaps[2 * i + 1] = mm.gap_gradient(i, in(x)).dot(in(f));
            }
            for (int k = 0; k < model_type::section_count(); ++k) {
                sections[2 * k] = mm.section(k, in(x));
                sections[2 * k + 1] = mm.section_gradient(k, in(x)).dot(in(f));
            }
        };
    }

    [[nodiscard]] const vimpact_model_table& table() const { return m_table; }

private:
    void add_switches()
    {
        m_table.switch_count = model_type::switches;
        for (const auto& s : D::switches) {
            m_switch_names.push_back(keep(s.name));
            m_switch_meanings.push_back(keep(s.meaning));
            m_switch_directions.push_back(static_cast<int>(s.direction));
            m_switch_affine.push_back(s.affine ? 1 : 0);
        }
        m_table.switch_names = m_switch_names.data();
        m_table.switch_meanings = m_switch_meanings.data();
        m_table.switch_directions = m_switch_directions.data();
        m_table.switch_affine = m_switch_affine.data();
        m_table.switching = [](const void* c, int k, const double* x) { return m(c).switching(k, in(x)); };
        m_table.switching_gradient = [](const void* c, int k, const double* x, double* o) {
            out(o) = m(c).switching_gradient(k, in(x));
        };
        m_table.copy_context = [](const void* c) -> void* { return new model_type(m(c)); };
        m_table.pin_sides = [](void* c, unsigned long long negative) {
            static_cast<model_type*>(c)->pin_sides(switch_sides::from_bits(negative));
        };
        m_table.sides_at = [](const void* c, const double* x) -> unsigned long long {
            return m(c).sides_at(in(x)).negative_bits();
        };
        m_table.cross = [](void* c, int k, const double* x, double* o) {
            vec<N> after;
            const bool applied = static_cast<model_type*>(c)->cross(k, in(x), after);
            out(o) = after;
            return applied ? 1 : 0;
        };
        m_table.switch_reset_jacobian = [](const void* c, int k, const double* x, double* o) {
            matrix_out(o) = m(c).switch_reset_jacobian(k, in(x));
        };
    }

    // The free field for the fused Runge-Kutta steps (integrate/fused_step.hpp).
    struct field {
        const void* c;
        vec<N> operator()(const vec<N>& x) const { return static_cast<const model_type*>(c)->rhs(x); }
    };

    static const model_type& m(const void* c) { return *static_cast<const model_type*>(c); }
    static Eigen::Map<const vec<N>> in(const double* x) { return Eigen::Map<const vec<N>>(x); }
    static Eigen::Map<vec<N>> out(double* x) { return Eigen::Map<vec<N>>(x); }
    static Eigen::Map<mat<N>> matrix_out(double* x) { return Eigen::Map<mat<N>>(x); }

    static void* create(const double* parameters, char* error, size_t error_size)
    {
        try {
            return new model_type(std::span<const double>(parameters, D::parameters.size()));
        } catch (const std::exception& e) {
            if (error && error_size > 0) {
                std::strncpy(error, e.what(), error_size - 1);
                error[error_size - 1] = '\0';
            }
            return nullptr;
        }
    }
    static void destroy(void* c) { delete static_cast<model_type*>(c); }

    const char* keep(std::string_view s)
    {
        m_strings.emplace_back(s);
        return m_strings.back().c_str();
    }

    vimpact_model_table m_table{};
    std::deque<std::string> m_strings;  // a deque: the c_str() pointers stay valid
    std::vector<const char*> m_state_names, m_state_meanings, m_state_units;
    std::vector<const char*> m_parameter_names, m_parameter_meanings, m_parameter_units;
    std::vector<const char*> m_surface_names, m_surface_meanings, m_section_names, m_section_meanings;
    std::vector<const char*> m_preset_names, m_preset_meanings, m_switch_names, m_switch_meanings;
    std::vector<double> m_state_periods, m_initial, m_defaults, m_lower, m_upper, m_preset_values;
    std::vector<int> m_closed, m_sticks, m_directions, m_surface_affine, m_section_affine, m_preset_sizes,
        m_preset_parameters, m_switch_directions, m_switch_affine;
};

}  // namespace detail

// The table of definition D, built once.
template <model_definition D>
const vimpact_model_table& definition_table()
{
    static const detail::definition_table<D> t;
    return t.table();
}

}  // namespace vimpact

#define VIMPACT_EXPORT_MODEL(D)                                                            \
    extern "C" __attribute__((visibility("default"))) const vimpact_model_table* vimpact_model(void) \
    {                                                                                      \
        return &::vimpact::definition_table<D>();                                          \
    }

template <class D>
vimpact::model vimpact::model::from_definition()
{
    return from_table(definition_table<D>(), "C++ definition");
}
