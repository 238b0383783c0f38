#pragma once
// Records the library describes (core/record.hpp) as numpy columns, one entry per record: a
// field of one value is a 1-D array (int64, float64, bool) or a list of str, a per-surface
// field an array (records, surfaces), a per-switch field (records, switches), a state vector
// (records, dim), a series its points one
// record after the other (points, dim) with NAME_run, the record of each point, a spectrum an
// array (records, dim) of complex128 (NaN where a record has fewer values); a group is a dict
// of its own fields. vimpact/results.py reads the same columns from an output directory
// (read_tables), so a result is built the same way from either. record_dict gives one record
// (a single run's) as Python values by the same description.
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <complex>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "vimpact/core/outcome.hpp"
#include "vimpact/core/record.hpp"
#include "vimpact/core/state_series.hpp"
#include "vimpact/model/model.hpp"

namespace vimpact::python {

namespace py = pybind11;

namespace detail {

enum class column_kind { real, integer, flag, text, complex, group };

template <class T>
constexpr column_kind kind_of()
{
    if constexpr (std::is_same_v<T, bool>) return column_kind::flag;
    else if constexpr (std::is_integral_v<T> || std::is_same_v<T, std::vector<long>>) return column_kind::integer;
    else if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, outcome>) return column_kind::text;
    else if constexpr (std::is_same_v<T, std::vector<std::complex<double>>>) return column_kind::complex;
    else return column_kind::real;
}

struct record_column {
    std::string name;
    field_span span = field_span::one;
    column_kind kind = column_kind::real;
    std::vector<double> reals;
    std::vector<std::int64_t> integers;
    std::vector<bool> flags;
    std::vector<std::complex<double>> complexes;
    std::vector<std::string> texts;
    std::vector<std::int64_t> runs;  // a series: the record of each point
    int width = 1;                   // values per record (per surface, per state), per point (series)
    std::vector<record_column> fields;  // a group's

    static record_column of(std::string_view name, field_span span, column_kind kind)
    {
        record_column c;
        c.name = name;
        c.span = span;
        c.kind = kind;
        return c;
    }
};

// Appends one record's fields to the columns, creating them on the first record.
struct column_collector {
    std::vector<record_column>& columns;
    std::int64_t record;
    int surfaces;
    int switches;
    int dim;
    std::size_t next = 0;

    record_column& column(const field& f, column_kind kind)
    {
        if (columns.size() <= next) columns.push_back(record_column::of(f.name, f.span, kind));
        return columns[next++];
    }

    template <class T>
    void operator()(const field& f, const T& v)
    {
        record_column& c = column(f, kind_of<T>());
        if constexpr (std::is_same_v<T, bool>) {
            c.flags.push_back(v);
        } else if constexpr (std::is_integral_v<T>) {
            c.integers.push_back(static_cast<std::int64_t>(v));
        } else if constexpr (std::is_floating_point_v<T>) {
            c.reals.push_back(v);
        } else if constexpr (std::is_same_v<T, std::string>) {
            c.texts.push_back(v);
        } else if constexpr (std::is_same_v<T, outcome>) {
            c.texts.emplace_back(to_string(v));
        } else if constexpr (std::is_same_v<T, std::vector<double>> || std::is_same_v<T, std::vector<long>>) {
            c.width = f.span == field_span::per_switch ? switches : surfaces;
            for (int s = 0; s < c.width; ++s) {
                const bool has = static_cast<std::size_t>(s) < v.size();
                if constexpr (std::is_same_v<T, std::vector<double>>)
                    c.reals.push_back(has ? v[static_cast<std::size_t>(s)] : std::numeric_limits<double>::quiet_NaN());
                else
                    c.integers.push_back(has ? v[static_cast<std::size_t>(s)] : 0);
            }
        } else if constexpr (std::is_same_v<T, std::vector<std::complex<double>>>) {
            c.width = dim;
            for (int k = 0; k < dim; ++k)
                c.complexes.push_back(static_cast<std::size_t>(k) < v.size()
                                          ? v[static_cast<std::size_t>(k)]
                                          : std::complex<double>(std::numeric_limits<double>::quiet_NaN(), 0.0));
        } else if constexpr (std::is_same_v<T, Eigen::VectorXd>) {
            c.width = dim;
            for (int k = 0; k < dim; ++k) c.reals.push_back(k < v.size() ? v[k] : std::numeric_limits<double>::quiet_NaN());
        } else {
            static_assert(std::is_same_v<T, state_series>, "a field type without a column form");
            c.width = dim;
            c.reals.insert(c.reals.end(), v.values().begin(), v.values().end());
            c.runs.insert(c.runs.end(), v.size(), record);
        }
    }

