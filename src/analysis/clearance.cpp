#include "vimpact/analysis/clearance.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "io/json_codec.hpp"
#include "io/record_json.hpp"
#include "jobs/journal.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/core/format.hpp"

namespace vimpact {

namespace {

using detail::json;

// The point's fields and its cells, each as its record.
json encode(const clearance_point& p)
{
    json j = detail::record_json(p);
    j["cells"] = json::array();
    for (const auto& c : p.cells) j["cells"].push_back(detail::record_json(c));
    return j;
}

clearance_point decode(const json& j)
{
    auto p = detail::record_from<clearance_point>(j);
    for (const auto& c : j.at("cells")) p.cells.push_back(detail::record_from<clearance_cell>(c));
    return p;
}

// m with G at value, or nullopt when the value is outside G's range.
std::optional<model> with_value(const model& m, int parameter, double value)
{
    if (!std::isfinite(value)) return std::nullopt;
    try {
        return m.with_parameter(parameter, value);
    } catch (const input_error&) {
        return std::nullopt;
    }
}

}  // namespace

std::vector<double> default_clearance_fractions() { return grid_values(0.1, 1.3, 13); }

clearance_result clearance(const model& m, const clearance_options& o, const job_options& j)
{
    check_options(o);
    validate(o.protocol);
    validate(m, o.protocol.section);
    const int P = static_cast<int>(m.parameters().size());
    if (o.parameter < 0 || o.parameter >= P) throw input_error("clearance: flow parameter index out of range");
    if (o.values.empty()) throw input_error("clearance needs at least one value of the flow parameter");
    const int G = o.gap_parameter >= 0 ? o.gap_parameter : first_grazing_parameter(m);
    if (G < 0)
        throw input_error("clearance: model " + m.name() +
                          " has no parameter that moves a surface or switch without entering the vector field");
    if (G >= P) throw input_error("clearance: gap parameter index out of range");
    const int surface = surface_moved_by(m, G);
    const int sw = surface < 0 ? switch_moved_by(m, G) : -1;
    const auto& names = m.info().parameters;
    if (surface < 0 && sw < 0)
        throw input_error("clearance: parameter " + names[static_cast<std::size_t>(G)].name +
                          " moves no surface or switch");
    if (G == o.parameter)
        throw input_error("clearance: the flow parameter " + names[static_cast<std::size_t>(G)].name +
                          " is the gap parameter");
    for (const double g : o.gaps)
        if (!(g >= 0.0) || !std::isfinite(g))
            throw input_error("gap " + format_double(g) + " is below zero: a chart's gaps must be >= 0");
    for (const double f : o.fractions)
        if (!(f > 0.0) || !std::isfinite(f))
            throw input_error("fraction " + format_double(f) + " of the clearance must be > 0");
    if (o.gaps.empty() && o.fractions.empty()) throw input_error("clearance needs gaps or fractions for its chart");
    const Eigen::VectorXd ic = o.initial_state.size() ? o.initial_state : m.initial_state();
    check_state_size(m, ic.size(), "the initial state");
    for (const double v : o.values) (void)m.with_parameter(o.parameter, v);  // validates each value
    grazing_options go = o.grazing;
    go.parameter = G;
    validate(m, go);

    const json spec = {{"analysis", "clearance"},
                       {"model", detail::to_json(m)},
                       {"parameter", o.parameter},
                       {"values", detail::to_json(o.values)},
                       {"gap_parameter", G},
                       {"gaps", detail::numbers(o.gaps)},
                       {"fractions", detail::numbers(o.fractions)},
                       {"initial_state", detail::vector_json(ic)},
                       {"protocol", detail::to_json(o.protocol)},
                       {"period_tolerance", detail::number(o.period_tolerance)},
                       {"grazing", detail::to_json(go)}};
    protocol_options po = o.protocol;
    po.flow.cancel = j.stop;
    go.cancel = j.stop;
    auto run = [&](long job, const clearance_point*) {
        clearance_point p;
        p.value = o.values[static_cast<std::size_t>(job)];
        const model mv = m.with_parameter(o.parameter, p.value);
        const grazing_result g = grazing(mv, ic, go);
        const surface_grazing& sg = surface >= 0 ? g.surfaces[static_cast<std::size_t>(surface)]
                                                 : g.switches[static_cast<std::size_t>(sw)];
        p.converged = sg.converged && g.status == outcome::ok;
        p.grazing_value = sg.parameter_value;
        const Eigen::VectorXd rest = mv.initial_state();
        // A switch's gap is on the side the runs start on (the side its grazing margin has).
        const double side = surface >= 0 ? 1.0 : switch_side_at(mv, sw, ic);
        const auto gap_for = [&](double gap) {
            return surface >= 0 ? parameter_for_gap(mv, surface, G, rest, gap)
                                : switch_parameter_for_gap(mv, sw, G, rest, side, gap);
        };
        if (const auto at_grazing = with_value(mv, G, p.grazing_value))
            p.clearance = surface >= 0 ? rest_gap(*at_grazing, surface) : switch_rest_gap(*at_grazing, sw, side);
        std::vector<double> gaps = o.gaps;
        if (gaps.empty() && std::isfinite(p.clearance) && p.clearance > 0.0)
            for (const double f : o.fractions) gaps.push_back(f * p.clearance);
        for (const double gap : gaps) {
            clearance_cell cell;
            cell.gap = gap;
            cell.gap_parameter_value = gap_for(gap);
            const auto mg = with_value(mv, G, cell.gap_parameter_value);
            if (!mg || violated_surface(*mg, ic) >= 0) {
                cell.status = outcome::inadmissible;
                cell.label.label = std::string(to_string(cell.status));
            } else {
                const auto r = run_and_classify(*mg, ic, po, o.period_tolerance);
                cell.label = r.label;
                cell.status = r.run.status;
                cell.statistics = r.run.statistics;
                if (cell.label.label == "aperiodic") {
                    if (!(gap >= p.aperiodic_min)) p.aperiodic_min = gap;
                    if (!(gap <= p.aperiodic_max)) p.aperiodic_max = gap;
                }
            }
            p.cells.push_back(std::move(cell));
        }
        return p;
    };
    clearance_result res;
    res.gap_parameter = G;
    res.surface = surface;
    res.switch_index = sw;
    const long n = static_cast<long>(o.values.size());
    res.jobs = detail::run_journaled<clearance_point>(spec, {n, 0}, j, run, encode, decode,
                                                      [&](long, clearance_point&& p) { res.points.push_back(std::move(p)); });
    return res;
}

}  // namespace vimpact
