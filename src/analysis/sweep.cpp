#include "vimpact/analysis/sweep.hpp"

#include <cmath>

#include "admissible_jobs.hpp"
#include "io/record_json.hpp"
#include "jobs/journal.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/core/format.hpp"

namespace vimpact {

namespace {

using detail::json;

// Which job is which point: job j of a sweep over n values is value index `index` on branch
// `branch` (0 up, 1 down). Fixed starts: independent jobs in the sweep's direction. Followed
// branches: one chain per direction; with both directions the chains interleave (job 2k is
// the k-th point up, job 2k + 1 the k-th point down), so the two run in parallel.
struct sweep_plan {
    long values = 0;
    bool follow = false;
    sweep_direction direction = sweep_direction::up;

    [[nodiscard]] bool both() const { return direction == sweep_direction::both; }
    [[nodiscard]] job_schedule schedule() const
    {
        return {both() ? 2 * values : values, follow ? (both() ? 2 : 1) : 0};
    }
    [[nodiscard]] std::pair<int, long> at(long job) const
    {
        if (both()) return {static_cast<int>(job % 2), job % 2 == 0 ? job / 2 : values - 1 - job / 2};
        if (direction == sweep_direction::down) return {1, values - 1 - job};
        return {0, job};
    }
};

}  // namespace

std::vector<double> grid_values(double a, double b, long n) { return value_grid::range(a, b, n).values(); }

Eigen::VectorXd continue_from(const model& next, const Eigen::VectorXd& x_in)
{
    Eigen::VectorXd x = x_in;
    const auto& t = next.table();
    Eigen::VectorXd n(next.dim()), f(next.dim());
    for (int pass = 0; pass < 4; ++pass) {
        const int i = violated_surface(next, x);
        if (i < 0) break;
        // Onto the surface: Newton steps along the gap's gradient.
        for (int it = 0; it < 20; ++it) {
            const double g = t.gap(next.context(), i, x.data());
            if (g >= 0.0) break;
            t.gap_gradient(next.context(), i, x.data(), n.data());
            const double nn = n.squaredNorm();
            if (!(nn > 0.0)) break;
            x -= (g / nn) * n;
        }
        // Moving into it: an impact.
        t.rhs(next.context(), x.data(), f.data());
        t.gap_gradient(next.context(), i, x.data(), n.data());
        if (n.dot(f) < 0.0) {
            Eigen::VectorXd post(next.dim());
            t.reset(next.context(), i, x.data(), post.data());
            x = post;
        }
    }
    return x;
}

sweep_result sweep(const model& m, const sweep_options& o, const job_options& j, const job_stream<sweep_point>& each)
{
    validate(o.protocol);
    validate(m, o.protocol.section);
    check_options(o);
    const bool follow = o.start == sweep_start::follow;
    const int P = static_cast<int>(m.parameters().size());
    if (o.parameter < 0 || o.parameter >= P) throw input_error("sweep parameter index out of range");
    if (o.values.empty()) throw input_error("a sweep needs at least one value");
    if (o.direction == sweep_direction::both && !follow)
        throw option_error("direction", " = both needs ic_mode follow (with fixed starts both directions are the "
                                        "same runs)");
    if (o.grazing_parameter >= P) throw input_error("grazing parameter index out of range");
    const Eigen::VectorXd ic = o.initial_state.size() ? o.initial_state : m.initial_state();
    check_state_size(m, ic.size(), "the initial state");
    const auto& pname = m.info().parameters[static_cast<std::size_t>(o.parameter)].name;
    for (const double v : o.values) {
        const model mv = m.with_parameter(o.parameter, v);  // validates the value
        if (!follow && violated_surface(mv, ic) >= 0)
            throw input_error("the initial state lies beyond surface " +
                              mv.info().surfaces[static_cast<std::size_t>(violated_surface(mv, ic))].name + " at " +
                              pname + " = " + format_double(v) + "; choose another initial state or range");
    }
    if (follow) {
        const double first = o.direction == sweep_direction::down ? o.values.back() : o.values.front();
        if (violated_surface(m.with_parameter(o.parameter, first), ic) >= 0)
            throw input_error("the initial state lies beyond a surface at the first point of the sweep (" + pname +
                              " = " + format_double(first) + ")");
    }
    grazing_options go = job_grazing_options(o.protocol.flow.integration);
    go.parameter = o.grazing_parameter;
    go.method = o.protocol.method;
    if (o.grazing_parameter >= 0) validate(m, go);

    const sweep_plan plan{static_cast<long>(o.values.size()), follow, o.direction};
    const json spec = {{"analysis", "sweep"},
                       {"model", detail::to_json(m)},
                       {"parameter", o.parameter},
                       {"values", detail::to_json(o.values)},
                       {"initial_state", detail::vector_json(ic)},
                       {"follow", follow},
                       {"direction", std::string(to_string(o.direction))},
                       {"protocol", detail::to_json(o.protocol)},
                       {"period_tolerance", detail::number(o.period_tolerance)},
                       {"grazing_parameter", o.grazing_parameter}};
    protocol_options po = o.protocol;
    po.flow.cancel = j.stop;
    go.cancel = j.stop;
    const int batch = follow ? 1 : resolve_batch(m, j.batch);
    // The points `next` gives, from the fixed start or, on a followed branch, from where the
    // previous point `prev` ended. Independent points run their protocols together (SIMD
    // lanes where the model allows); a followed branch goes one point after the other.
    auto stream_from = [&](const job_source& next, const job_sink<sweep_point>& done, const sweep_point* prev) {
        auto point_at = [&](long job) {
            const auto [branch, i] = plan.at(job);
            sweep_point p;
            p.branch = branch;
            p.value = o.values[static_cast<std::size_t>(i)];
            p.grazing.assign(static_cast<std::size_t>(m.surface_count()), std::numeric_limits<double>::quiet_NaN());
            p.switch_grazing.assign(m.info().switches.size(), std::numeric_limits<double>::quiet_NaN());
            return p;
        };
        simulate_stream(
            m, po, batch,
            detail::admissible_jobs(
                next,
                [&](long job) {
                    model mv = m.with_parameter(o.parameter, o.values[static_cast<std::size_t>(plan.at(job).second)]);
                    Eigen::VectorXd x0 = prev ? continue_from(mv, prev->final_state) : ic;
                    return protocol_job{job, std::move(mv), std::move(x0)};
                },
                [&](protocol_job&& pj) {
                    sweep_point p = point_at(pj.key);
                    p.status = outcome::inadmissible;
                    p.label.label = std::string(to_string(p.status));
                    p.points = state_series(m.dim());
                    p.final_state = std::move(pj.x0);
                    done(pj.key, std::move(p));
                }),
            [&](protocol_job&& pj, simulation&& run) {
                sweep_point p = point_at(pj.key);
                p.label = classify_period(pj.m, run, o.period_tolerance);
                p.status = run.status;
                p.points = std::move(run.points);
                p.final_state = run.final_state;
                p.stats = run.stats;
                p.statistics = run.statistics;
                if (o.grazing_parameter >= 0) {
                    const auto g = grazing(pj.m, ic, go);
                    for (std::size_t s = 0; s < g.surfaces.size(); ++s) p.grazing[s] = g.surfaces[s].parameter_value;
                    for (std::size_t k = 0; k < g.switches.size(); ++k) p.switch_grazing[k] = g.switches[k].parameter_value;
                }
                done(pj.key, std::move(p));
            });
    };
    auto single = [&](long job, const sweep_point* prev) {
        return run_alone<sweep_point>(
            [&](const job_source& next, const job_sink<sweep_point>& done) { stream_from(next, done, prev); }, job);
    };
    auto stream = [&](const job_source& next, const job_sink<sweep_point>& done) { stream_from(next, done, nullptr); };
    sweep_result res;
    job_options jb = j;
    jb.batch = batch;
    res.jobs = detail::run_journaled<sweep_point>(spec, plan.schedule(), jb, job_runners{single, stream}, detail::record_json<sweep_point>,
                                                  detail::record_from<sweep_point>,
                                                  [&](long job, sweep_point&& p) {
                                                      if (each) each(job, p);
                                                      else res.points.push_back(std::move(p));
                                                  });
    return res;
}

}  // namespace vimpact