    template <class R>
    void group(const field& f, const R& r)
    {
        record_column& c = column(f, column_kind::group);
        column_collector sub{c.fields, record, surfaces, switches, dim};
        describe(sub, r);
    }
};

inline py::object column_object(const record_column& c, py::ssize_t records)
{
    switch (c.kind) {
        case column_kind::group: {
            py::dict d;
            for (const auto& f : c.fields) d[py::str(f.name)] = column_object(f, records);
            return d;
        }
        case column_kind::text: return py::cast(c.texts);
        case column_kind::flag: {
            py::array_t<bool> a(records);
            for (py::ssize_t i = 0; i < records; ++i) a.mutable_at(i) = c.flags[static_cast<std::size_t>(i)];
            return a;
        }
        case column_kind::integer:
        case column_kind::complex:
        case column_kind::real: break;
    }
    std::vector<py::ssize_t> shape{c.span == field_span::series ? static_cast<py::ssize_t>(c.runs.size()) : records};
    if (c.span != field_span::one) shape.push_back(c.width);
    if (c.kind == column_kind::complex) {
        py::array_t<std::complex<double>> a(shape);
        if (!c.complexes.empty())
            std::memcpy(a.mutable_data(), c.complexes.data(), c.complexes.size() * sizeof(std::complex<double>));
        return a;
    }
    if (c.kind == column_kind::integer) {
        py::array_t<std::int64_t> a(shape);
        if (!c.integers.empty()) std::memcpy(a.mutable_data(), c.integers.data(), c.integers.size() * sizeof(std::int64_t));
        return a;
    }
    py::array_t<double> a(shape);
    if (!c.reals.empty()) std::memcpy(a.mutable_data(), c.reals.data(), c.reals.size() * sizeof(double));
    return a;
}

}  // namespace detail

// The columns of `records` of model m (its surfaces, switches and dimension: the widths of
// per-surface and per-switch fields and of states). Every field is present, even for no
// records.
template <class R>
py::dict record_arrays(const std::vector<R>& records, const model& m)
{
    const int surfaces = m.surface_count(), switches = static_cast<int>(m.info().switches.size()), dim = m.dim();
    std::vector<detail::record_column> columns;
    for (std::size_t i = 0; i < records.size(); ++i) {
        detail::column_collector c{columns, static_cast<std::int64_t>(i), surfaces, switches, dim};
        describe(c, records[i]);
    }
    if (records.empty()) {  // the fields' names and kinds from a default record, without its values
        std::vector<detail::record_column> seen;
        detail::column_collector c{seen, 0, surfaces, switches, dim};
        const R blank{};
        describe(c, blank);
        const auto empty = [&](auto&& self, const detail::record_column& col) -> detail::record_column {
            detail::record_column e = detail::record_column::of(col.name, col.span, col.kind);
            e.width = col.width;
            for (const auto& f : col.fields) e.fields.push_back(self(self, f));
            return e;
        };
        for (const auto& col : seen) columns.push_back(empty(empty, col));
    }
    py::dict d;
    const auto n = static_cast<py::ssize_t>(records.size());
    for (const auto& c : columns) {
        d[py::str(c.name)] = detail::column_object(c, n);
        if (c.span == field_span::series) {
            py::array_t<std::int64_t> runs(static_cast<py::ssize_t>(c.runs.size()));
            if (!c.runs.empty()) std::memcpy(runs.mutable_data(), c.runs.data(), c.runs.size() * sizeof(std::int64_t));
            d[py::str(c.name + "_run")] = runs;
        }
    }
    return d;
}

namespace detail {

// One record's fields as Python values: a number, bool or str as itself, a per-surface field a
// dict by surface name (a missing entry 0 or NaN, as in record_arrays), a state vector an
// array (dim,) NaN-padded, a spectrum its complex values, a series its points (n, dim) and
// NAME_t their times, a group a dict.
struct value_collector {
    py::dict& d;
    const model& m;

