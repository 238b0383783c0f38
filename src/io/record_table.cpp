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
    if (f.span == field_span::per_switch) {
        const bool placed = pattern.find("{switch}") != std::string::npos;
        for (const auto& w : c.switches) {
            std::string name = pattern;
            if (placed) replace_all(name, "{switch}", w);
            else name += "_" + w;
            out.push_back(std::move(name));
        }
        return out;
    }
    if (f.span != field_span::per_surface) return {pattern};
    const bool placed = pattern.find("{surface}") != std::string::npos;
    for (const auto& s : c.surfaces) {
        std::string name = pattern;
        if (placed) replace_all(name, "{surface}", s);
        else if (c.surfaces.size() > 1) name += "_" + s;
        out.push_back(std::move(name));
    }
    return out;
}

}  // namespace detail
}  // namespace vimpact
