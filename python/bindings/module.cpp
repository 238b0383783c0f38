// The extension module vimpact._vimpact. The public API is the package vimpact
// (python/vimpact/__init__.py), which documents every function and wraps these results.
#include <pybind11/pybind11.h>

#include <string>

#include "bindings.hpp"
#include "common.hpp"
#include "records.hpp"
#include "vimpact/analysis/basins.hpp"
#include "vimpact/analysis/clearance.hpp"
#include "vimpact/analysis/continuation.hpp"
#include "vimpact/analysis/correlation_dimension.hpp"
#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/lyapunov.hpp"
#include "vimpact/analysis/map.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol_declaration.hpp"
#include "vimpact/analysis/response.hpp"
#include "vimpact/analysis/stability_sweep.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/io/build_info.hpp"

namespace py = pybind11;
using namespace vimpact;

namespace {

// The library's defaults, so that the Python signatures and docstrings show them without
// restating them.
py::dict defaults()
{
    const protocol_options po;
    const grazing_options go;
    const job_options jo;
    py::dict d;
    d["transient"] = po.transient_impacts;
    d["record"] = po.record_points;
    d["rtol"] = po.flow.integration.rtol;
    d["atol"] = po.flow.integration.atol;
    d["hold_band"] = py::none();  // the method's (integrator_options::hold_band)
    d["method"] = std::string(to_string(po.method));
    d["sample_dt"] = po.sample_dt;
    d["quiet_time"] = po.quiet_time;
    d["t_max"] = po.flow.t_max;
    d["period_tol"] = default_period_tolerance;
    d["grazing_transient_time"] = go.transient_time;
    d["grazing_rtol"] = go.integration.rtol;
    d["grazing_atol"] = go.integration.atol;
    d["threads"] = jo.threads;
    const floquet_options fo;
    d["tangent_rtol"] = fo.tangent_integration.rtol;
    d["tangent_atol"] = fo.tangent_integration.atol;
    const centre_count_options centres;
    d["radii"] = py::make_tuple(centres.r_min, centres.r_max, centres.r_step);
    return d;
}

}  // namespace

PYBIND11_MODULE(_vimpact, m)
{
    m.doc() = "vimpact's compiled core; use the package vimpact.";
    // Bad input (the library's input_error) is a ValueError carrying the library's message.
    py::register_exception<input_error>(m, "InputError", PyExc_ValueError);
    m.attr("__version__") = std::string(version());
    m.attr("git_hash") = std::string(git_hash());
    m.attr("defaults") = defaults();
    // What each analysis declares of its options (core/option.hpp): vimpact/_api.py builds
    // those keyword arguments, their defaults and their documentation from it.
    py::dict declared;
    declared["lyapunov"] = vimpact::python::declarations<lyapunov_options>();
    declared["floquet"] = vimpact::python::declarations<floquet_options>();
    declared["continuation"] = vimpact::python::declarations<continuation_options>();
    declared["sweep"] = vimpact::python::declarations<sweep_options>();
    declared["map"] = vimpact::python::declarations<map_options>();
    declared["basins"] = vimpact::python::declarations<basins_options>();
    declared["grazing"] = vimpact::python::declarations<grazing_options>();
    declared["response"] = vimpact::python::declarations<response_options>();
    declared["clearance"] = vimpact::python::declarations<clearance_options>();
    declared["dimension"] = vimpact::python::declarations<dimension_options>();
    declared["protocol"] = vimpact::python::declarations<protocol_options>();
    m.attr("declared") = declared;
    // What each record says of its fields (core/record.hpp): vimpact/results.py documents the
    // results' arrays from it.
    py::dict described;
    described["sweep"] = vimpact::python::described<sweep_point>();
    described["map"] = vimpact::python::described<map_cell>();
    described["basins"] = vimpact::python::described<basin_cell>();
    described["response"] = vimpact::python::described<response_point>();
    described["floquet_sweep"] = vimpact::python::described<floquet_sweep_point>();
    described["lyapunov_sweep"] = vimpact::python::described<lyapunov_sweep_point>();
    described["floquet"] = vimpact::python::described<floquet_result>();
    described["lyapunov"] = vimpact::python::described<lyapunov_result>();
    described["period"] = vimpact::python::described<period_label>();
    described["impact_statistics"] = vimpact::python::described<impact_statistics>();
    described["run_stats"] = vimpact::python::described<run_stats>();
    m.attr("described") = described;
    m.def(
        "grid",
        [](double a, double b, long n) { return vimpact::python::vector_array(grid_values(a, b, n)); },
        py::arg("a"), py::arg("b"), py::arg("n"), "Internal: see vimpact.grid.");
    m.def(
        "remove_journal", [](const std::string& dir) { remove_journal(dir); }, py::arg("directory"),
        "Internal: removes a journal directory.");
    vimpact::python::bind_models(m);
    vimpact::python::bind_runs(m);
    vimpact::python::bind_jobs(m);
    vimpact::python::bind_stability(m);
    vimpact::python::bind_dimension(m);
    vimpact::python::bind_continuation(m);
    vimpact::python::bind_units(m);
    vimpact::python::bind_systems(m);
}
