#include "vimpact/analysis/basins.hpp"

#include <cmath>
#include <numbers>

#include "admissible_jobs.hpp"
#include "io/record_json.hpp"
#include "jobs/journal.hpp"

namespace vimpact {

namespace {

using detail::json;

// A journal line: the cell as described and the signature its attractor is identified by.
// The attractor's id (-1 in the line) is given as the cells are read back, in job order.
struct basin_record {
    basin_cell cell;
};

template <class V, record_of<basin_record> R>
void describe(V& v, R& r)
{
    describe(v, r.cell);
    v.group(field{"signature", "what identifies the attractor the run reached"}, r.cell.signature);
}

}  // namespace

attractor_signature signature_of(const model& m, const simulation& run, const period_label& label)
{
    const auto& info = m.info();
    const auto k = static_cast<Eigen::Index>(coordinate_names(info).size());
    std::vector<Eigen::VectorXd> coords;
    coords.reserve(run.points.size());
    for (std::size_t i = 0; i < run.points.size(); ++i) {
        Eigen::VectorXd c(k);
        state_coordinates(info, run.points.x(i).data(), c.data());
        coords.push_back(std::move(c));
    }
    return make_signature(label.label, label.period, coords);
}

basins_result basins(const model& m, const basins_options& o, const job_options& j, const job_stream<basin_cell>& each)
{
    validate(o.protocol);
    validate(m, o.protocol.section);
    check_options(o);
    if (o.x_state < 0 || o.x_state >= m.dim() || o.y_state < 0 || o.y_state >= m.dim())
        throw input_error("basin axis state index out of range");
    if (o.x_state == o.y_state)
        throw input_error("the basin axes must be different state variables (both are " +
                          m.info().state[static_cast<std::size_t>(o.x_state)].name + ")");
    if (o.x_values.empty() || o.y_values.empty()) throw input_error("a basin axis needs at least one value");
    for (const auto* axis : {&o.x_values, &o.y_values})
        for (const double v : *axis)
            if (!std::isfinite(v)) throw input_error("basin axis values must be finite");
    const Eigen::VectorXd base = o.initial_state.size() ? o.initial_state : m.initial_state();
    check_state_size(m, base.size(), "the initial state");
    protocol_options po = o.protocol;
    po.flow.cancel = j.stop;
    const long nx = static_cast<long>(o.x_values.size()), ny = static_cast<long>(o.y_values.size());
    const json spec = {{"analysis", "basins"},
                       {"model", detail::to_json(m)},
                       {"x", {{"state", o.x_state}, {"values", detail::to_json(o.x_values)}}},
                       {"y", {{"state", o.y_state}, {"values", detail::to_json(o.y_values)}}},
                       {"initial_state", detail::vector_json(base)},
                       {"protocol", detail::to_json(o.protocol)},
                       {"period_tolerance", detail::number(o.period_tolerance)},
                       {"match_tolerance", detail::number(o.match.tolerance)}};
    const int batch = resolve_batch(m, j.batch);
    // The admissible jobs run their protocols together as lanes free up (SIMD lanes where the
    // model allows).
    auto stream = [&](const job_source& next, const job_sink<basin_record>& done) {
        simulate_stream(
            m, po, batch,
            detail::admissible_jobs(
                next,
                [&](long job) {
                    Eigen::VectorXd x0 = base;
                    x0[o.x_state] = o.x_values[static_cast<std::size_t>(job % nx)];
                    x0[o.y_state] = o.y_values[static_cast<std::size_t>(job / nx)];
                    return protocol_job{job, m, std::move(x0)};
                },
                [&](protocol_job&& pj) {
                    basin_cell c;
                    c.status = outcome::inadmissible;
                    c.label.label = std::string(to_string(c.status));
                    done(pj.key, {std::move(c)});
                }),
            [&](protocol_job&& pj, simulation&& run) {
                basin_cell c;
                c.admissible = true;
                c.label = classify_period(m, run, o.period_tolerance);
                c.status = run.status;
                c.steps = run.stats.steps;
                c.signature = signature_of(m, run, c.label);
                done(pj.key, {std::move(c)});
            });
    };
    basins_result res;
    // Attractors are numbered in order of first appearance: identified as the cells stream.
    attractor_catalogue catalogue(o.match);
    job_options jb = j;
    jb.batch = batch;
    res.jobs = detail::run_journaled<basin_record>(spec, {nx * ny, 0}, jb, job_streamer{stream},
                                                   detail::record_json<basin_record>,
                                                   detail::record_from<basin_record>, [&](long job, basin_record&& r) {
        basin_cell& c = r.cell;
        c.attractor = c.admissible ? catalogue.identify(c.signature) : -1;
        if (each) each(job, c);
        else res.cells.push_back(std::move(c));
    });
    if (res.jobs.complete()) res.attractors = catalogue.entries();
    return res;
}

}  // namespace vimpact
