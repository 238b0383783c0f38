#include "json_codec.hpp"

#include <cmath>
#include <limits>

#include "vimpact/core/input_error.hpp"

namespace vimpact::detail {

json number(double v)
{
    if (std::isfinite(v)) return v;
    if (std::isnan(v)) return "nan";
    return v > 0 ? "inf" : "-inf";
}

double number_from(const json& j)
{
    if (j.is_number()) return j.get<double>();
    const auto s = j.get<std::string>();
    if (s == "inf") return std::numeric_limits<double>::infinity();
    if (s == "-inf") return -std::numeric_limits<double>::infinity();
    return std::numeric_limits<double>::quiet_NaN();
}

json numbers(const std::vector<double>& v)
{
    json a = json::array();
    for (const double x : v) a.push_back(number(x));
    return a;
}

json to_json(const value_grid& g)
{
    json j;
    if (g.is_range()) {
        j = {{"from", number(g.range_from())}, {"to", number(g.range_to())}, {"n", g.size()}};
    } else {
        json a = json::array();
        for (std::size_t i = 0; i < g.size(); ++i) a.push_back(number(g.given(i)));
        if (!g.is_mapped()) return a;
        j = {{"values", std::move(a)}};
    }
    if (g.is_mapped()) j["map"] = g.map_name();
    return j;
}

std::vector<double> numbers_from(const json& j)
{
    std::vector<double> v;
    v.reserve(j.size());
    for (const auto& x : j) v.push_back(number_from(x));
    return v;
}

json vector_json(const Eigen::VectorXd& v) { return numbers(std::vector<double>(v.data(), v.data() + v.size())); }

Eigen::VectorXd vector_from(const json& j)
{
    const auto v = numbers_from(j);
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

json to_json(const model& m)
{
    return {{"name", m.name()}, {"identity", m.info().identity}, {"parameters", numbers(m.parameters())}};
}

json to_json(const integrator_options& o)
{
    json j = {{"rtol", number(o.rtol)},       {"atol", number(o.atol)},
              {"h_max", number(o.h_max)},     {"h_init", number(o.h_init)},
              {"safety", number(o.safety)},   {"factor_min", number(o.factor_min)},
              {"factor_max", number(o.factor_max)}, {"pi_beta", number(o.pi_beta)}};
    // Only a band that holds (here without a method: the tangent runs' DOP853, whose default is
    // none): a job journal's spec written before the option existed still matches.
    if (o.hold_band.value_or(0.0) > 0.0) j["hold_band"] = number(*o.hold_band);
    return j;
}

namespace {

// The options of a run of `method`, with the band it uses: a DOPRI5 journal written before
// DOPRI5 held by default (its spec has no band) is then not resumed with the band, and one
// with --hold-band 0 matches it.
json run_json(const integrator_options& o, integration_method method)
{
    json j = to_json(o);
    j.erase("hold_band");
    if (const double band = effective_hold_band(o, method); band > 0.0) j["hold_band"] = number(band);
    return j;
}

json run_json(const flow_options& o, integration_method method)
{
    json j = to_json(o);
    j["integration"] = run_json(o.integration, method);
    return j;
}

}  // namespace

json to_json(const flow_options& o)
{
    return {{"integration", to_json(o.integration)},
            {"sticking_velocity", number(o.sticking_velocity)},
            {"sticking_height", number(o.sticking_height)},
            {"t_max", number(o.t_max)},
            {"max_steps", o.max_steps},
            {"max_impacts", o.max_impacts},
            {"event_subdivisions", o.event_subdivisions}};
}

json to_json(const section_choice& s)
{
    return {{"type", s.type == section_choice::kind::crossing ? "crossing" : "impacts"}, {"index", s.index}};
}

json to_json(const protocol_options& o)
{
    return {{"transient", o.transient_impacts}, {"record", o.record_points}, {"section", to_json(o.section)},
            {"quiet_time", number(o.quiet_time)}, {"sample_dt", number(o.sample_dt)}, {"flow", run_json(o.flow, o.method)},
            {"method", std::string(to_string(o.method))}};
}

json to_json(const grazing_options& o)
{
    return {{"integration", run_json(o.integration, o.method)}, {"method", std::string(to_string(o.method))},
            {"transient_time", number(o.transient_time)}, {"block", o.block},
            {"tolerance", number(o.tolerance)},         {"t_max", number(o.t_max)},
            {"parameter", o.parameter},                 {"response_variable", o.response_variable}};
}

json to_json(const floquet_options& o)
{
    return {{"protocol", to_json(o.protocol)},
            {"period_tolerance", number(o.period_tolerance)},
            {"newton_tolerance", number(o.newton_tolerance)},
            {"newton_iterations", o.newton_iterations},
            {"tangent_integration", to_json(o.tangent_integration)},
            {"jump", std::string(to_string(o.jump))},
            {"sample_dt", number(o.sample_dt)}};
}

json to_json(const lyapunov_options& o)
{
    return {{"transient", o.transient_impacts}, {"quiet_time", number(o.quiet_time)},
            {"flow", run_json(o.flow, o.method)}, {"method", std::string(to_string(o.method))},
            {"tdm", std::string(to_string(o.tdm))}, {"r0", number(o.r0)},
            {"t0", number(o.t0)},               {"warmup", o.warmup_intervals},
            {"impacts", o.impacts},             {"time", number(o.time)},
            {"p0_time", number(o.p0_time)},     {"max_time", number(o.max_time)},
            {"divergence", o.divergence},       {"record", o.record_points},
            {"section", o.section}};
}

json to_json(const impact_statistics& s)
{
    json values = json::array();
    for (const double v : impact_statistics_values(s)) values.push_back(number(v));
    return {{"values", values}, {"excursion_by_surface", numbers(s.excursion_by_surface)}};
}

impact_statistics statistics_from(const json& j)
{
    (void)j.at("values").at(impact_statistics_names().size() - 1);  // a short record: json::out_of_range
    impact_statistics s = impact_statistics_from_values(numbers_from(j.at("values")));
    s.excursion_by_surface = numbers_from(j.at("excursion_by_surface"));
    return s;
}

json to_json(const period_label& l)
{
    return {{"label", l.label}, {"period", l.period}, {"impacts", l.impacts_per_period},
            {"impacts_by_surface", l.impacts_by_surface}, {"closure", number(l.closure)}, {"settled", l.settled}};
}

period_label label_from(const json& j)
{
    period_label l;
    l.label = j.at("label").get<std::string>();
    l.period = j.at("period").get<int>();
    l.impacts_per_period = j.at("impacts").get<long>();
    l.impacts_by_surface = j.at("impacts_by_surface").get<std::vector<long>>();
    l.closure = number_from(j.at("closure"));
    l.settled = j.at("settled").get<bool>();
    return l;
}

json to_json(const state_series& s)
{
    return {{"dim", s.dim()}, {"t", numbers(s.times())}, {"x", numbers(s.values())}};
}

state_series series_from(const json& j)
{
    state_series s(j.at("dim").get<int>());
    const auto t = numbers_from(j.at("t"));
    const auto x = numbers_from(j.at("x"));
    s.reserve(t.size());
    for (std::size_t i = 0; i < t.size(); ++i) s.push_back(t[i], x.data() + i * static_cast<std::size_t>(s.dim()));
    return s;
}

outcome outcome_from(const json& j)
{
    const auto o = outcome_from_string(j.get<std::string>());
    if (!o) throw input_error("unknown outcome '" + j.get<std::string>() + "' in a journal");
    return *o;
}

}  // namespace vimpact::detail
