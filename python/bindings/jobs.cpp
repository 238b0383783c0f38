// The job-loop analyses: sweep, map, basins, response. Each validates its inputs with the
// library's checks (analysis/job_points.hpp, the same as the command line's), runs one job
// per point through run_jobs (threaded, results in job order, so they do not depend on the
// thread count) with the GIL released, and returns a dict of numpy arrays and lists in job
// order; vimpact/_api.py shapes it into a result object.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "common.hpp"

namespace vimpact::python {
namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

struct job_settings {
    protocol_options protocol;
    integration_method method = integration_method::dop853;
    job_loop_options loop;
};

job_settings settings_of(int threads, long transient, long record, double rtol, double atol, const std::string& method,
                         const std::string& section, double quiet_time, double t_max)
{
    job_settings s;
    s.protocol = protocol_of(transient, record, rtol, atol, section, 0.0, quiet_time, t_max);
    s.method = parse_integration_method(method, spelling);
    (void)resolve_threads(threads);
    s.loop.threads = threads;
    return s;
}

// Runs the jobs with the GIL released, Ctrl-C and progress reports; returns the job loop's
// summary. run(job, predecessor, protocol, grazing, Method) computes one job with the
// cancellable options it is given.
template <class Record, class Run, class Sink>
job_loop_summary run_job_loop(const job_settings& s, const job_schedule& schedule, const py::object& progress,
                              Run&& run, Sink&& sink)
{
    progress_reporter reporter(progress, schedule.jobs);
    const auto summary = run_released(
        [&](const std::atomic<bool>& cancel) {
            job_settings c = s;
            c.protocol.flow.cancel = &cancel;
            c.loop.stop = &cancel;
            c.loop.progress = reporter.sink();
            grazing_options go = job_grazing_options(c.protocol.flow.integration);
            go.cancel = &cancel;
            const std::unordered_map<long, Record> none;
            return with_integration_method(c.method, [&]<template <int> class M>() {
                return run_jobs<Record>(
                    schedule, c.loop, none,
                    [&](long job, const Record* prev) { return run.template operator()<M>(job, prev, c.protocol, go); },
                    sink);
            });
        },
        [&] { reporter.poll(); });
    reporter.finish();
    return summary;
}

py::dict loop_stats(const job_loop_summary& s, long steps, long rhs_calls)
{
    py::dict d;
    d["jobs"] = s.computed;
    d["threads"] = s.threads;
    d["steps"] = steps;
    d["rhs_calls"] = rhs_calls;
    return d;
}

// ---------------------------------------------------------------- sweep

template <int N>
struct sweep_record {
    int branch = 0;
    double value = 0.0;
    period_label label;
    outcome status = outcome::ok;
    double sigma_graze = nan;
    vec<N> final_state = vec<N>::Zero();
    std::vector<vec<N>> points;
    run_stats stats;
};

template <class Model>
py::dict sweep(const Model& base, const std::string& param, const input_array& values_in, const input_array& ic_in,
               const std::string& ic_mode, const std::string& direction, double tol, bool grazing, int threads,
               long transient, long record, double rtol, double atol, const std::string& method,
               const std::string& section, double quiet_time, double t_max, const py::object& progress)
{
    constexpr int N = Model::dim;
    const auto ic = state_of(base, ic_in, "ic");
    const job_settings s = settings_of(threads, transient, record, rtol, atol, method, section, quiet_time, t_max);
    check_parameter_name(base, param, input_name(spelling, "param"));
    const std::vector<double> values = values_of(values_in, "values");
    check_period_tolerance(tol, spelling);
    const sweep_plan plan = make_sweep_plan(static_cast<long>(values.size()), ic_mode, direction, spelling);
    check_sweep_starts(base, param, values, ic, plan, spelling);

    const job_schedule schedule = plan.schedule();
    std::vector<sweep_record<N>> records(static_cast<std::size_t>(schedule.jobs));
    const auto summary = run_job_loop<sweep_record<N>>(
        s, schedule, progress,
        [&]<template <int> class M>(long job, const sweep_record<N>* prev, const protocol_options& po,
                                    const grazing_options& go) {
            const auto [branch, i] = plan.at(job);
            sweep_record<N> rec;
            rec.branch = branch;
            rec.value = values[static_cast<std::size_t>(i)];
            const Model m = with_parameter(base, param, rec.value);
            const vec<N> x0 = sweep_start(m, prev ? &prev->final_state : nullptr, ic);
            auto r = run_and_classify<M>(m, x0, po, tol);
            rec.label = std::move(r.label);
            rec.status = r.run.status;
            rec.final_state = r.run.final_state;
            rec.stats = r.run.stats;
            rec.points.reserve(r.run.points.size());
            for (const auto& p : r.run.points) rec.points.push_back(p.x);
            if (grazing) rec.sigma_graze = grazing_value<M>(m, ic, go).sigma_graze;
            return rec;
        },
        [&](long job, sweep_record<N>&& r) { records[static_cast<std::size_t>(job)] = std::move(r); });

    std::size_t npoints = 0;
    long steps = 0, rhs = 0;
    for (const auto& r : records) {
        npoints += r.points.size();
        steps += r.stats.steps;
        rhs += r.stats.rhs_calls;
    }
    auto points = new_array(static_cast<py::ssize_t>(npoints), N);
    py::array_t<std::int64_t> point_run(static_cast<py::ssize_t>(npoints));
    {
        auto pv = points.mutable_unchecked<2>();
        auto rv = point_run.mutable_unchecked<1>();
        py::ssize_t k = 0;
        for (std::size_t j = 0; j < records.size(); ++j)
            for (const auto& x : records[j].points) {
                for (int c = 0; c < N; ++c) pv(k, c) = x[c];
                rv(k++) = static_cast<std::int64_t>(j);
            }
    }
    py::list labels, outcomes;
    for (const auto& r : records) {
        labels.append(r.label.label);
        outcomes.append(std::string(to_string(r.status)));
    }
    py::dict d;
    d["branch"] = typed_rows<std::int64_t>(records, [](const auto& r) { return r.branch; });
    d["value"] = scalar_rows(records, [](const auto& r) { return r.value; });
    d["label"] = labels;
    d["period"] = typed_rows<std::int64_t>(records, [](const auto& r) { return r.label.period; });
    d["impacts"] = typed_rows<std::int64_t>(records, [](const auto& r) { return r.label.impacts_per_period; });
    d["closure"] = scalar_rows(records, [](const auto& r) { return r.label.closure; });
    d["outcome"] = outcomes;
    d["sigma_graze"] = scalar_rows(records, [](const auto& r) { return r.sigma_graze; });
    d["final_state"] = state_rows<N>(records, [](const auto& r) -> const vec<N>& { return r.final_state; });
    d["steps"] = typed_rows<std::int64_t>(records, [](const auto& r) { return r.stats.steps; });
    d["points"] = points;
    d["point_run"] = point_run;
    d["stats"] = loop_stats(summary, steps, rhs);
    return d;
}

// ---------------------------------------------------------------- map

struct map_record {
    period_label label;
    outcome status = outcome::ok;
    long steps = 0, rhs_calls = 0;
    bool has_graze = false;
    double sigma_graze = nan;
};

template <class Model>
py::dict map2d(const Model& base, const std::string& x, const input_array& xs_in, const std::string& y,
               const input_array& ys_in, const input_array& ic_in, double tol, bool grazing, int threads, long transient,
               long record, double rtol, double atol, const std::string& method, const std::string& section,
               double quiet_time, double t_max, const py::object& progress)
{
    const auto ic = state_of(base, ic_in, "ic");
    const job_settings s = settings_of(threads, transient, record, rtol, atol, method, section, quiet_time, t_max);
    check_parameter_name(base, x, input_name(spelling, "x"));
    const std::vector<double> xs = values_of(xs_in, "x values");
    check_parameter_name(base, y, input_name(spelling, "y"));
    const std::vector<double> ys = values_of(ys_in, "y values");
    check_map_axes(x, y, spelling);
    check_period_tolerance(tol, spelling);
    check_map_starts(base, x, xs, y, ys, ic, spelling);
    const grazing_line graze = map_grazing_line(grazing, x, y, spelling);

    const long nx = static_cast<long>(xs.size()), ny = static_cast<long>(ys.size());
    const job_schedule schedule{nx * ny, 0};
    std::vector<map_record> records(static_cast<std::size_t>(schedule.jobs));
    const auto summary = run_job_loop<map_record>(
        s, schedule, progress,
        [&]<template <int> class M>(long job, const map_record*, const protocol_options& po, const grazing_options& go) {
            const long ix = job % nx, iy = job / nx;
            const Model m = map_model(base, x, xs[static_cast<std::size_t>(ix)], y, ys[static_cast<std::size_t>(iy)]);
            const auto r = run_and_classify<M>(m, ic, po, tol);
            map_record rec;
            rec.label = r.label;
            rec.status = r.run.status;
            rec.steps = r.run.stats.steps;
            rec.rhs_calls = r.run.stats.rhs_calls;
            if (computes_grazing(graze, ix, iy)) {
                rec.has_graze = true;
                rec.sigma_graze = grazing_value<M>(m, ic, go).sigma_graze;
            }
            return rec;
        },
        [&](long job, map_record&& r) { records[static_cast<std::size_t>(job)] = std::move(r); });

    long steps = 0, rhs = 0;
    py::list labels, outcomes;
    std::vector<std::pair<double, double>> line;
    for (std::size_t j = 0; j < records.size(); ++j) {
        const auto& r = records[j];
        labels.append(r.label.label);
        outcomes.append(std::string(to_string(r.status)));
        steps += r.steps;
        rhs += r.rhs_calls;
        if (r.has_graze) {
            const long job = static_cast<long>(j);
            const double other = graze == grazing_line::along_x ? xs[static_cast<std::size_t>(job % nx)]
                                                                : ys[static_cast<std::size_t>(job / nx)];
            line.emplace_back(other, r.sigma_graze);
        }
    }
    py::dict d;
    d["label"] = labels;
    d["outcome"] = outcomes;
    d["period"] = typed_rows<std::int64_t>(records, [](const auto& r) { return r.label.period; });
    d["impacts"] = typed_rows<std::int64_t>(records, [](const auto& r) { return r.label.impacts_per_period; });
    d["closure"] = scalar_rows(records, [](const auto& r) { return r.label.closure; });
    d["steps"] = typed_rows<std::int64_t>(records, [](const auto& r) { return r.steps; });
    if (graze != grazing_line::none) {
        auto g = new_array(static_cast<py::ssize_t>(line.size()), 2);
        auto gv = g.mutable_unchecked<2>();
        for (std::size_t k = 0; k < line.size(); ++k) {
            gv(static_cast<py::ssize_t>(k), 0) = line[k].first;
            gv(static_cast<py::ssize_t>(k), 1) = line[k].second;
        }
        d["grazing"] = g;
    } else {
        d["grazing"] = py::none();
    }
    d["stats"] = loop_stats(summary, steps, rhs);
    return d;
}

// ---------------------------------------------------------------- basins

struct basin_record {
    bool admissible = false;
    period_label label;
    std::string outcome_text = "none";
    long steps = 0, rhs_calls = 0;
    attractor_signature signature;
};

py::array_t<double> rows_of(const std::vector<Eigen::VectorXd>& v, Eigen::Index cols)
{
    auto a = new_array(static_cast<py::ssize_t>(v.size()), static_cast<py::ssize_t>(cols));
    auto av = a.mutable_unchecked<2>();
    for (std::size_t i = 0; i < v.size(); ++i)
        for (Eigen::Index c = 0; c < cols; ++c) av(static_cast<py::ssize_t>(i), c) = v[i][c];
    return a;
}

template <class Model>
py::dict basins(const Model& model, const std::string& x, const input_array& xs_in, const std::string& y,
                const input_array& ys_in, const input_array& ic_in, double tol, double match_tol, int threads,
                long transient, long record, double rtol, double atol, const std::string& method,
                const std::string& section, double quiet_time, double t_max, const py::object& progress)
{
    const auto ic = state_of(model, ic_in, "ic");
    const job_settings s = settings_of(threads, transient, record, rtol, atol, method, section, quiet_time, t_max);
    const int sx = state_axis_index(model, x, input_name(spelling, "x"));
    const std::vector<double> xs = values_of(xs_in, "x values");
    const int sy = state_axis_index(model, y, input_name(spelling, "y"));
    const std::vector<double> ys = values_of(ys_in, "y values");
    check_basin_axes(sx, sy, x, spelling);
    check_period_tolerance(tol, spelling);
    check_match_tolerance(match_tol, spelling);

    const long nx = static_cast<long>(xs.size()), ny = static_cast<long>(ys.size());
    const job_schedule schedule{nx * ny, 0};
    std::vector<basin_record> records(static_cast<std::size_t>(schedule.jobs));
    const auto summary = run_job_loop<basin_record>(
        s, schedule, progress,
        [&]<template <int> class M>(long job, const basin_record*, const protocol_options& po, const grazing_options&) {
            const auto x0 = basin_start(ic, sx, xs[static_cast<std::size_t>(job % nx)], sy,
                                        ys[static_cast<std::size_t>(job / nx)]);
            basin_record rec;
            if (!admissible_start(model, x0)) {
                rec.label.label = "inadmissible";
                return rec;
            }
            const auto r = run_and_classify<M>(model, x0, po, tol);
            rec.admissible = true;
            rec.label = r.label;
            rec.outcome_text = std::string(to_string(r.run.status));
            rec.steps = r.run.stats.steps;
            rec.rhs_calls = r.run.stats.rhs_calls;
            rec.signature = signature_of(model, r);
            return rec;
        },
        [&](long job, basin_record&& r) { records[static_cast<std::size_t>(job)] = std::move(r); });

    attractor_catalogue catalogue({.tolerance = match_tol});
    std::vector<const attractor_signature*> runs;
    runs.reserve(records.size());
    for (const auto& r : records) runs.push_back(r.admissible ? &r.signature : nullptr);
    const std::vector<int> ids = identify_attractors(runs, catalogue);

    long steps = 0, rhs = 0;
    py::list labels, outcomes;
    for (const auto& r : records) {
        labels.append(r.label.label);
        outcomes.append(r.outcome_text);
        steps += r.steps;
        rhs += r.rhs_calls;
    }
    py::list table;
    for (std::size_t i = 0; i < catalogue.entries().size(); ++i) {
        const auto& e = catalogue.entries()[i];
        const Eigen::Index k = e.signature.lo.size();
        py::dict a;
        a["id"] = static_cast<long>(i);
        a["label"] = e.signature.label;
        a["cells"] = e.members;
        a["cycle"] = rows_of(e.signature.cycle, k);
        std::vector<Eigen::VectorXd> box;
        if (k > 0) box = {e.signature.lo, e.signature.hi};
        a["box"] = rows_of(box, k);
        table.append(a);
    }
    py::dict d;
    d["attractor"] = typed_rows<std::int64_t>(ids, [](int id) { return id; });
    d["label"] = labels;
    d["outcome"] = outcomes;
    d["period"] = typed_rows<std::int64_t>(records, [](const auto& r) { return r.label.period; });
    d["steps"] = typed_rows<std::int64_t>(records, [](const auto& r) { return r.steps; });
    d["attractors"] = table;
    d["stats"] = loop_stats(summary, steps, rhs);
    return d;
}

// ---------------------------------------------------------------- response

py::dict response(const wake_impact& base, const std::string& param, const input_array& values_in,
                  const std::vector<std::pair<double, double>>& curves, const input_array& ic_in,
                  double transient_time, double rtol, double atol, const std::string& method, int threads,
                  const py::object& progress)
{
    const auto ic = state_of(base, ic_in, "ic");
    job_settings s;
    s.protocol.flow.integration = tolerances_of(rtol, atol);
    s.method = parse_integration_method(method, spelling);
    (void)resolve_threads(threads);
    s.loop.threads = threads;
    check_parameter_name(base, param, input_name(spelling, "param"));
    check_response_param(param, spelling);
    const std::vector<double> values = values_of(values_in, "values");
    if (curves.empty()) throw input_error("curves must hold at least one (A, eps) pair");
    check_transient_time(transient_time, spelling);
    for (const auto& [A, eps] : curves) (void)base.with("A", A).with("eps", eps);  // validates

    const long n = static_cast<long>(values.size()), nc = static_cast<long>(curves.size());
    const job_schedule schedule{n * nc, 0};
    std::vector<response_point> records(static_cast<std::size_t>(schedule.jobs));
    const auto summary = run_job_loop<response_point>(
        s, schedule, progress,
        [&]<template <int> class M>(long job, const response_point*, const protocol_options& po,
                                    const grazing_options&) {
            const long k = job / n, i = job % n;
            const auto [A, eps] = curves[static_cast<std::size_t>(k)];
            const wake_impact m = response_model(base, A, eps, param, values[static_cast<std::size_t>(i)]);
            grazing_options go = job_grazing_options(po.flow.integration, transient_time);
            go.cancel = po.flow.cancel;
            return run_response_point<M>(m, ic, go);
        },
        [&](long job, response_point&& r) { records[static_cast<std::size_t>(job)] = std::move(r); });

    long steps = 0, rhs = 0;
    py::list outcomes;
    for (const auto& r : records) {
        outcomes.append(std::string(to_string(r.status)));
        steps += r.stats.steps;
        rhs += r.stats.rhs_calls;
    }
    py::dict d;
    d["amplitude"] = scalar_rows(records, [](const auto& r) { return r.amplitude; });
    d["y_max"] = scalar_rows(records, [](const auto& r) { return r.y_max; });
    d["sigma_graze"] = scalar_rows(records, [](const auto& r) { return r.sigma_graze; });
    d["frequency_ratio"] = scalar_rows(records, [](const auto& r) { return r.frequency_ratio; });
    d["structure_frequency"] = scalar_rows(records, [](const auto& r) { return r.structure_frequency; });
    d["converged"] = typed_rows<bool>(records, [](const auto& r) { return r.converged; });
    d["outcome"] = outcomes;
    d["steps"] = typed_rows<std::int64_t>(records, [](const auto& r) { return r.stats.steps; });
    d["stats"] = loop_stats(summary, steps, rhs);
    return d;
}

template <class Model>
void bind_for(py::module_& m)
{
    using namespace pybind11::literals;
    m.def("_sweep", &sweep<Model>, "model"_a, "param"_a, "values"_a, "ic"_a, "ic_mode"_a, "direction"_a, "tol"_a,
          "grazing"_a, "threads"_a, "transient"_a, "record"_a, "rtol"_a, "atol"_a, "method"_a, "section"_a,
          "quiet_time"_a, "t_max"_a, "progress"_a, "Internal: see vimpact.sweep.");
    m.def("_map", &map2d<Model>, "model"_a, "x"_a, "x_values"_a, "y"_a, "y_values"_a, "ic"_a, "tol"_a, "grazing"_a,
          "threads"_a, "transient"_a, "record"_a, "rtol"_a, "atol"_a, "method"_a, "section"_a, "quiet_time"_a,
          "t_max"_a, "progress"_a, "Internal: see vimpact.map.");
    m.def("_basins", &basins<Model>, "model"_a, "x"_a, "x_values"_a, "y"_a, "y_values"_a, "ic"_a, "tol"_a,
          "match_tol"_a, "threads"_a, "transient"_a, "record"_a, "rtol"_a, "atol"_a, "method"_a, "section"_a,
          "quiet_time"_a, "t_max"_a, "progress"_a, "Internal: see vimpact.basins.");
}

}  // namespace

void bind_jobs(py::module_& m)
{
    bind_for<wake_impact>(m);
    bind_for<forced_impact_oscillator>(m);
    using namespace pybind11::literals;
    m.def("_response", &response, "model"_a, "param"_a, "values"_a, "curves"_a, "ic"_a, "transient_time"_a, "rtol"_a,
          "atol"_a, "method"_a, "threads"_a, "progress"_a, "Internal: see vimpact.response.");
}

}  // namespace vimpact::python
