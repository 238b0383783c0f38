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

py::dict floquet_dict(const model& m, const floquet_result& r)
{
    const bool have = r.has_multipliers();
    py::dict d;
    d["status"] = std::string(to_string(r.status));
    d["label"] = r.label;
    d["section_returns"] = r.section_returns;
    d["period"] = have ? r.period : nan;
    d["impacts_per_period"] = have ? r.impacts_per_period : 0L;
    d["impacts_by_surface"] = py::cast(r.impacts_by_surface);
    d["initial_closure"] = r.section_returns > 0 ? r.initial_closure : nan;
    d["closure"] = r.section_returns > 0 ? r.closure : nan;
    d["newton_iterations"] = r.newton_iterations;
    d["orbit_point"] = have && r.orbit_point.size() ? vector_array(r.orbit_point)
                                                    : vector_array(Eigen::VectorXd::Constant(m.dim(), nan));
    d["monodromy"] = have && r.monodromy.size() ? matrix_array(r.monodromy)
                                                : matrix_array(Eigen::MatrixXd::Constant(m.dim(), m.dim(), nan));
    py::array_t<std::complex<double>> mults(static_cast<py::ssize_t>(r.multipliers.size()));
    {
        auto mv = mults.mutable_unchecked<1>();
        for (std::size_t i = 0; i < r.multipliers.size(); ++i) mv(static_cast<py::ssize_t>(i)) = r.multipliers[i];
    }
    d["multipliers"] = mults;
    d["trivial_error"] = have ? r.trivial_error : nan;
    d["trivial_residual"] = have ? r.trivial_residual : nan;
    d["max_nontrivial_modulus"] = have ? r.max_nontrivial_modulus : nan;
    d["stable"] = have ? py::object(py::bool_(r.stable())) : py::object(py::none());
    d["det_monodromy"] = have ? r.det_monodromy : nan;
    d["liouville_det"] = have ? r.liouville_det : nan;
    d["divergence_integral"] = have ? r.divergence_integral : nan;
    d["log_det_jumps"] = have ? r.log_det_jumps : nan;
    d["impact_map"] = std::string(to_string(r.jump));
    put_impacts(d, "impact", r.impacts);
    put_series(d, "orbit", r.orbit);
    put_series(d, "section", r.section_points);
    d["protocol_stats"] = stats_dict(r.protocol_stats);
    d["tangent_stats"] = stats_dict(r.tangent_stats);
    d["map_evaluations"] = r.map_evaluations;
    return d;
}

py::dict lyapunov_dict(const model& m, const lyapunov_result& r)
{
    py::dict d;
    d["status"] = std::string(to_string(r.status));
    d["tdm"] = std::string(to_string(r.tdm));
    d["impacting"] = r.impacting;
    d["exponents"] = r.exponents.size() ? vector_array(r.exponents) : vector_array(Eigen::VectorXd::Constant(m.dim(), nan));
    d["lle_standard_error"] = r.lle_standard_error;
    d["positive"] = r.positive_largest_exponent();
    d["settled"] = r.settled;
    d["t_start"] = r.t_start;
    d["time"] = r.time;
    d["impacts"] = r.impacts;
    d["impacts_by_surface"] = py::cast(r.impacts_by_surface);
    d["intervals"] = r.intervals;
    d["divergence_average"] = r.divergence_average;
    d["jump_log_det_rate"] = r.jump_log_det_rate;
    d["sum_rule"] = r.sum_rule;
    d["misses"] = r.misses;
    d["history_t"] = vector_array(r.history_t);
    d["history_growth"] = rows_array(r.history, m.dim());
    put_series(d, "section", r.section_points);
    d["transient_stats"] = stats_dict(r.transient_stats);
    d["stats"] = stats_dict(r.stats);
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
        d["records"] = record_arrays(r.points, m.surface_count(), m.dim());
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
        d["records"] = record_arrays(r.points, m.surface_count(), m.dim());
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
