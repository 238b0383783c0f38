// The extension module vimpact._vimpact. The public API is the package vimpact
// (python/vimpact/__init__.py), which documents every function and wraps these results.
#include <pybind11/pybind11.h>

#include <string>

#include "bindings.hpp"
#include "common.hpp"
#include "vimpact/analysis/attractor.hpp"
#include "vimpact/analysis/correlation_dimension.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/io/build_info.hpp"
#include "vimpact/jobs/job_loop.hpp"
#include "vimpact/stability/floquet.hpp"
#include "vimpact/stability/lyapunov.hpp"

namespace py = pybind11;
using namespace vimpact;

namespace {

// The library's defaults, so that the Python signatures show them without restating them.
py::dict defaults()
{
    const protocol_options po;
    const grazing_options go;
    py::dict d;
    d["transient"] = po.transient_impacts;
    d["record"] = po.record_points;
    d["rtol"] = po.flow.integration.rtol;
    d["atol"] = po.flow.integration.atol;
    d["method"] = "dop853";
    d["section"] = std::string(to_string(po.section));
    d["sample_dt"] = po.sample_dt;
    d["quiet_time"] = po.quiet_time;
    d["t_max"] = po.flow.t_max;
    d["period_tol"] = default_period_tolerance;
    d["grazing_tol"] = go.tolerance;
    d["grazing_transient_time"] = go.transient_time;
    d["grazing_rtol"] = go.integration.rtol;
    d["grazing_atol"] = go.integration.atol;
    d["grazing_block"] = go.block;
    d["grazing_t_max"] = go.t_max;
    d["match_tol"] = attractor_match_options{}.tolerance;
    d["threads"] = job_loop_options{}.threads;
    const floquet_options fo;
    d["newton_tol"] = fo.shooting.tolerance;
    d["newton_iterations"] = fo.shooting.max_iterations;
    const lyapunov_options lo;
    d["r0"] = lo.r0;
    d["t0"] = lo.t0;
    d["lyapunov_impacts"] = lo.impacts;
    d["warmup"] = lo.warmup_intervals;
    const dimension_options dop;
    d["centres"] = dop.centre.centres;
    d["radii"] = py::make_tuple(dop.centre.r_min, dop.centre.r_max, dop.centre.r_step);
    d["slope_tolerance"] = dop.scaling.slope_tolerance;
    d["slope_window"] = dop.scaling.slope_window;
    d["min_extent"] = dop.scaling.min_extent;
    d["min_pairs"] = dop.scaling.min_pairs;
    d["max_correlation"] = dop.scaling.max_correlation;
    d["max_pairs"] = dop.max_pairs;
    d["bins_per_octave"] = dop.correlation.bins_per_octave;
    return d;
}

}  // namespace

PYBIND11_MODULE(_vimpact, m)
{
    m.doc() = "vimpact's compiled core; use the package vimpact.";
    // Bad input (the library's input_error) is a ValueError carrying the library's message,
    // the same text the command line prints after "vimpact: error: ".
    py::register_exception<input_error>(m, "InputError", PyExc_ValueError);
    m.attr("__version__") = std::string(version());
    m.attr("git_hash") = std::string(git_hash());
    m.attr("defaults") = defaults();
    m.def(
        "grid",
        [](double a, double b, long n) {
            const auto v = grid_values(a, b, n);
            return vimpact::python::scalar_rows(v, [](double x) { return x; });
        },
        py::arg("a"), py::arg("b"), py::arg("n"),
          R"(n values from a to b inclusive, evenly spaced: the command line's range a:b:n.

Value i is computed as a + i (b - a)/(n - 1) and the last is b exactly, so the values are
bit-for-bit those of ``vimpact sweep --range a:b:n`` (numpy.linspace rounds differently).

Returns
-------
ndarray, float64, shape (n,))");
    vimpact::python::bind_models(m);
    vimpact::python::bind_runs(m);
    vimpact::python::bind_jobs(m);
    vimpact::python::bind_stability(m);
    vimpact::python::bind_dimension(m);
}
