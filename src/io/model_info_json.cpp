#include "vimpact/io/model_info_json.hpp"

#include "vimpact/io/summary_json.hpp"

namespace vimpact {

namespace {

using json = nlohmann::json;

json range_json(const value_range& r)
{
    return {{"lower", finite_or_null(r.lower)},
            {"upper", finite_or_null(r.upper)},
            {"lower_inclusive", r.lower_inclusive},
            {"upper_inclusive", r.upper_inclusive},
            {"text", r.text()}};
}

}  // namespace

json model_info_json(const model_info& info)
{
    json state = json::array(), params = json::array(), surfaces = json::array(), sections = json::array(),
         switches = json::array(), presets = json::array();
    for (const auto& v : info.state)
        state.push_back({{"name", v.name},
                         {"meaning", v.meaning},
                         {"unit", v.unit},
                         {"period", v.period > 0.0 ? json(v.period) : json(nullptr)}});
    for (const auto& p : info.parameters)
        params.push_back({{"name", p.name},
                          {"meaning", p.meaning},
                          {"unit", p.unit},
                          {"default", p.default_value},
                          {"range", range_json(p.range)}});
    for (const auto& s : info.surfaces) surfaces.push_back({{"name", s.name}, {"meaning", s.meaning}, {"sticks", s.sticks}});
    for (const auto& s : info.sections)
        sections.push_back({{"name", s.name}, {"meaning", s.meaning}, {"direction", std::string(to_string(s.direction))}});
    for (const auto& s : info.switches)
        switches.push_back({{"name", s.name}, {"meaning", s.meaning}, {"direction", std::string(to_string(s.direction))}});
    for (const auto& p : info.presets) {
        json values = json::object();
        for (const auto& [i, v] : p.values) values[info.parameters[static_cast<std::size_t>(i)].name] = v;
        presets.push_back({{"name", p.name}, {"meaning", p.meaning}, {"values", values}});
    }
    return {{"name", info.name},
            {"description", info.description},
            {"source", info.source},
            {"identity", info.identity},
            {"state", state},
            {"initial_state", info.initial_state},
            {"parameters", params},
            {"surfaces", surfaces},
            {"sections", sections},
            {"switches", switches},
            {"presets", presets}};
}

}  // namespace vimpact
