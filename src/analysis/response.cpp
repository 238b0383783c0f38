#include "vimpact/analysis/response.hpp"

#include <cmath>

#include "io/record_json.hpp"
#include "jobs/journal.hpp"
#include "vimpact/core/format.hpp"

namespace vimpact {

using detail::json;

model response_model(const model& m, const response_options& o, int curve, double value)
{
    model c = m;
    if (curve >= 0 && curve < static_cast<int>(o.curves.size()))
        for (const auto& [p, v] : o.curves[static_cast<std::size_t>(curve)]) c = c.with_parameter(p, v);
    return c.with_parameter(o.parameter, value);
}

response_result response(const model& m, const response_options& o, const job_options& j,
                         const job_stream<response_point>& each)
{
    const int P = static_cast<int>(m.parameters().size());
    if (o.parameter < 0 || o.parameter >= P) throw input_error("response parameter index out of range");
    if (o.values.empty()) throw input_error("a response needs at least one value");
    if (o.variable < 0 || o.variable >= m.dim()) throw input_error("response variable index out of range");
    const auto& pname = m.info().parameters[static_cast<std::size_t>(o.parameter)].name;
    if (!parameter_enters_field(m, o.parameter))
        throw input_error("parameter " + pname + " does not enter the vector field of model " + m.name() +
                          ": the surface-free response does not depend on it");
    grazing_options go = o.grazing;
    go.response_variable = o.variable;
    validate(m, go);
    const auto curves = o.curves.empty() ? std::vector<std::vector<std::pair<int, double>>>{{}} : o.curves;
    for (std::size_t k = 0; k < curves.size(); ++k) {
        for (const auto& [p, v] : curves[k]) {
            if (p < 0 || p >= P) throw input_error("curve parameter index out of range");
            if (p == o.parameter)
                throw input_error("a curve sets " + pname + ", the swept parameter (its values come from the range)");
        }
        for (const double v : o.values) (void)response_model(m, o, static_cast<int>(k), v);  // validates the values
    }
    const Eigen::VectorXd ic = o.initial_state.size() ? o.initial_state : m.initial_state();
    check_state_size(m, ic.size(), "the initial state");
    go.cancel = j.stop;
    json cj = json::array();
    for (const auto& c : curves) {
        json one = json::array();
        for (const auto& [p, v] : c) one.push_back({p, detail::number(v)});
        cj.push_back(one);
    }
    const json spec = {{"analysis", "response"},          {"model", detail::to_json(m)},
                       {"parameter", o.parameter},         {"values", detail::to_json(o.values)},
                       {"curves", cj},                     {"variable", o.variable},
                       {"initial_state", detail::vector_json(ic)}, {"grazing", detail::to_json(go)}};
    const long n = static_cast<long>(o.values.size()), nc = static_cast<long>(curves.size());
    auto run = [&](long job, const response_point*) {
        const long k = job / n, i = job % n;
        response_point p;
        p.curve = static_cast<int>(k);
        p.value = o.values[static_cast<std::size_t>(i)];
        const model mv = response_model(m, o, p.curve, p.value);
        const auto g = grazing(mv, ic, go);
        p.maximum = g.response_max;
        p.minimum = g.response_min;
        p.amplitude = std::max(std::abs(g.response_max), std::abs(g.response_min));
        p.frequency = g.response_omega;
        for (const auto& s : g.surfaces) {
            p.grazing.push_back(s.parameter_value);
            p.margin.push_back(s.margin);
        }
        for (const auto& s : g.switches) {
            p.switch_grazing.push_back(s.parameter_value);
            p.switch_margin.push_back(s.margin);
        }
        p.converged = g.converged;
        p.status = g.status;
        p.stats = g.stats;
        return p;
    };
    response_result res;
    res.jobs = detail::run_journaled<response_point>(spec, {n * nc, 0}, j, run, detail::record_json<response_point>,
                                                     detail::record_from<response_point>,
                                                     [&](long job, response_point&& p) {
                                                         if (each) each(job, p);
                                                         else res.points.push_back(std::move(p));
                                                     });
    return res;
}

}  // namespace vimpact
