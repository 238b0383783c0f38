#include "vimpact/io/record_table.hpp"

#include "vimpact/model/model_info.hpp"

namespace vimpact {

table_context table_context_for(const model_info& info, std::string axis, int grazing_parameter)
{
    table_context c{std::move(axis), {}, {}};
    if (grazing_parameter >= 0) c.grazing = info.parameters[static_cast<std::size_t>(grazing_parameter)].name;
    for (const auto& s : info.surfaces) c.surfaces.push_back(s.name);
    for (const auto& x : info.state) c.states.push_back(x.name);
    for (const auto& w : info.switches) c.switches.push_back(w.name);
    return c;
}

namespace detail {

namespace {

void replace_all(std::string& s, std::string_view what, const std::string& with)
{
    for (auto i = s.find(what); i != std::string::npos; i = s.find(what, i + with.size())) s.replace(i, what.size(), with);
}

// One column per item (surface or switch): the pattern with `placeholder` replaced by the
// item's name, or without one, NAME_ITEM (NAME alone for a single item where `alone` allows).
std::vector<std::string> per_item(const std::string& pattern, std::string_view placeholder,
                                  const std::vector<std::string>& items, bool alone)
{
    const bool placed = pattern.find(placeholder) != std::string::npos;
    std::vector<std::string> out;
    for (const auto& item : items) {
        std::string name = pattern;
        if (placed) replace_all(name, placeholder, item);
        else if (!alone || items.size() > 1) name += "_" + item;
        out.push_back(std::move(name));
    }
    return out;
}

}  // namespace

std::vector<std::string> column_names(const field& f, const table_context& c)
{
    if (column_count(f, c) == 0) return {};
    std::string pattern(f.column.empty() ? f.name : f.column);
    replace_all(pattern, "{axis}", c.axis);
    replace_all(pattern, "{grazing}", c.grazing);
    replace_all(pattern, "{variable}", c.variable);
    std::vector<std::string> out;
    if (f.span == field_span::per_state) {
        const bool indexed = pattern.find("{index}") != std::string::npos;
        for (std::size_t k = 0; k < c.states.size(); ++k) {
            std::string name = pattern;
            if (indexed) replace_all(name, "{index}", std::to_string(k + 1));
            else name += "_" + c.states[k];
            out.push_back(std::move(name));
        }
        return out;
    }
    // A switch's column always names it: a model may have a surface with the same field.
    if (f.span == field_span::per_switch) return per_item(pattern, "{switch}", c.switches, false);
    if (f.span == field_span::per_surface) return per_item(pattern, "{surface}", c.surfaces, true);
    return {pattern};
}

}  // namespace detail
}  // namespace vimpact
