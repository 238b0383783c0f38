#include "vimpact/io/continuation_json.hpp"

#include <cmath>
#include <string>

namespace vimpact {
namespace {

using json = nlohmann::json;

json finite(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json vector_of(const Eigen::VectorXd& v)
{
    json j = json::array();
    for (Eigen::Index i = 0; i < v.size(); ++i) j.push_back(finite(v[i]));
    return j;
}

json multipliers_of(const std::vector<std::complex<double>>& mu)
{
    json j = json::array();
    for (const auto& m : mu) j.push_back({finite(m.real()), finite(m.imag())});
    return j;
}

json by_surface(const std::vector<long>& counts, const model_info& info)
{
    json j = json::object();
    for (std::size_t i = 0; i < info.surfaces.size(); ++i) j[info.surfaces[i].name] = i < counts.size() ? counts[i] : 0L;
    return j;
}

json surface_of(int surface, const model_info& info)
{
    return surface >= 0 ? json(info.surfaces[static_cast<std::size_t>(surface)].name) : json(nullptr);
}

json sequence_of(const std::vector<int>& seq, const model_info& info)
{
    json j = json::array();
    for (const int s : seq) j.push_back(info.surfaces[static_cast<std::size_t>(s)].name);
    return j;
}

json sections_of(const state_series& s)
{
    json j = json::array();
    for (std::size_t i = 0; i < s.size(); ++i) j.push_back(vector_of(s.x(i)));
    return j;
}

json point_of(const continuation_point& p, const model_info& info)
{
    const json sections = sections_of(p.section_points);
    return {{"param", p.parameter},
            {"stable", p.stable},
            {"multipliers", multipliers_of(p.multipliers)},
            {"period", finite(p.period)},
            {"impacts", p.impacts()},
            {"impacts_by_surface", by_surface(p.impacts_by_surface, info)},
            {"state", vector_of(p.state)},
            {"section_points", sections},
            {"closure", finite(p.closure)},
            {"arclength", p.arclength}};
}

}  // namespace

json continuation_json(const model& m, const continuation_options& o, const continuation_result& r)
{
    const model_info& info = m.info();
    json branches = json::array(), branch_info = json::array();
    for (const auto& br : r.branches) {
        json pts = json::array();
        for (const auto& p : br.points) pts.push_back(point_of(p, info));
        branches.push_back(pts);
        branch_info.push_back({{"returns", br.returns},
                               {"parent", br.parent >= 0 ? json(br.parent) : json(nullptr)},
                               {"origin", br.origin >= 0 ? json(br.origin) : json(nullptr)},
                               {"points", br.points.size()},
                               {"end", std::string(to_string(br.end))},
                               {"end_reason", end_reason(br, info.parameters[static_cast<std::size_t>(o.parameter)].name)},
                               {"failure", std::string(to_string(br.failure))}});
    }
    json bifs = json::array();
    for (const auto& bf : r.bifurcations)
        bifs.push_back({{"type", std::string(to_string(bf.type))},
                        {"param", bf.parameter},
                        {"branch", bf.branch},
                        {"after_point", bf.after_point},
                        {"located", bf.located},
                        {"bracket", finite(bf.bracket)},
                        {"state", vector_of(bf.point.state)},
                        {"section_points", sections_of(bf.point.section_points)},
                        {"period", finite(bf.point.period)},
                        {"multipliers", multipliers_of(bf.point.multipliers)},
                        {"section_multipliers", multipliers_of(bf.point.section_multipliers)},
                        {"surface", surface_of(bf.surface, info)},
                        {"switch", bf.switch_surface >= 0 ? json(info.switches[static_cast<std::size_t>(bf.switch_surface)].name)
                                                          : json(nullptr)},
                        {"crossings_before", bf.switch_surface >= 0 ? json(bf.crossings_before) : json(nullptr)},
                        {"crossings_after", bf.switch_surface >= 0 ? json(bf.crossings_after) : json(nullptr)},
                        {"time", bf.type == bifurcation_type::grazing ? json(bf.time) : json(nullptr)},
                        {"sequence_before", sequence_of(bf.sequence_before, info)},
                        {"sequence_after", sequence_of(bf.sequence_after, info)}});
    return {{"param", info.parameters[static_cast<std::size_t>(o.parameter)].name},
            {"range", {o.start, o.end}},
            {"status", std::string(to_string(r.status))},
            {"start_label", r.start_label},
            {"branches", branches},
            {"branch_info", branch_info},
            {"bifurcations", bifs},
            {"tangent_maps", r.tangent_maps},
            {"plain_maps", r.plain_maps}};
}

json continuation_json(const model& m, const continuation_options& o, const continuation_result& r,
                       const curve_options& o2, const std::vector<bifurcation_curve>& curves)
{
    const model_info& info = m.info();
    json j = continuation_json(m, o, r);
    json cj = json::array();
    for (const auto& cv : curves) {
        json pts = json::array();
        for (const auto& p : cv.points)
            pts.push_back({{"param", p.parameter},
                           {"param2", p.parameter2},
                           {"state", vector_of(p.state)},
                           {"period", finite(p.period)},
                           {"impacts_by_surface", by_surface(p.impacts_by_surface, info)},
                           {"multipliers", multipliers_of(p.multipliers)},
                           {"section_multipliers", multipliers_of(p.section_multipliers)},
                           {"closure", finite(p.closure)},
                           {"condition", finite(p.condition)}});
        cj.push_back({{"type", std::string(to_string(cv.type))},
                      {"origin", cv.origin},
                      {"surface", surface_of(cv.surface, info)},
                      {"switch", cv.switch_surface >= 0 ? json(info.switches[static_cast<std::size_t>(cv.switch_surface)].name)
                                                        : json(nullptr)},
                      {"start", cv.start},
                      {"end_backward", std::string(to_string(cv.end_backward))},
                      {"end_forward", std::string(to_string(cv.end_forward))},
                      {"failure", std::string(to_string(cv.failure))},
                      {"points", pts}});
    }
    j["param2"] = info.parameters[static_cast<std::size_t>(o2.parameter2)].name;
    j["range2"] = {o2.lo2, o2.hi2};
    j["curves"] = cj;
    return j;
}

}  // namespace vimpact
