#pragma once
// A described record (core/record.hpp) as one row of a table: its columns, their schema (what
// run.json says of each column, so that a reader needs no knowledge of the record), and its
// cells. Fields that are not tabular, series and spectra take no column; a group's fields are
// columns of the row like the others.
#include <complex>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "vimpact/core/format.hpp"
#include "vimpact/core/outcome.hpp"
#include "vimpact/core/record.hpp"
#include "vimpact/core/state_series.hpp"

namespace vimpact {

// What a run's table names its columns after (the placeholders of field::column).
struct table_context {
    std::string axis;                   // the parameter the run varies ("{axis}")
    std::string grazing;                // the grazing parameter, empty for none ("{grazing}")
    std::vector<std::string> surfaces;  // the model's surfaces, in order
    std::string variable = {};          // the state variable a run measures ("{variable}")
    std::vector<std::string> states = {};  // the model's state variables (per-state fields)
    std::vector<std::string> switches = {};  // the model's switching surfaces (per-switch fields)
};

struct model_info;
// The context of a run of a model described by `info` that varies `axis` (may be empty) with
// grazing values of parameter `grazing_parameter` (-1: none).
table_context table_context_for(const model_info& info, std::string axis, int grazing_parameter);

// One column: its name in the file, the field (and group) it holds, the surface of a
// per-surface field, the switch of a per-switch one or the state of a per-state one, its type
// (int, float, bool or text) and what the field means.
struct column_schema {
    std::string name;
    std::string field;
    std::string group;  // empty outside a group
    int surface = -1;   // a per-surface field's surface
    int state = -1;     // a per-state field's index
    int switch_index = -1;  // a per-switch field's switch
    std::string type;
    std::string meaning;
    std::string unit;
};

namespace detail {

// The column names of field f in context c (none when it names a parameter the run lacks),
// and how many there are.
std::vector<std::string> column_names(const field& f, const table_context& c);
inline std::size_t column_count(const field& f, const table_context& c)
{
    if (f.column.find("{grazing}") != std::string_view::npos && c.grazing.empty()) return 0;
    if (f.column.find("{axis}") != std::string_view::npos && c.axis.empty()) return 0;
    if (f.span == field_span::per_state) return c.states.size();
    if (f.span == field_span::per_switch) return c.switches.size();
    return f.span == field_span::per_surface ? c.surfaces.size() : 1;
}

template <class T>
constexpr const char* column_type()
{
    if constexpr (std::is_same_v<T, bool>) return "bool";
    else if constexpr (std::is_integral_v<T> || std::is_same_v<T, std::vector<long>>) return "int";
    else if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, outcome>) return "text";
    else return "float";
}

template <class T>
constexpr bool has_columns = !std::is_same_v<T, state_series> && !std::is_same_v<T, std::vector<std::complex<double>>>;

struct schema_visitor {
    const table_context& context;
    std::vector<column_schema> columns;
    std::string in_group;

    template <class T>
    void operator()(const field& f, const T&)
    {
        if (!f.tabular || !has_columns<T>) return;
        const auto names = column_names(f, context);
        const auto at = [&](field_span s, std::size_t i) { return f.span == s ? static_cast<int>(i) : -1; };
        for (std::size_t i = 0; i < names.size(); ++i)
            columns.push_back({names[i], std::string(f.name), in_group, at(field_span::per_surface, i),
                               at(field_span::per_state, i), at(field_span::per_switch, i), column_type<T>(),
                               std::string(f.meaning), std::string(f.unit)});
    }
    template <class R>
    void group(const field& f, const R& r)
    {
        if (!f.tabular) return;
        in_group = f.name;
        describe(*this, r);
        in_group.clear();
    }
};

struct cell_visitor {
    const table_context& context;
    std::vector<std::string>& cells;

    static std::string cell(double v) { return format_double(v); }
    static std::string cell(bool v) { return v ? "1" : "0"; }
    static std::string cell(const std::string& v) { return v; }
    static std::string cell(outcome v) { return std::string(to_string(v)); }
    template <class T>
        requires std::is_integral_v<T>
    static std::string cell(T v)
    {
        return std::to_string(v);
    }

    template <class T>
    void operator()(const field& f, const T& v)
    {
        if constexpr (has_columns<T>) {
            if (!f.tabular) return;
            const std::size_t n = column_count(f, context);
            if constexpr (std::is_same_v<T, std::vector<double>> || std::is_same_v<T, std::vector<long>>) {
                // A surface without a value: NaN, or no count.
                using E = typename T::value_type;
                const E missing = std::is_floating_point_v<E> ? std::numeric_limits<double>::quiet_NaN() : E{0};
                for (std::size_t i = 0; i < n; ++i) cells.push_back(cell(i < v.size() ? v[i] : missing));
            } else if constexpr (std::is_same_v<T, Eigen::VectorXd>) {
                for (std::size_t i = 0; i < n; ++i)
                    cells.push_back(cell(static_cast<Eigen::Index>(i) < v.size() ? v[static_cast<Eigen::Index>(i)]
                                                                                 : std::numeric_limits<double>::quiet_NaN()));
            } else if (n > 0) {
                cells.push_back(cell(v));
            }
        }
    }
    template <class R>
    void group(const field& f, const R& r)
    {
        if (f.tabular) describe(*this, r);
    }
};

}  // namespace detail

// The columns of record type R in context c, in the order of its description.
template <class R>
std::vector<column_schema> record_columns(const table_context& c)
{
    detail::schema_visitor v{c, {}, {}};
    const R r{};
    describe(v, r);
    return std::move(v.columns);
}

// The cells of one record, in the order of record_columns<R>(c).
template <class R>
std::vector<std::string> record_cells(const R& r, const table_context& c)
{
    std::vector<std::string> cells;
    detail::cell_visitor v{c, cells};
    describe(v, r);
    return cells;
}

}  // namespace vimpact
