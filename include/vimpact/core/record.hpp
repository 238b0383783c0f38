#pragma once
// A result record described once. Each record type has one function
//   template <class V, class R> void describe(V& v, R& r)   (R: the record, const or not)
// beside its struct, calling v(field{...}, r.member) for every field in order, and
// v.group(field{...}, r.member) for a member that is itself a described record. Every other
// form of the record is a visitor of that description: its journal line (src/io/), the columns
// of its table and their schema in run.json (io/record_table.hpp), its arrays in Python
// (python/bindings/records.hpp), and Python's reader of an output directory follows the
// schema. Adding a field to a record is one member and one line in its describe().
//
// A visitor that reads (a decoder) is called with R non-const, one that writes with R const;
// a describe() is written once for both through `record_of`.
#include <concepts>
#include <string_view>
#include <type_traits>

namespace vimpact {

// How many values a field holds, and so how many columns it takes in a table.
enum class field_span {
    one,          // one value
    per_surface,  // one value per surface of the model (a vector; missing entries read as 0 or NaN)
    per_switch,   // one value per switching surface of the model (as per_surface)
    per_state,    // one value per state variable (a state vector)
    series,       // many timed states (a state_series): a table of its own, never a column
    spectrum,     // complex values, at most one per state variable (eigenvalues, in the record's
                  // order): a table of its own, a row per value, never a column
};

struct field {
    std::string_view name;     // key in JSON, journal and Python; a column's name unless `column` says
    std::string_view meaning;  // for run.json's schema and the documentation
    std::string_view unit;     // in the model's units: "" for none; "parameter" for the unit of the
                               // parameter a column is named after, "variable" for that of the
                               // state variable a run measures; t for time, g for gap
    field_span span;
    // The column's name in a table when it is not `name`. "{axis}" is replaced by the name of
    // the parameter the run varies, "{grazing}" by the grazing parameter's (a field naming one
    // that the run does not have is left out of the table), "{variable}" by the measured state
    // variable's; a per-surface field's columns are the name alone for one surface and
    // name_SURFACE for several, unless the name says where the surface goes with "{surface}";
    // a per-switch field's are name_SWITCH (even for one: a model may have a surface too), or
    // the pattern with "{switch}" replaced by the switch's name;
    // a per-state field's are name_STATE, or the pattern with "{index}" replaced by 1, 2, ...
    // (values in their own order, such as exponents by size, not one per state variable).
    std::string_view column;
    bool tabular;              // false: journal and Python only (counters, final states)

    constexpr field(std::string_view name_, std::string_view meaning_, std::string_view unit_ = {},
                    field_span span_ = field_span::one, std::string_view column_ = {}, bool tabular_ = true)
        : name(name_), meaning(meaning_), unit(unit_), span(span_), column(column_), tabular(tabular_)
    {
    }
};

// R is the record T, const or not: describe(V&, R&) is one function for readers and writers.
template <class R, class T>
concept record_of = std::same_as<std::remove_const_t<R>, T>;

}  // namespace vimpact
