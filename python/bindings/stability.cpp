// Stability of the attractor: Floquet multipliers of a periodic orbit
// (include/vimpact/analysis/floquet.hpp), the Lyapunov spectrum (lyapunov.hpp) and both over
// a range of one parameter (stability_sweep.hpp; their points as records.hpp's columns).
// Dicts of numpy arrays; vimpact/_api.py makes result objects of them.
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <complex>
#include <cstdint>
#include <limits>
#include <string>

#include "bindings.hpp"
#include "common.hpp"
#include "records.hpp"
#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/lyapunov.hpp"
#include "vimpact/analysis/stability_sweep.hpp"
#include "vimpact/integrate/tangent_integration.hpp"

namespace vimpact::python {
namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

floquet_options floquet_of(const model& m, options& o)
{
    floquet_options fo;
    fo.protocol = protocol_of(m, o);
    read_declared(o, fo);
    fo.tangent_integration = tangent_integration(fo.protocol.flow.integration);
    fo.tangent_integration.rtol = o.get<double>("tangent_rtol", fo.tangent_integration.rtol);
    fo.tangent_integration.atol = o.get<double>("tangent_atol", fo.tangent_integration.atol);
    fo.sample_dt = o.get<double>("sample_dt", fo.sample_dt);
    return fo;
}

// The protocol's sample_dt belongs to simulate; Floquet samples the refined orbit instead.
void no_protocol_samples(floquet_options& fo) { fo.protocol.sample_dt = 0.0; }

lyapunov_options lyapunov_of(const model& m, options& o)
{
    lyapunov_options lo;
    // The protocol's keywords, read as the protocol's (record 0 is the Lyapunov analysis' own
    // default, checked by it: no points).
    protocol_options po;
    read_declared(o, po);
    lo.transient_impacts = po.transient_impacts;
    lo.record_points = po.record_points;
    lo.method = po.method;
    lo.flow.integration = po.flow.integration;
    lo.quiet_time = po.quiet_time;
    lo.flow.t_max = po.flow.t_max;
    read_declared(o, lo);
    if (o.has("section")) {
        const section_choice s = section_of(m, o.need<std::string>("section"));
        if (s.type != section_choice::kind::crossing)
            throw input_error("the Lyapunov analysis records a section crossing (one of " + m.info().section_names() +
                              "), not the impacts");
        lo.section = s.index;
    }
    (void)o.object("section");
    return lo;
}

// The result's record by its description (record_dict), NaN where a run without multipliers
// (or without a period) has no value, and what the record leaves out: the monodromy, the
// verdict, the impacts and the orbit over one period.
py::dict floquet_dict(const model& m, floquet_result r)
{
    const bool have = r.has_multipliers();
    if (!have) {
        r.period = r.trivial_error = r.trivial_residual = r.max_nontrivial_modulus = nan;
        r.det_monodromy = r.liouville_det = r.divergence_integral = r.log_det_jumps = nan;
        r.impacts_per_period = 0;
        r.orbit_point.resize(0);
    }
    if (r.section_returns <= 0) r.initial_closure = r.closure = nan;
    py::dict d;
    d["record"] = record_dict(r, m);
    d["monodromy"] = have && r.monodromy.size() ? matrix_array(r.monodromy)
                                                : matrix_array(Eigen::MatrixXd::Constant(m.dim(), m.dim(), nan));
    d["stable"] = have ? py::object(py::bool_(r.stable())) : py::object(py::none());
    d["impact_map"] = std::string(to_string(r.jump));
    put_impacts(d, "impact", r.impacts);
    put_series(d, "orbit", r.orbit);
    return d;
}

// The record (record_dict), the library's verdict on the exponents and the interval history.
py::dict lyapunov_dict(const model& m, const lyapunov_result& r)
{
    py::dict d;
    d["record"] = record_dict(r, m);
    d["tdm"] = std::string(to_string(r.tdm));
    d["positive"] = r.positive_largest_exponent();
    d["history_t"] = vector_array(r.history_t);
    d["history_growth"] = rows_array(r.history, m.dim());
    d["running_exponents"] = rows_array(r.running_exponents(), m.dim());
    return d;
}

py::dict floquet_run(const model& m, const py::object& ic, const py::dict& kw)
{
    options o(kw);
    const Eigen::VectorXd x0 = initial_state_of(m, ic);
    floquet_options fo = floquet_of(m, o);
    no_protocol_samples(fo);
    o.finish();
    const auto r = run_released([&](const std::atomic<bool>& cancel) {
        floquet_options c = fo;
        c.protocol.flow.cancel = &cancel;
        return floquet(m, x0, c);
    });
    return floquet_dict(m, r);
}

py::dict lyapunov_run(const model& m, const py::object& ic, const py::dict& kw)
{
    options o(kw);
    const Eigen::VectorXd x0 = initial_state_of(m, ic);
    const lyapunov_options lo = lyapunov_of(m, o);
    o.finish();
    const auto r = run_released([&](const std::atomic<bool>& cancel) {
        lyapunov_options c = lo;
        c.flow.cancel = &cancel;
        return lyapunov(m, x0, c);
    });
    return lyapunov_dict(m, r);
}

py::dict floquet_sweep_run(const model& m, const py::dict& kw)
{
    options o(kw);
    floquet_sweep_options so;
    read_parameter_values(m, o, so);
    so.floquet = floquet_of(m, o);
    no_protocol_samples(so.floquet);
    const auto analysis = [&](const job_options& c) { return floquet_sweep(m, so, c); };
    return run_jobs(o, analysis, [&](py::dict& d, const floquet_sweep_result& r) {
        d["records"] = record_arrays(r.points, m);
    });
}

py::dict lyapunov_sweep_run(const model& m, const py::dict& kw)
{
    options o(kw);
    lyapunov_sweep_options so;
    read_parameter_values(m, o, so);
    so.lyapunov = lyapunov_of(m, o);
    const auto analysis = [&](const job_options& c) { return lyapunov_sweep(m, so, c); };
    return run_jobs(o, analysis, [&](py::dict& d, const lyapunov_sweep_result& r) {
        d["records"] = record_arrays(r.points, m);
    });
}

}  // namespace

void bind_stability(py::module_& m)
{
    using namespace pybind11::literals;
    m.def("_floquet", &floquet_run, "model"_a, "ic"_a, "options"_a, "Internal: see vimpact.floquet.");
    m.def("_lyapunov", &lyapunov_run, "model"_a, "ic"_a, "options"_a, "Internal: see vimpact.lyapunov.");
    m.def("_floquet_sweep", &floquet_sweep_run, "model"_a, "options"_a, "Internal: see vimpact.floquet_sweep.");
    m.def("_lyapunov_sweep", &lyapunov_sweep_run, "model"_a, "options"_a, "Internal: see vimpact.lyapunov_sweep.");
}

}  // namespace vimpact::python
