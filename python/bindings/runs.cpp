// Single runs: the protocol (simulate), its period label (period) and the grazing analysis.
// Each returns a dict of numpy arrays and numbers, keyed by the attributes of its result object
// in vimpact/results.py (which documents them).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>

#include "bindings.hpp"
#include "common.hpp"
#include "records.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/period.hpp"

namespace vimpact::python {
namespace {

py::dict simulation_dict(const model& m, const simulation& r)
{
    const auto velocities = impact_velocities(m, r.impacts);
    py::dict d;
    d["outcome"] = std::string(to_string(r.status));
    d["impacting"] = r.impacting;
    d["transient_impacts"] = r.transient_impacts;
    d["t_record_start"] = r.t_record_start;
    d["final_state"] = vector_array(r.final_state);
    put_series(d, "section", r.points);
    put_impacts(d, "impact", r.impacts);
    put_impacts(d, "switching", r.switchings);
    put_series(d, "series", r.series);
    d["stats"] = record_dict(r.stats, m);
    d["t_record_end"] = r.t_record_end;
    d["statistics"] = statistics_dict(r.statistics);
    d["impact_velocity"] = column<double>(velocities, [](const auto& v) { return v.normal; });
    d["impact_rebound"] = column<double>(velocities, [](const auto& v) { return v.rebound; });
    d["impact_energy"] = column<double>(velocities, [](const auto& v) { return v.energy; });
    return d;
}

py::dict simulate(const model& m, const py::object& ic, const py::dict& kw)
{
    options o(kw);
    const Eigen::VectorXd x0 = initial_state_of(m, ic);
    const protocol_options po = protocol_of(m, o);
    o.finish();
    const auto r = run_released([&](const std::atomic<bool>& cancel) {
        protocol_options c = po;
        c.flow.cancel = &cancel;
        return simulate(m, x0, c);
    });
    return simulation_dict(m, r);
}

py::dict period(const model& m, const py::object& ic, const py::dict& kw)
{
    options o(kw);
    const Eigen::VectorXd x0 = initial_state_of(m, ic);
    const protocol_options po = protocol_of(m, o);
    const double tol = o.need<double>("tol");
    o.finish();
    const auto r = run_released([&](const std::atomic<bool>& cancel) {
        protocol_options c = po;
        c.flow.cancel = &cancel;
        return run_and_classify(m, x0, c, tol);
    });
    py::dict d;
    d["record"] = record_dict(r.label, m);
    d["simulation"] = simulation_dict(m, r.run);
    return d;
}

grazing_options grazing_of(const model& m, options& o)
{
    grazing_options go;
    read_integration(o, go.integration, go.method);
    read_declared(o, go);
    // None: each surface's own gap parameter (the library's rule).
    go.parameter = o.has("param") ? parameter_index(m, o.need<std::string>("param"), "param") : each_surface_gap_parameter;
    (void)o.object("param");
    if (o.has("variable")) go.response_variable = state_index(m, o.need<std::string>("variable"), "variable");
    (void)o.object("variable");
    return go;
}

py::dict grazing_run(const model& m, const py::object& ic, const py::dict& kw)
{
    options o(kw);
    const Eigen::VectorXd x0 = initial_state_of(m, ic);
    const grazing_options go = grazing_of(m, o);
    o.finish();
    const auto g = run_released([&](const std::atomic<bool>& cancel) {
        grazing_options c = go;
        c.cancel = &cancel;
        return grazing(m, x0, c);
    });
    py::dict d;
    d["outcome"] = std::string(to_string(g.status));
    d["converged"] = g.converged;
    const auto& s = g.surfaces;
    d["surface_converged"] = column<bool>(s, [](const auto& x) { return x.converged; });
    d["margin"] = column<double>(s, [](const auto& x) { return x.margin; });
    d["change"] = column<double>(s, [](const auto& x) { return x.change; });
    d["value"] = column<double>(s, [](const auto& x) { return x.parameter_value; });
    py::list params;
    for (const auto& x : s)
        params.append(x.parameter >= 0 ? py::object(py::str(m.info().parameters[static_cast<std::size_t>(x.parameter)].name))
                                       : py::object(py::none()));
    d["param"] = params;
    d["t"] = column<double>(s, [](const auto& x) { return x.t; });
    d["minima"] = column<std::int64_t>(s, [](const auto& x) { return x.minima; });
    std::vector<Eigen::VectorXd> xs;
    for (const auto& x : s) xs.push_back(x.x);
    d["x"] = rows_array(xs, m.dim());
    py::list switches;  // per switch, as Grazing.by_surface gives a surface's
    for (const auto& x : g.switches) {
        py::dict w;
        w["param"] = x.parameter >= 0 ? py::object(py::str(m.info().parameters[static_cast<std::size_t>(x.parameter)].name))
                                      : py::object(py::none());
        w["value"] = x.parameter_value;
        w["margin"] = x.margin;
        w["converged"] = x.converged;
        w["change"] = x.change;
        w["t"] = x.t;
        w["x"] = vector_array(x.x.size() ? x.x : Eigen::VectorXd::Constant(m.dim(), std::nan("")));
        w["minima"] = x.minima;
        switches.append(w);
    }
    d["switch_grazing"] = switches;
    d["response_max"] = g.response_max;
    d["response_min"] = g.response_min;
    d["response_omega"] = g.response_omega;
    d["stats"] = record_dict(g.stats, m);
    return d;
}

}  // namespace

void bind_runs(py::module_& m)
{
    using namespace pybind11::literals;
    m.def("_simulate", &simulate, "model"_a, "ic"_a, "options"_a, "Internal: see vimpact.simulate.");
    m.def("_period", &period, "model"_a, "ic"_a, "options"_a, "Internal: see vimpact.period.");
    m.def("_grazing", &grazing_run, "model"_a, "ic"_a, "options"_a, "Internal: see vimpact.grazing.");
}

}  // namespace vimpact::python
