#include "vimpact/analysis/stability_sweep.hpp"

#include <limits>

#include "io/json_codec.hpp"
#include "io/record_json.hpp"
#include "jobs/journal.hpp"
#include "vimpact/core/format.hpp"

namespace vimpact {

namespace {

using detail::json;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// A point as its description keeps it, so that a point read back from the journal is the
// point run: without what is not described, and NaN (0 counts) where a result has no values.
floquet_sweep_point floquet_point(double value, floquet_result r)
{
    r.monodromy.resize(0, 0);
    r.impacts.clear();
    r.orbit.clear();
    if (!r.has_multipliers()) {
        r.period = r.trivial_error = r.max_nontrivial_modulus = nan;
        r.impacts_per_period = 0;
        r.impacts_by_surface.clear();
    }
    if (r.section_returns <= 0) r.closure = r.initial_closure = nan;
    const bool stable = r.stable();
    return {value, std::move(r), stable};
}

lyapunov_sweep_point lyapunov_point(double value, lyapunov_result r)
{
    r.history.clear();
    r.history_t.clear();
    if (!r.has_exponents()) {
        r.exponents.setConstant(nan);
        r.lle_standard_error = nan;
    }
    const bool positive = r.positive_largest_exponent();
    return {value, std::move(r), positive};
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
        const double v = o.values[static_cast<std::size_t>(job)];
        return floquet_point(v, floquet(m.with_parameter(o.parameter, v), ic, fo));
    };
    floquet_sweep_result res;
    res.jobs = detail::run_journaled<floquet_sweep_point>(
        spec, {static_cast<long>(o.values.size()), 0}, j, run, detail::record_json<floquet_sweep_point>,
        [&](const json& r) {
            auto p = detail::record_from<floquet_sweep_point>(r);
            p.result.jump = o.floquet.jump;
            return p;
        },
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
        const double v = o.values[static_cast<std::size_t>(job)];
        return lyapunov_point(v, lyapunov(m.with_parameter(o.parameter, v), ic, lo));
    };
    lyapunov_sweep_result res;
    res.jobs = detail::run_journaled<lyapunov_sweep_point>(
        spec, {static_cast<long>(o.values.size()), 0}, j, run, detail::record_json<lyapunov_sweep_point>,
        [&](const json& r) {
            auto p = detail::record_from<lyapunov_sweep_point>(r);
            p.result.tdm = o.lyapunov.tdm;
            return p;
        },
        [&](long job, lyapunov_sweep_point&& p) {
            if (each) each(job, p);
            else res.points.push_back(std::move(p));
        });
    return res;
}

}  // namespace vimpact
