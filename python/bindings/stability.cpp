// Stability of the attractor: Floquet multipliers of a periodic orbit (include/vimpact/
// stability/floquet.hpp) and the Lyapunov spectrum (lyapunov.hpp). Dicts of numpy arrays;
// vimpact/_api.py makes result objects of them.
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <complex>
#include <cstdint>
#include <limits>
#include <string>

#include "bindings.hpp"
#include "common.hpp"
#include "vimpact/stability/floquet.hpp"
#include "vimpact/stability/lyapunov.hpp"

namespace vimpact::python {
namespace {

template <int N>
py::array_t<double> matrix_array(const mat<N>& m)
{
    auto a = new_array(N, N);
    auto v = a.template mutable_unchecked<2>();
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) v(i, j) = m(i, j);
    return a;
}

impact_tangent parse_impact_map(const std::string& s)
{
    if (s == "saltation") return impact_tangent::saltation;
    if (s == "reset-jacobian") return impact_tangent::reset_jacobian;
    if (s == "identity") return impact_tangent::identity;
    throw input_error(input_name(spelling, "impact_map") + " '" + s +
                      "' is not one of saltation, reset-jacobian, identity");
}

template <class Model>
py::dict floquet(const Model& model, const input_array& ic, double tol, double newton_tol, int newton_iterations,
                 const std::string& impact_map, double sample_dt, long transient, long record, double rtol,
                 double atol, const std::string& method, double quiet_time, double t_max)
{
    constexpr int N = Model::dim;
    const auto x0 = state_of(model, ic, "ic");
    floquet_options fo;
    fo.protocol = protocol_of(transient, record, rtol, atol, "maxima", 0.0, quiet_time, t_max);
    fo.period_tolerance = tol;
    fo.shooting.tolerance = newton_tol;
    fo.shooting.max_iterations = newton_iterations;
    fo.shooting.map.flow.integration = tangent_integration_options(fo.protocol.flow.integration);
    fo.jump = parse_impact_map(impact_map);
    if (!(sample_dt >= 0.0) || !std::isfinite(sample_dt)) throw input_error("sample_dt must be >= 0 and finite");
    fo.sample_dt = sample_dt;
    const integration_method im = parse_integration_method(method, spelling);
    const auto r = run_released([&](const std::atomic<bool>& cancel) {
        floquet_options o = fo;
        o.protocol.flow.cancel = &cancel;
        o.shooting.map.flow.cancel = &cancel;
        return with_integration_method(im, [&]<template <int> class M>() { return floquet_analysis<M>(model, x0, o); });
    });
    const bool have = r.status == floquet_status::ok || r.status == floquet_status::not_converged;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    py::array_t<std::complex<double>> mults(static_cast<py::ssize_t>(r.multipliers.size()));
    {
        auto mv = mults.mutable_unchecked<1>();
        for (std::size_t i = 0; i < r.multipliers.size(); ++i) mv(static_cast<py::ssize_t>(i)) = r.multipliers[i];
    }
    py::dict d;
    d["status"] = std::string(to_string(r.status));
    d["flow_outcome"] = r.flow_outcome;
    d["label"] = r.label;
    d["section_returns"] = r.section_returns;
    d["period"] = have ? r.period : nan;
    d["impacts_per_period"] = have ? r.impacts_per_period : 0L;
    d["initial_closure"] = r.section_returns > 0 ? r.initial_closure : nan;
    d["closure"] = r.section_returns > 0 ? r.closure : nan;
    d["newton_iterations"] = r.newton_iterations;
    d["orbit_point"] = vector_array<N>(have ? r.orbit_point : vec<N>::Constant(nan));
    d["monodromy"] = matrix_array<N>(have ? r.monodromy : mat<N>::Constant(nan));
    d["multipliers"] = mults;
    d["trivial_error"] = have ? r.trivial_error : nan;
    d["trivial_residual"] = have ? r.trivial_residual : nan;
    d["max_nontrivial_modulus"] = have ? r.max_nontrivial_modulus : nan;
    d["stable"] = have ? py::object(py::bool_(r.stable())) : py::object(py::none());
    d["det_monodromy"] = have ? r.det_monodromy : nan;
    d["liouville_det"] = have ? r.liouville_det : nan;
    d["impact_map"] = std::string(to_string(r.jump));
    d["tangent_rtol"] = fo.shooting.map.flow.integration.rtol;
    d["impact_t"] = scalar_rows(r.impacts, [](const auto& e) { return e.t; });
    d["impact_pre"] = state_rows<N>(r.impacts, [](const auto& e) -> const vec<N>& { return e.pre; });
    d["impact_post"] = state_rows<N>(r.impacts, [](const auto& e) -> const vec<N>& { return e.post; });
    d["orbit_t"] = scalar_rows(r.orbit, [](const auto& p) { return p.t; });
    d["orbit"] = state_rows<N>(r.orbit, [](const auto& p) -> const vec<N>& { return p.x; });
    d["protocol_stats"] = stats_dict(r.protocol_stats);
    d["tangent_stats"] = stats_dict(r.tangent_stats);
    d["map_evaluations"] = r.map_evaluations;
    return d;
}

template <class Model>
py::dict lyapunov(const Model& model, const input_array& ic, const std::string& tdm, double r0, double t0,
                  long impacts, double time, long warmup, long transient, double rtol, double atol,
                  const std::string& method, double quiet_time, double t_max)
{
    constexpr int N = Model::dim;
    const auto x0 = state_of(model, ic, "ic");
    lyapunov_options lo;
    // The protocol's checks for what the transient shares with it (one recorded point).
    const protocol_options po = protocol_of(transient, 1, rtol, atol, "maxima", 0.0, quiet_time, t_max);
    if (tdm == "saltation") lo.tdm = lyapunov_tdm::saltation;
    else if (tdm == "second-order") lo.tdm = lyapunov_tdm::second_order;
    else if (tdm == "trajectory") lo.tdm = lyapunov_tdm::trajectory;
    else throw input_error(input_name(spelling, "tdm") + " '" + tdm + "' is not one of saltation, second-order, trajectory");
    lo.r0 = r0;
    lo.t0 = t0;
    lo.impacts = impacts;
    lo.time = time;
    lo.warmup_intervals = warmup;
    lo.transient_impacts = transient;
    lo.quiet_time = quiet_time;
    lo.flow = po.flow;
    const integration_method im = parse_integration_method(method, spelling);
    const auto r = run_released([&](const std::atomic<bool>& cancel) {
        lyapunov_options o = lo;
        o.flow.cancel = &cancel;
        return with_integration_method(im, [&]<template <int> class M>() { return lyapunov_spectrum<M>(model, x0, o); });
    });
    py::dict d;
    d["status"] = std::string(to_string(r.status));
    d["flow_outcome"] = r.flow_outcome;
    d["tdm"] = std::string(to_string(r.tdm));
    d["impacting"] = r.impacting;
    d["exponents"] = vector_array<N>(r.exponents);
    d["lle_standard_error"] = r.lle_standard_error;
    d["t_start"] = r.t_start;
    d["time"] = r.time;
    d["impacts"] = r.impacts;
    d["intervals"] = r.intervals;
    d["divergence_average"] = r.divergence_average;
    d["jump_log_det_rate"] = r.jump_log_det_rate;
    d["sum_rule"] = r.sum_rule;
    d["misses"] = r.misses;
    d["history_t"] = scalar_rows(r.history, [](const auto& s) { return s.t; });
    d["history_growth"] = state_rows<N>(r.history, [](const auto& s) -> const vec<N>& { return s.growth; });
    d["transient_stats"] = stats_dict(r.transient_stats);
    d["tangent_stats"] = stats_dict(r.stats);
    return d;
}

template <class Model>
void bind_for(py::module_& m)
{
    using namespace pybind11::literals;
    m.def("_floquet", &floquet<Model>, "model"_a, "ic"_a, "tol"_a, "newton_tol"_a, "newton_iterations"_a,
          "impact_map"_a, "sample_dt"_a, "transient"_a, "record"_a, "rtol"_a, "atol"_a, "method"_a, "quiet_time"_a,
          "t_max"_a, "Internal: see vimpact.floquet.");
    m.def("_lyapunov", &lyapunov<Model>, "model"_a, "ic"_a, "tdm"_a, "r0"_a, "t0"_a, "impacts"_a, "time"_a,
          "warmup"_a, "transient"_a, "rtol"_a, "atol"_a, "method"_a, "quiet_time"_a, "t_max"_a,
          "Internal: see vimpact.lyapunov.");
}

}  // namespace

void bind_stability(py::module_& m)
{
    bind_for<wake_impact>(m);
    bind_for<forced_impact_oscillator>(m);
}

}  // namespace vimpact::python
