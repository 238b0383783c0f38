// Single runs: the protocol (simulate), its period label (period) and the grazing value.
// Each returns a dict of numpy arrays and numbers; vimpact/_api.py turns it into a result
// object and documents it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>

#include "bindings.hpp"
#include "common.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/sweep.hpp"

namespace vimpact::python {
namespace {

template <int N>
py::dict simulation_dict(const protocol_result<N>& r)
{
    py::dict d;
    d["outcome"] = std::string(to_string(r.status));
    d["impacting"] = r.impacting;
    d["transient_impacts"] = r.transient_impacts;
    d["t_record_start"] = r.t_record_start;
    d["final_state"] = vector_array<N>(r.final_state);
    d["section_t"] = scalar_rows(r.points, [](const auto& p) { return p.t; });
    d["section"] = state_rows<N>(r.points, [](const auto& p) -> const vec<N>& { return p.x; });
    d["impact_t"] = scalar_rows(r.impacts, [](const auto& e) { return e.t; });
    d["impact_pre"] = state_rows<N>(r.impacts, [](const auto& e) -> const vec<N>& { return e.pre; });
    d["impact_post"] = state_rows<N>(r.impacts, [](const auto& e) -> const vec<N>& { return e.post; });
    d["series_t"] = scalar_rows(r.series, [](const auto& p) { return p.t; });
    d["series"] = state_rows<N>(r.series, [](const auto& p) -> const vec<N>& { return p.x; });
    d["stats"] = stats_dict(r.stats);
    return d;
}

template <class Model>
py::dict simulate(const Model& model, const input_array& ic, long transient, long record, double rtol, double atol,
                  const std::string& method, const std::string& section, double sample_dt, double quiet_time,
                  double t_max)
{
    const auto x0 = state_of(model, ic, "ic");
    const protocol_options po = protocol_of(transient, record, rtol, atol, section, sample_dt, quiet_time, t_max);
    const integration_method im = parse_integration_method(method, spelling);
    const auto r = run_released([&](const std::atomic<bool>& cancel) {
        protocol_options o = po;
        o.flow.cancel = &cancel;
        return with_integration_method(im, [&]<template <int> class M>() { return run_protocol<M>(model, x0, o); });
    });
    return simulation_dict(r);
}

template <class Model>
py::dict period(const Model& model, const input_array& ic, double tol, long transient, long record, double rtol,
                double atol, const std::string& method, const std::string& section, double quiet_time, double t_max)
{
    const auto x0 = state_of(model, ic, "ic");
    const protocol_options po = protocol_of(transient, record, rtol, atol, section, 0.0, quiet_time, t_max);
    const integration_method im = parse_integration_method(method, spelling);
    check_period_tolerance(tol, spelling);
    const auto r = run_released([&](const std::atomic<bool>& cancel) {
        protocol_options o = po;
        o.flow.cancel = &cancel;
        return with_integration_method(
            im, [&]<template <int> class M>() { return run_and_classify<M>(model, x0, o, tol); });
    });
    py::dict d;
    d["label"] = r.label.label;
    d["period"] = r.label.period;
    d["impacts"] = r.label.impacts_per_period;
    d["closure"] = r.label.closure;
    // The distinct section values of y of one period (the picture's "PN" points).
    std::vector<double> ys;
    for (int i = 0; i < r.label.period; ++i) ys.push_back(r.run.points[static_cast<std::size_t>(i)].x[Model::position]);
    d["section_y"] = scalar_rows(ys, [](double y) { return y; });
    d["simulation"] = simulation_dict(r.run);
    return d;
}

template <class Model>
py::dict grazing(const Model& model, const input_array& ic, double tol, double transient_time, double rtol, double atol,
                 const std::string& method, int block, double t_max)
{
    const auto x0 = state_of(model, ic, "ic");
    check_transient_time(transient_time, spelling);
    grazing_options go = job_grazing_options(tolerances_of(rtol, atol), transient_time);
    go.tolerance = tol;
    go.block = block;
    if (!(t_max > 0.0)) throw input_error("t_max must be > 0 (got " + format_double(t_max) + ")");
    go.t_max = t_max;
    const integration_method im = parse_integration_method(method, spelling);
    const auto g = run_released([&](const std::atomic<bool>& cancel) {
        grazing_options o = go;
        o.cancel = &cancel;
        return with_integration_method(im, [&]<template <int> class M>() { return grazing_value<M>(model, x0, o); });
    });
    py::dict d;
    d["sigma_graze"] = g.sigma_graze;
    d["converged"] = g.converged;
    d["change"] = g.change;
    d["t_graze"] = g.t_graze;
    d["x_graze"] = vector_array<Model::dim>(std::isfinite(g.sigma_graze) ? g.x_graze : vec<Model::dim>::Constant(std::nan("")));
    d["y_max"] = g.y_max;
    d["omega"] = g.omega;
    d["minima"] = g.minima;
    d["outcome"] = std::string(to_string(g.status));
    d["stats"] = stats_dict(g.stats);
    d["rtol"] = go.integration.rtol;
    d["atol"] = go.integration.atol;
    return d;
}

template <class Model>
void bind_for(py::module_& m)
{
    using namespace pybind11::literals;
    m.def("_simulate", &simulate<Model>, "model"_a, "ic"_a, "transient"_a, "record"_a, "rtol"_a, "atol"_a, "method"_a,
          "section"_a, "sample_dt"_a, "quiet_time"_a, "t_max"_a, "Internal: see vimpact.simulate.");
    m.def("_period", &period<Model>, "model"_a, "ic"_a, "tol"_a, "transient"_a, "record"_a, "rtol"_a, "atol"_a,
          "method"_a, "section"_a, "quiet_time"_a, "t_max"_a, "Internal: see vimpact.period.");
    m.def("_grazing", &grazing<Model>, "model"_a, "ic"_a, "tol"_a, "transient_time"_a, "rtol"_a, "atol"_a, "method"_a,
          "block"_a, "t_max"_a, "Internal: see vimpact.grazing.");
}

}  // namespace

void bind_runs(py::module_& m)
{
    bind_for<wake_impact>(m);
    bind_for<forced_impact_oscillator>(m);
}

}  // namespace vimpact::python
