#include "vimpact/analysis/map.hpp"

#include <cmath>

#include "io/record_json.hpp"
#include "jobs/journal.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/core/format.hpp"

namespace vimpact {

namespace {

using detail::json;

struct map_record {
    map_cell cell;
    std::vector<double> grazing;  // per surface, on the jobs that compute the grazing line
    std::vector<double> switch_grazing;  // per switch, the same
};

template <class V, record_of<map_record> R>
void describe(V& v, R& r)
{
    describe(v, r.cell);
    v(field{"grazing", "grazing values per surface, on the jobs of the grazing line", "parameter",
            field_span::per_surface},
      r.grazing);
    v(field{"switch_grazing", "grazing values per switch, on the jobs of the grazing line", "parameter",
            field_span::per_switch},
      r.switch_grazing);
}

bool moves_a_surface_or_switch(const model& m, int parameter)
{
    return surface_moved_by(m, parameter) >= 0 || switch_moved_by(m, parameter) >= 0;
}

}  // namespace

map_result map2d(const model& m, const map_options& o, const job_options& j, const job_stream<map_cell>& each)
{
    validate(o.protocol);
    validate(m, o.protocol.section);
    check_options(o);
    const int P = static_cast<int>(m.parameters().size());
    if (o.x.parameter < 0 || o.x.parameter >= P || o.y.parameter < 0 || o.y.parameter >= P)
        throw input_error("map axis parameter index out of range");
    const auto& info = m.info();
    const auto& xname = info.parameters[static_cast<std::size_t>(o.x.parameter)].name;
    const auto& yname = info.parameters[static_cast<std::size_t>(o.y.parameter)].name;
    if (o.x.parameter == o.y.parameter)
        throw input_error("the map's axes must be different parameters (both are " + xname + ")");
    if (o.x.values.empty() || o.y.values.empty()) throw input_error("a map axis needs at least one value");
    const Eigen::VectorXd ic = o.initial_state.size() ? o.initial_state : m.initial_state();
    check_state_size(m, ic.size(), "the initial state");
    for (const double yv : o.y.values) {
        const model my = m.with_parameter(o.y.parameter, yv);
        for (const double xv : o.x.values) {
            const model mxy = my.with_parameter(o.x.parameter, xv);
            if (violated_surface(mxy, ic) >= 0)
                throw input_error("the initial state lies beyond a surface at " + xname + " = " + format_double(xv) +
                                  ", " + yname + " = " + format_double(yv) + "; choose another initial state or ranges");
        }
    }
    int grazing_axis = -1;
    if (o.grazing) {
        if (moves_a_surface_or_switch(m, o.y.parameter)) grazing_axis = 1;
        else if (moves_a_surface_or_switch(m, o.x.parameter)) grazing_axis = 0;
        else
            throw input_error("the grazing line needs an axis parameter that moves a surface or switch without "
                              "entering the vector field (" + xname + " and " + yname + " do not)");
    }
    grazing_options go = job_grazing_options(o.protocol.flow.integration);
    go.method = o.protocol.method;
    go.parameter = grazing_axis == 1 ? o.y.parameter : o.x.parameter;
    go.cancel = j.stop;
    protocol_options po = o.protocol;
    po.flow.cancel = j.stop;
    const int res_batch = resolve_batch(m, j.batch);

    const long nx = static_cast<long>(o.x.values.size()), ny = static_cast<long>(o.y.values.size());
    const json spec = {{"analysis", "map"},
                       {"model", detail::to_json(m)},
                       {"x", {{"parameter", o.x.parameter}, {"values", detail::to_json(o.x.values)}}},
                       {"y", {{"parameter", o.y.parameter}, {"values", detail::to_json(o.y.values)}}},
                       {"initial_state", detail::vector_json(ic)},
                       {"protocol", detail::to_json(o.protocol)},
                       {"period_tolerance", detail::number(o.period_tolerance)},
                       {"grazing", o.grazing}};
    auto computes_grazing = [&](long ix, long iy) {
        return (grazing_axis == 1 && iy == 0) || (grazing_axis == 0 && ix == 0);
    };
    // The jobs run their protocols together as lanes free up (SIMD lanes where the model allows).
    auto stream = [&](const job_source& next, const job_sink<map_record>& done) {
        simulate_stream(
            m, po, res_batch,
            [&]() -> std::optional<protocol_job> {
                const std::optional<long> job = next();
                if (!job) return std::nullopt;
                return protocol_job{*job,
                                    m.with_parameter(o.x.parameter, o.x.values[static_cast<std::size_t>(*job % nx)])
                                        .with_parameter(o.y.parameter, o.y.values[static_cast<std::size_t>(*job / nx)]),
                                    ic};
            },
            [&](protocol_job&& pj, simulation&& run) {
                map_record rec;
                rec.cell.label = classify_period(pj.m, run, o.period_tolerance);
                rec.cell.status = run.status;
                rec.cell.steps = run.stats.steps;
                rec.cell.statistics = run.statistics;
                if (computes_grazing(pj.key % nx, pj.key / nx)) {
                    const auto g = grazing(pj.m, ic, go);
                    for (const auto& s : g.surfaces) rec.grazing.push_back(s.parameter_value);
                    for (const auto& s : g.switches) rec.switch_grazing.push_back(s.parameter_value);
                }
                done(pj.key, std::move(rec));
            });
    };
    map_result res;
    res.grazing_axis = grazing_axis;
    job_options jb = j;
    jb.batch = res_batch;
    res.jobs = detail::run_journaled<map_record>(spec, {nx * ny, 0}, jb, job_streamer{stream},
                                                 detail::record_json<map_record>, detail::record_from<map_record>,
                                                 [&](long job, map_record&& r) {
        if (computes_grazing(job % nx, job / nx)) {
            res.grazing_other.push_back(grazing_axis == 1 ? o.x.values[static_cast<std::size_t>(job % nx)]
                                                          : o.y.values[static_cast<std::size_t>(job / nx)]);
            res.grazing_values.push_back(r.grazing);
            res.grazing_switch_values.push_back(r.switch_grazing);
        }
        if (each) each(job, r.cell);
        else res.cells.push_back(std::move(r.cell));
    });
    return res;
}

}  // namespace vimpact
