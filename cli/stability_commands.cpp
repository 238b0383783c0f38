// The stability commands: floquet and lyapunov (docs/stability.md), each a single analysis or,
// with --param P --range a:b:n, a sweep of it through the job loop (Figures 14-17).
#include <cmath>
#include <complex>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>

#include "commands.hpp"
#include "declared_options.hpp"
#include "job_runner.hpp"
#include "interrupts.hpp"
#include "output.hpp"
#include "parse.hpp"
#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/lyapunov.hpp"
#include "vimpact/analysis/stability_sweep.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/core/names.hpp"
#include "vimpact/io/csv_writer.hpp"
#include "vimpact/integrate/tangent_integration.hpp"
#include "vimpact/io/state_columns.hpp"
#include "vimpact/model/model_phrases.hpp"
#include "vimpact/physical/si_units.hpp"

namespace vimpact::cli {
namespace {

struct sweep_request {
    std::string param;
    std::string range;
    job_args jobs;
    [[nodiscard]] bool wanted() const { return !param.empty() || !range.empty(); }
};

struct floquet_args {
    common_args common;
    sweep_request sweep;
    floquet_options options;  // what it declares; the protocol and tangent runs from common
};

struct lyapunov_args {
    common_args common;
    sweep_request sweep;
    lyapunov_options options;  // what it declares; the protocol's part from common
};

std::string fixed(double v, int digits)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

// The swept parameter (with --si also U [m/s] or gap [m]), its name in the model and values.
struct sweep_values : axis_values {
    std::string name;
};

sweep_values parse_sweep(const sweep_request& s, const run_config& c)
{
    if (s.param.empty() || s.range.empty()) throw input_error("a sweep needs both --param and --range a:b:n");
    sweep_values v{resolve_axis(c, s.param, parse_range(s.range, "--range"), "--param"), {}};
    v.name = c.info().parameters[static_cast<std::size_t>(v.parameter)].name;
    const model& m = c.model;
    warn_validity(c, {m.with_parameter(v.parameter, v.values.front()), m.with_parameter(v.parameter, v.values.back())});
    return v;
}

// One model unit of time in seconds where the swept parameter is `value` (with --si).
double time_scale_at(const run_config& c, const sweep_values& sv, double value)
{
    return scales_at(*c.si, c.model.with_parameter(sv.parameter, value)).time;
}

// With --si: the sweep's SI quantity (si_param) and the conversion (si).
void add_si_sweep(json& summary, const run_config& c, const sweep_values& sv)
{
    if (sv.si()) summary["si_param"] = sv.si_name;
    if (c.si) summary["si"] = si_json(*c.si, c.model);
}

// points.csv of a stability sweep: the section points of every value's result (the records
// of `records`), a value at a time as the results stream.
std::vector<std::string> points_header(const std::string& param, const model_info& info)
{
    std::vector<std::string> h{param};
    append(h, state_columns(info));
    return h;
}
json points_schema(const std::string& param, const std::string& records, const model_info& info)
{
    return series_schema("section_points", records, {{param, "value"}}, state_columns(info), {});
}

void write_sweep_points(streamed_table& w, double value, const state_series& pts)
{
    std::vector<double> row(static_cast<std::size_t>(pts.dim()) + 1);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        row[0] = value;
        for (int k = 0; k < pts.dim(); ++k) row[static_cast<std::size_t>(k) + 1] = pts.x(i, k);
        w.row(row);
    }
}

// The summaries' names of the results' fields where they differ from the description: every
// command's "outcome", the run counters under "stats".
const summary_form floquet_form{
    {{"status", "outcome"}, {"protocol_stats", "stats/protocol"}, {"tangent_stats", "stats/tangent"}}};
const summary_form lyapunov_form{
    {{"status", "outcome"}, {"transient_stats", "stats/transient"}, {"stats", "stats/tangent"}}};
// A sweep's value without --out: its row of the table.
const summary_form sweep_row_form{{{"status", "outcome"}}, true};

// ---------------------------------------------------------------- floquet

int run_floquet_sweep(const floquet_args& a, const run_config& c, const floquet_options& fo)
{
    job_session session(a.sweep.jobs, c.out);
    const auto& info = c.info();
    const sweep_values sv = parse_sweep(a.sweep, c);
    std::vector<std::string> trail;  // labels.csv's SI columns after the record's
    if (sv.si()) trail.push_back(sv.si_name);
    if (c.si) trail.emplace_back("period_si");

    // The values stream in job order: rows to --out DIR, or each value's result to the
    // summary without it (with it they are in the CSV files).
    label_tally tally;
    json per_value = json::array();
    long unstable = 0;
    streamed_output stream(c);
    record_table<floquet_sweep_point> lab(stream, "labels.csv", table_context_for(info, sv.name, -1), {}, trail);
    streamed_table mu(stream, "multipliers.csv", {sv.name, "index", "re", "im", "modulus", "trivial"},
                      spectrum_schema("multipliers", "labels.csv", {{sv.name, "value"}}, info.dim(), {"modulus", "trivial"}));
    streamed_table pts(stream, "points.csv", points_header(sv.name, info), points_schema(sv.name, "labels.csv", info));
    auto each = [&](long, const floquet_sweep_point& p) {
        const auto& r = p.result;  // NaN and 0 where it has no multipliers (floquet_sweep_point)
        const bool have = r.has_multipliers();
        tally.add(r.label);
        if (have && !p.stable) ++unstable;
        const double period_si = c.si ? r.period * time_scale_at(c, sv, p.value) : std::nan("");
        std::vector<double> si;
        if (sv.si()) si.push_back(sv.si_at(c, p.value));
        if (c.si) si.push_back(period_si);
        if (!c.out) {
            json row = summary_json(p, info, sweep_row_form);
            if (!have) null_keys(row, {"impacts_per_period", "impacts_by_surface"});
            if (sv.si()) row[sv.si_name] = si.front();
            if (c.si) row["period_si"] = finite_or_null(period_si);
            per_value.push_back(std::move(row));
            return;
        }
        lab.row({}, p, si);
        for (std::size_t i = 0; i < r.multipliers.size(); ++i)
            mu.row({p.value, static_cast<double>(i), r.multipliers[i].real(), r.multipliers[i].imag(),
                    std::abs(r.multipliers[i]), i == 0 ? 1.0 : 0.0});
        write_sweep_points(pts, p.value, r.section_points);
    };
    const floquet_sweep_result res =
        floquet_sweep(c.model, {sv.parameter, sv.values, c.ic, fo}, session.options(), each);
    if (!session.complete(res.jobs)) return session.exit_code();

    const json counts = tally.counts();
    json summary = {{"command", "floquet"},
                    {"param", sv.name},
                    {"values", sv.values.size()},
                    {"label_counts", counts},
                    {"unstable", unstable},
                    {"files", {"labels.csv", "multipliers.csv", "points.csv"}},
                    {"out", out_path(c)}};
    if (!c.out) summary["points"] = per_value;
    add_si_sweep(summary, c, sv);
    std::string text = "floquet sweep of " + sv.name + " over " + std::to_string(sv.values.size()) +
                       " values: " + counts_text(counts) + "; " + std::to_string(unstable) +
                       " periodic orbit(s) with a multiplier outside the unit circle\n";
    return stream.finish(session, "floquet", "floquet_sweep", summary, text);
}

int run_floquet(const floquet_args& a)
{
    run_config c = resolve(a.common);
    floquet_options fo = a.options;
    fo.protocol = c.protocol;
    fo.tangent_integration = tangent_integration(c.protocol.flow.integration);
    validate(c.model, fo);
    if (a.sweep.wanted()) return run_floquet_sweep(a, c, fo);
    if (c.si) c.plot_options["units"] = "si";  // the orbit in metres and m/s, the period in s
    check_admissible(c);
    warn_validity(c, {c.model});
    if (c.out) fo.sample_dt = 0.01;
    const floquet_result r = floquet(c.model, c.ic, fo);
    const auto& info = c.info();

    const bool have = r.has_multipliers();
    json moduli = json::array();
    for (const auto& mu : r.multipliers) moduli.push_back(std::abs(mu));
    json summary = summary_json(r, info, floquet_form);
    if (!have)
        null_keys(summary, {"period", "impacts_per_period", "impacts_by_surface", "trivial_error", "trivial_residual",
                            "max_nontrivial_modulus", "orbit_point", "det_monodromy", "liouville_det",
                            "divergence_integral", "log_det_jumps"});
    if (r.section_returns <= 0) null_keys(summary, {"section_returns", "closure", "initial_closure"});
    summary.update({{"command", "floquet"},
                    {"moduli", moduli},
                    {"trivial_index", have ? json(0) : json(nullptr)},
                    {"stable", have ? json(r.stable()) : json(nullptr)},
                    {"impact_map", std::string(to_string(r.jump))},
                    {"tangent_rtol", fo.tangent_integration.rtol},
                    {"out", out_path(c)}});
    add_si_summary(summary, c, c.model);
    const double period_si = c.si && have ? r.period * scales_at(*c.si, c.model).time : std::nan("");
    if (c.si) summary["period_si"] = finite_or_null(period_si);
    if (c.out) {
        json result = summary;
        result["monodromy"] = have ? matrix_json(r.monodromy) : json(nullptr);
        write_run(c, "floquet", result, [&](staged_output& out) {
            csv_writer w(out.file("multipliers.csv"), {"index", "re", "im", "modulus", "trivial"});
            for (std::size_t i = 0; i < r.multipliers.size(); ++i)
                w.row({static_cast<double>(i), r.multipliers[i].real(), r.multipliers[i].imag(),
                       std::abs(r.multipliers[i]), i == 0 ? 1.0 : 0.0});
            w.close();
            const auto si = si_tables_of(c, c.model);  // the SI columns with --si
            write_states(out.file("orbit.csv"), r.orbit, info, si ? &*si : nullptr);
            write_impacts(out.file("impacts.csv"), r.impacts, c.model, si ? &*si : nullptr);
            return json{"multipliers.csv", "orbit.csv", "impacts.csv"};
        });
    }

    const std::string status(to_string(r.status));
    std::string text = r.label == status || r.status == outcome::ok ? r.label + "\n" : r.label + " (" + status + ")\n";
    if (have) {
        text += "period T = " + format_double(r.period) +
                (c.si ? " = " + format_double(period_si) + " s" : std::string()) + " (" +
                std::to_string(r.section_returns) +
                " section return(s), " + std::to_string(r.impacts_per_period) + " impact(s)), closure " +
                fixed(r.closure, 3) + " after " + std::to_string(r.newton_iterations) + " Newton step(s)\n";
        text += "multipliers (" + std::string(to_string(r.jump)) + " at impacts; trivial first):\n";
        for (std::size_t i = 0; i < r.multipliers.size(); ++i) {
            const auto mu = r.multipliers[i];
            text += "  " + fixed(mu.real(), 12) + (mu.imag() < 0 ? " - " : " + ") + fixed(std::abs(mu.imag()), 12) +
                    "i   |mu| = " + fixed(std::abs(mu), 8);
            if (i == 0) text += "   trivial, |mu - 1| = " + fixed(r.trivial_error, 3);
            text += "\n";
        }
        text += r.stable() ? "stable: every nontrivial |mu| < 1\n" : "unstable: a nontrivial |mu| >= 1\n";
    } else if (r.status == outcome::aperiodic) {
        text += "no periodic orbit within the period tolerance " + format_double(fo.period_tolerance) +
                ": no multipliers (use `vimpact lyapunov`)\n";
    }
    if (c.out) text += "output written to " + c.out->string() + "\n";
    print(c, summary, text);
    return 0;
}

// ---------------------------------------------------------------- lyapunov

int run_lyapunov_sweep(const lyapunov_args& a, const run_config& c, lyapunov_options lo)
{
    job_session session(a.sweep.jobs, c.out);
    const auto& info = c.info();
    const int dim = c.model.dim();
    const sweep_values sv = parse_sweep(a.sweep, c);
    if (c.protocol.section.type != section_choice::kind::crossing)
        throw input_error("--section " + c.section_name() + ": a lyapunov sweep records points on a section crossing (" +
                          sections_it_has(info) + ")");
    lo.record_points = c.protocol.record_points;
    lo.section = c.protocol.section.index;
    std::vector<std::string> trail;  // exponents.csv's SI columns after the record's
    if (sv.si()) trail.push_back(sv.si_name);
    if (c.si)
        for (int i = 1; i <= dim; ++i) trail.push_back("lambda" + std::to_string(i) + "_si");

    // The values stream in job order: rows to --out DIR, or each value's result to the
    // summary without it (with it they are in the CSV files).
    json per_value = json::array();
    long positive = 0, unsettled = 0;
    streamed_output stream(c);
    record_table<lyapunov_sweep_point> w(stream, "exponents.csv", table_context_for(info, sv.name, -1), {}, trail);
    streamed_table pts(stream, "points.csv", points_header(sv.name, info), points_schema(sv.name, "exponents.csv", info));
    auto each = [&](long, const lyapunov_sweep_point& p) {
        const auto& r = p.result;  // NaN exponents where it has none (lyapunov_sweep_point)
        const bool have = r.has_exponents();
        if (p.positive) ++positive;
        if (have && !r.settled) ++unsettled;
        // Exponents per second with --si: per unit of model time over its length in seconds.
        const double per_second = c.si ? 1.0 / time_scale_at(c, sv, p.value) : std::nan("");
        const auto exponent = [&](int i) { return i < r.exponents.size() ? r.exponents[i] : std::nan(""); };
        std::vector<double> si;
        if (sv.si()) si.push_back(sv.si_at(c, p.value));
        if (c.si)
            for (int i = 0; i < dim; ++i) si.push_back(exponent(i) * per_second);
        if (!c.out) {
            json row = summary_json(p, info, sweep_row_form);
            row["lle"] = finite_or_null(exponent(0));
            if (!have) row["exponents"] = json::array();
            if (sv.si()) row[sv.si_name] = si.front();
            if (c.si) row["lle_si"] = finite_or_null(exponent(0) * per_second);
            per_value.push_back(std::move(row));
            return;
        }
        w.row({}, p, si);
        write_sweep_points(pts, p.value, r.section_points);
    };
    const lyapunov_sweep_result res =
        lyapunov_sweep(c.model, {sv.parameter, sv.values, c.ic, lo}, session.options(), each);
    if (!session.complete(res.jobs)) return session.exit_code();

    json summary = {{"command", "lyapunov"},
                    {"param", sv.name},
                    {"values", sv.values.size()},
                    {"tdm", std::string(to_string(lo.tdm))},
                    {"positive", positive},
                    {"unsettled", unsettled},
                    {"files", {"exponents.csv", "points.csv"}},
                    {"out", out_path(c)}};
    if (!c.out) summary["points"] = per_value;
    add_si_sweep(summary, c, sv);
    std::string text = "lyapunov sweep of " + sv.name + " over " + std::to_string(sv.values.size()) + " values (" +
                       std::string(to_string(lo.tdm)) + "): largest exponent above 3 standard errors at " +
                       std::to_string(positive) + "\n";
    if (unsettled > 0)
        text += "warning: the largest exponent drifts between the halves of the averaging at " +
                std::to_string(unsettled) + " value(s) (column settled = 0): lengthen --transient or --impacts\n";
    return stream.finish(session, "lyapunov", "lyapunov_sweep", summary, text);
}

int run_lyapunov(const CLI::App& app, const lyapunov_args& a)
{
    const bool sweep = a.sweep.wanted();
    if (!sweep && app.get_option("--section")->count() > 0)
        throw input_error("--section is used by lyapunov only in a sweep (--param, --range), for the bifurcation diagram");
    if (!sweep && app.get_option("--record")->count() > 0)
        throw input_error("--record is used by lyapunov only in a sweep (--param, --range), for the bifurcation diagram");
    run_config c = resolve(a.common);
    lyapunov_options lo = a.options;
    check_options(lo);  // before a sweep writes anything
    lo.transient_impacts = c.protocol.transient_impacts;
    lo.quiet_time = c.protocol.quiet_time;
    lo.flow = c.protocol.flow;
    lo.method = c.protocol.method;
    if (sweep) return run_lyapunov_sweep(a, c, lo);
    if (c.si) c.plot_options["units"] = "si";  // the exponents per second over time in s
    check_admissible(c);
    warn_validity(c, {c.model});
    const lyapunov_result r = lyapunov(c.model, c.ic, lo);
    const auto& info = c.info();

    const bool have = r.has_exponents();
    const double rate = r.time > 0.0 ? static_cast<double>(r.impacts) / r.time : 0.0;
    json summary = summary_json(r, info, lyapunov_form);
    if (!have) {
        summary["exponents"] = json::array();
        null_keys(summary, {"lle_standard_error", "sum_rule", "divergence_average", "jump_log_det_rate"});
    }
    summary.update({{"command", "lyapunov"},
                    {"tdm", std::string(to_string(r.tdm))},
                    {"lle", have ? finite_or_null(r.exponents[0]) : json(nullptr)},
                    {"positive", r.positive_largest_exponent()},
                    {"sum", have ? finite_or_null(r.exponents.sum()) : json(nullptr)},
                    {"impact_rate", rate},
                    {"r0", lo.r0},
                    {"t0", lo.t0},
                    {"warmup", lo.warmup_intervals},
                    {"out", out_path(c)}});
    // With --si: exponents and the impact rate per second, times in seconds.
    const double second = c.si ? scales_at(*c.si, c.model).time : std::nan("");
    add_si_summary(summary, c, c.model);
    if (c.si) {
        json e = json::array();
        if (have)
            for (Eigen::Index i = 0; i < r.exponents.size(); ++i) e.push_back(finite_or_null(r.exponents[i] / second));
        summary["exponents_si"] = e;
        summary["lle_si"] = have ? finite_or_null(r.exponents[0] / second) : json(nullptr);
        summary["lle_standard_error_si"] = have ? finite_or_null(r.lle_standard_error / second) : json(nullptr);
        summary["impact_rate_si"] = rate / second;
        summary["time_si"] = r.time * second;
    }
    if (c.out)
        write_run(c, "lyapunov", summary, [&](staged_output& out) {
            // Running estimates per QR column (the columns converge to the descending order).
            std::vector<std::string> h{"t"};
            for (int i = 1; i <= c.model.dim(); ++i) h.push_back("lambda" + std::to_string(i));
            if (c.si) {
                h.emplace_back("t_si");
                for (int i = 1; i <= c.model.dim(); ++i)
                    h.push_back("lambda" + std::to_string(i) + "_si");
            }
            csv_writer w(out.file("convergence.csv"), h);
            const auto running = r.running_exponents();
            for (std::size_t k = 0; k < running.size(); ++k) {
                std::vector<double> row{r.history_t[k]};
                row.insert(row.end(), running[k].begin(), running[k].end());
                if (c.si) {
                    row.push_back(r.history_t[k] * second);
                    for (const double e : running[k]) row.push_back(e / second);
                }
                w.row(row);
            }
            w.close();
            return json{"convergence.csv"};
        });

    std::string text = "outcome " + std::string(to_string(r.status)) + ", mapping at impacts: " +
                       std::string(to_string(r.tdm)) + "\n";
    if (have) {
        text += "exponents:";
        for (Eigen::Index i = 0; i < r.exponents.size(); ++i) text += " " + fixed(r.exponents[i], 6);
        text += "\nlargest " + fixed(r.exponents[0], 6) + " +- " + fixed(r.lle_standard_error, 2) +
                " (standard error of 8 block means)\n";
        if (c.si)
            text += "in SI: largest " + fixed(r.exponents[0] / second, 6) + " +- " +
                    fixed(r.lle_standard_error / second, 2) + " per second\n";
        if (!r.settled)
            text += "warning: not settled: the largest exponent differs between the halves of the averaging by more "
                    "than 4 standard errors; lengthen --transient or --impacts\n";
        text += "averaged over " + std::to_string(r.impacts) + " impacts" +
                (c.info().switches.empty() ? "" : " and " + std::to_string(r.stats.switchings) + " crossings of switches") +
                ", t = " + fixed(r.time, 8) + " (" +
                std::to_string(r.intervals) + " intervals of t0 = " + fixed(lo.t0, 6) + ")\n";
        if (std::isfinite(r.sum_rule))
            text += "sum " + fixed(r.exponents.sum(), 10) + ", <div F> + rate ln|det S| = " + fixed(r.sum_rule, 10) + "\n";
        if (r.misses > 0)
            text += std::to_string(r.misses) + (r.tdm == lyapunov_tdm::trajectory
                                                    ? " perturbed orbit-intervals with a different impact count\n"
                                                    : " deviations missing a surface to second order\n");
    }
    if (c.out) text += "output written to " + c.out->string() + "\n";
    print(c, summary, text);
    return 0;
}

void add_sweep_options(CLI::App& app, sweep_request& s, const std::string& what)
{
    app.add_option("--param", s.param, "Sweep: the parameter to vary (with --si also U [m/s] or gap [m]); " + what);
    app.add_option("--range", s.range, "Sweep: values a:b:n (from a to b, n points; fixed starts from --ic)");
    add_job_options(app, s.jobs);
}

}  // namespace

cli_command add_floquet_command(CLI::App& app)
{
    auto a = std::make_shared<floquet_args>();
    auto* f = app.add_subcommand("floquet",
                                 "Floquet multipliers: find the periodic orbit after the transient, refine it by "
                                 "Newton shooting, and diagonalise its monodromy (saltation at impacts)");
    add_common_options(*f, a->common);
    add_si_option(*f, a->common);
    add_declared_options(*f, a->options);
    add_sweep_options(*f, a->sweep, "multipliers against it (Figures 14, 15)");
    return {f, [a] { return run_floquet(*a); }};
}

cli_command add_lyapunov_command(CLI::App& app)
{
    auto a = std::make_shared<lyapunov_args>();
    auto* l = app.add_subcommand("lyapunov",
                                 "Lyapunov spectrum by the paper's Algorithm 2: deviation vectors re-orthonormalised "
                                 "every t0, mapped through impacts by --tdm");
    add_common_options(*l, a->common);
    add_si_option(*l, a->common);
    add_declared_options(*l, a->options);
    add_sweep_options(*l, a->sweep, "exponents against it (Figures 16, 17; --record section points per value)");
    return {l, [a, l] { return run_lyapunov(*l, *a); }};
}

}  // namespace vimpact::cli