    template <class T>
    void operator()(const field& f, const T& v)
    {
        const py::str name{std::string(f.name)};
        if constexpr (std::is_same_v<T, outcome>) {
            d[name] = std::string(to_string(v));
        } else if constexpr (std::is_same_v<T, std::vector<double>> || std::is_same_v<T, std::vector<long>>) {
            typename T::value_type missing{};
            if constexpr (std::is_floating_point_v<typename T::value_type>) missing = std::numeric_limits<double>::quiet_NaN();
            py::dict by;
            const auto put = [&](const auto& items) {
                for (std::size_t s = 0; s < items.size(); ++s) by[py::str(items[s].name)] = s < v.size() ? v[s] : missing;
            };
            if (f.span == field_span::per_switch) put(m.info().switches);
            else put(m.info().surfaces);
            d[name] = by;
        } else if constexpr (std::is_same_v<T, std::vector<std::complex<double>>>) {
            d[name] = py::array_t<std::complex<double>>(static_cast<py::ssize_t>(v.size()), v.data());
        } else if constexpr (std::is_same_v<T, Eigen::VectorXd>) {
            py::array_t<double> a(m.dim());
            for (int k = 0; k < m.dim(); ++k) a.mutable_at(k) = k < v.size() ? v[k] : std::numeric_limits<double>::quiet_NaN();
            d[name] = a;
        } else if constexpr (std::is_same_v<T, state_series>) {
            py::array_t<double> points({static_cast<py::ssize_t>(v.size()), static_cast<py::ssize_t>(m.dim())});
            if (v.size()) std::memcpy(points.mutable_data(), v.values().data(), v.values().size() * sizeof(double));
            d[name] = points;
            d[py::str(std::string(f.name) + "_t")] = py::array_t<double>(static_cast<py::ssize_t>(v.size()),
                                                                          v.times().data());
        } else {
            d[name] = v;
        }
    }

    template <class R>
    void group(const field& f, const R& r)
    {
        py::dict sub;
        value_collector c{sub, m};
        describe(c, r);
        d[py::str(std::string(f.name))] = sub;
    }
};

}  // namespace detail

// One record of a run of model m by its description (detail::value_collector).
template <class R>
py::dict record_dict(const R& r, const model& m)
{
    py::dict d;
    detail::value_collector c{d, m};
    describe(c, r);
    return d;
}

namespace detail {

// The type names of run.json's schema (io/record_table.hpp), and complex and group, which take
// no column there.
constexpr const char* kind_name(column_kind k)
{
    switch (k) {
        case column_kind::integer: return "int";
        case column_kind::flag: return "bool";
        case column_kind::text: return "text";
        case column_kind::complex: return "complex";
        case column_kind::group: return "group";
        case column_kind::real: break;
    }
    return "float";
}

constexpr const char* span_name(field_span s)
{
    switch (s) {
        case field_span::per_surface: return "per_surface";
        case field_span::per_switch: return "per_switch";
        case field_span::per_state: return "per_state";
        case field_span::series: return "series";
        case field_span::spectrum: return "spectrum";
        case field_span::one: break;
    }
    return "one";
}

struct description_visitor {
    py::list fields;

    static py::dict entry(const field& f, column_kind kind)
    {
        py::dict d;
        d["name"] = std::string(f.name);
        d["meaning"] = std::string(f.meaning);
        d["unit"] = std::string(f.unit);
        d["span"] = span_name(f.span);
        d["type"] = kind_name(kind);
        d["tabular"] = f.tabular;
        return d;
    }
    template <class T>
    void operator()(const field& f, const T&)
    {
        fields.append(entry(f, kind_of<T>()));
    }
    template <class R>
    void group(const field& f, const R& r)
    {
        description_visitor sub;
        describe(sub, r);
        py::dict d = entry(f, column_kind::group);
        d["fields"] = sub.fields;
        fields.append(d);
    }
};

}  // namespace detail

// What record type R says of its fields, in order, for Python's documentation of the arrays
// of record_arrays: each field's name, meaning, unit, span (one, per_surface, per_state,
// series, spectrum), type (int, float, bool, text, complex, group: its own "fields") and
// whether a command's table has it (tabular).
template <class R>
py::list described()
{
    detail::description_visitor v;
    const R blank{};
    describe(v, blank);
    return v.fields;
}

}  // namespace vimpact::python
