#include "vimpact/analysis/stability_sweep.hpp"

#include "io/json_codec.hpp"
#include "jobs/journal.hpp"
#include "vimpact/core/format.hpp"

namespace vimpact {

namespace {

using detail::json;

json encode(const floquet_sweep_point& p)
{
    const floquet_result& r = p.result;
    json mu = json::array();
    for (const auto& m : r.multipliers) mu.push_back({detail::number(m.real()), detail::number(m.imag())});
    return {{"value", detail::number(p.value)},
            {"status", std::string(to_string(r.status))},
            {"label", r.label},
            {"section_returns", r.section_returns},
            {"period", detail::number(r.period)},
            {"impacts_per_period", r.impacts_per_period},
            {"impacts_by_surface", r.impacts_by_surface},
            {"initial_closure", detail::number(r.initial_closure)},
            {"closure", detail::number(r.closure)},
            {"newton_iterations", r.newton_iterations},
            {"orbit_point", detail::vector_json(r.orbit_point)},
            {"monodromy", detail::matrix_json(r.monodromy)},
            {"multipliers", mu},
            {"trivial_error", detail::number(r.trivial_error)},
            {"trivial_residual", detail::number(r.trivial_residual)},
            {"max_nontrivial_modulus", detail::number(r.max_nontrivial_modulus)},
            {"det_monodromy", detail::number(r.det_monodromy)},
            {"liouville_det", detail::number(r.liouville_det)},
            {"divergence_integral", detail::number(r.divergence_integral)},
            {"log_det_jumps", detail::number(r.log_det_jumps)},
            {"impacts", detail::to_json(r.impacts)},
            {"section_points", detail::to_json(r.section_points)},
            {"protocol_stats", detail::to_json(r.protocol_stats)},
            {"tangent_stats", detail::to_json(r.tangent_stats)},
            {"map_evaluations", r.map_evaluations}};
}

floquet_sweep_point decode_floquet(const json& j, impact_tangent jump)
{
    floquet_sweep_point p;
    p.value = detail::number_from(j.at("value"));
    floquet_result& r = p.result;
    r.status = detail::outcome_from(j.at("status"));
    r.label = j.at("label").get<std::string>();
    r.section_returns = j.at("section_returns").get<int>();
    r.period = detail::number_from(j.at("period"));
    r.impacts_per_period = j.at("impacts_per_period").get<long>();
    r.impacts_by_surface = j.at("impacts_by_surface").get<std::vector<long>>();
    r.initial_closure = detail::number_from(j.at("initial_closure"));
    r.closure = detail::number_from(j.at("closure"));
    r.newton_iterations = j.at("newton_iterations").get<int>();
    r.orbit_point = detail::vector_from(j.at("orbit_point"));
    r.monodromy = detail::matrix_from(j.at("monodromy"));
    for (const auto& m : j.at("multipliers"))
        r.multipliers.emplace_back(detail::number_from(m.at(0)), detail::number_from(m.at(1)));
    r.trivial_error = detail::number_from(j.at("trivial_error"));
    r.trivial_residual = detail::number_from(j.at("trivial_residual"));
    r.max_nontrivial_modulus = detail::number_from(j.at("max_nontrivial_modulus"));
    r.det_monodromy = detail::number_from(j.at("det_monodromy"));
    r.liouville_det = detail::number_from(j.at("liouville_det"));
    r.divergence_integral = detail::number_from(j.at("divergence_integral"));
    r.log_det_jumps = detail::number_from(j.at("log_det_jumps"));
    r.jump = jump;
    r.impacts = detail::impacts_from(j.at("impacts"));
    r.section_points = detail::series_from(j.at("section_points"));
    r.protocol_stats = detail::stats_from(j.at("protocol_stats"));
    r.tangent_stats = detail::stats_from(j.at("tangent_stats"));
    r.map_evaluations = j.at("map_evaluations").get<long>();
    return p;
}

json encode(const lyapunov_sweep_point& p)
{
    const lyapunov_result& r = p.result;
    return {{"value", detail::number(p.value)},
            {"status", std::string(to_string(r.status))},
            {"impacting", r.impacting},
            {"exponents", detail::vector_json(r.exponents)},
            {"lle_standard_error", detail::number(r.lle_standard_error)},
            {"settled", r.settled},
            {"t_start", detail::number(r.t_start)},
            {"time", detail::number(r.time)},
            {"impacts", r.impacts},
            {"impacts_by_surface", r.impacts_by_surface},
            {"intervals", r.intervals},
            {"divergence_average", detail::number(r.divergence_average)},
            {"jump_log_det_rate", detail::number(r.jump_log_det_rate)},
            {"sum_rule", detail::number(r.sum_rule)},
            {"misses", r.misses},
            {"section_points", detail::to_json(r.section_points)},
            {"transient_stats", detail::to_json(r.transient_stats)},
            {"stats", detail::to_json(r.stats)}};
}

lyapunov_sweep_point decode_lyapunov(const json& j, lyapunov_tdm tdm)
{
    lyapunov_sweep_point p;
    p.value = detail::number_from(j.at("value"));
    lyapunov_result& r = p.result;
    r.status = detail::outcome_from(j.at("status"));
    r.tdm = tdm;
    r.impacting = j.at("impacting").get<bool>();
    r.exponents = detail::vector_from(j.at("exponents"));
    r.lle_standard_error = detail::number_from(j.at("lle_standard_error"));
    r.settled = j.at("settled").get<bool>();
    r.t_start = detail::number_from(j.at("t_start"));
    r.time = detail::number_from(j.at("time"));
    r.impacts = j.at("impacts").get<long>();
    r.impacts_by_surface = j.at("impacts_by_surface").get<std::vector<long>>();
    r.intervals = j.at("intervals").get<long>();
    r.divergence_average = detail::number_from(j.at("divergence_average"));
    r.jump_log_det_rate = detail::number_from(j.at("jump_log_det_rate"));
    r.sum_rule = detail::number_from(j.at("sum_rule"));
    r.misses = j.at("misses").get<long>();
    r.section_points = detail::series_from(j.at("section_points"));
    r.transient_stats = detail::stats_from(j.at("transient_stats"));
    r.stats = detail::stats_from(j.at("stats"));
    return p;
}

// The values' models (each validated) and the start, checked admissible at every value.
Eigen::VectorXd check_values(const model& m, int parameter, const value_grid& values, const Eigen::VectorXd& x0)
{
    if (parameter < 0 || parameter >= static_cast<int>(m.parameters().size()))
        throw input_error("sweep parameter index out of range");
    if (values.empty()) throw input_error("a sweep needs at least one value");
    const Eigen::VectorXd ic = x0.size() ? x0 : m.initial_state();
    check_state_size(m, ic.size(), "the initial state");
    const auto& pname = m.info().parameters[static_cast<std::size_t>(parameter)].name;
    for (const double v : values)
        if (violated_surface(m.with_parameter(parameter, v), ic) >= 0)
            throw input_error("the initial state lies beyond a surface at " + pname + " = " + format_double(v) +
                              "; choose another initial state or range");
    return ic;
}

}  // namespace

floquet_sweep_result floquet_sweep(const model& m, const floquet_sweep_options& o, const job_options& j,
                                   const job_stream<floquet_sweep_point>& each)
{
    validate(m, o.floquet);
    const Eigen::VectorXd ic = check_values(m, o.parameter, o.values, o.initial_state);
    floquet_options fo = o.floquet;
    fo.sample_dt = 0.0;
    fo.protocol.flow.cancel = j.stop;
    const json spec = {{"analysis", "floquet_sweep"},     {"model", detail::to_json(m)},
                       {"parameter", o.parameter},         {"values", detail::to_json(o.values)},
                       {"initial_state", detail::vector_json(ic)}, {"floquet", detail::to_json(o.floquet)}};
    auto run = [&](long job, const floquet_sweep_point*) {
        floquet_sweep_point p;
        p.value = o.values[static_cast<std::size_t>(job)];
        p.result = floquet(m.with_parameter(o.parameter, p.value), ic, fo);
        return p;
    };
    floquet_sweep_result res;
    res.jobs = detail::run_journaled<floquet_sweep_point>(
        spec, {static_cast<long>(o.values.size()), 0}, j, run, [](const floquet_sweep_point& p) { return encode(p); },
        [&](const json& r) { return decode_floquet(r, o.floquet.jump); },
        [&](long job, floquet_sweep_point&& p) {
            if (each) each(job, p);
            else res.points.push_back(std::move(p));
        });
    return res;
}

lyapunov_sweep_result lyapunov_sweep(const model& m, const lyapunov_sweep_options& o, const job_options& j,
                                     const job_stream<lyapunov_sweep_point>& each)
{
    validate(m, o.lyapunov);
    const Eigen::VectorXd ic = check_values(m, o.parameter, o.values, o.initial_state);
    lyapunov_options lo = o.lyapunov;
    lo.flow.cancel = j.stop;
    const json spec = {{"analysis", "lyapunov_sweep"},    {"model", detail::to_json(m)},
                       {"parameter", o.parameter},         {"values", detail::to_json(o.values)},
                       {"initial_state", detail::vector_json(ic)}, {"lyapunov", detail::to_json(o.lyapunov)}};
    auto run = [&](long job, const lyapunov_sweep_point*) {
        lyapunov_sweep_point p;
        p.value = o.values[static_cast<std::size_t>(job)];
        p.result = lyapunov(m.with_parameter(o.parameter, p.value), ic, lo);
        p.result.history.clear();
        p.result.history_t.clear();
        return p;
    };
    lyapunov_sweep_result res;
    res.jobs = detail::run_journaled<lyapunov_sweep_point>(
        spec, {static_cast<long>(o.values.size()), 0}, j, run, [](const lyapunov_sweep_point& p) { return encode(p); },
        [&](const json& r) { return decode_lyapunov(r, o.lyapunov.tdm); },
        [&](long job, lyapunov_sweep_point&& p) {
            if (each) each(job, p);
            else res.points.push_back(std::move(p));
        });
    return res;
}

}  // namespace vimpact
