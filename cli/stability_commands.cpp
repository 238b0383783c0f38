// The stability commands: floquet and lyapunov (docs/stability.md).
#include "stability_commands.hpp"

#include <cmath>
#include <complex>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <string>

#include "job_runner.hpp"
#include "output.hpp"
#include "vimpact/analysis/job_points.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/io/csv_writer.hpp"
#include "vimpact/stability/floquet.hpp"
#include "vimpact/stability/lyapunov.hpp"

namespace vimpact::cli {
namespace {

// --param P --range a:b:n turns either command into a sweep through the shared job loop
// (threads, shards, resume: cli/job_runner.hpp), one analysis per value, fixed starts from
// --ic as the paper did: Figures 14-17 with the bifurcation diagram underneath.
struct sweep_request {
    std::string param;
    std::string range;
    job_args jobs;
    [[nodiscard]] bool wanted() const { return !param.empty() || !range.empty(); }
};

struct floquet_args {
    common_args common;
    sweep_request sweep;
    double tol = 1e-8;
    double newton_tol = 1e-11;
    int newton_iterations = 20;
    std::string impact_map = "saltation";
};

struct lyapunov_args {
    common_args common;
    sweep_request sweep;
    std::string tdm = "saltation";
    double r0 = 1e-4;
    double t0 = std::numbers::pi;
    long impacts = 800;
    double time = 0.0;
    long warmup = 16;
};

std::string fixed(double v, int digits)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

impact_tangent parse_impact_map(const std::string& s)
{
    if (s == "saltation") return impact_tangent::saltation;
    if (s == "reset-jacobian") return impact_tangent::reset_jacobian;
    if (s == "identity") return impact_tangent::identity;
    throw input_error("--impact-map '" + s + "' is not one of saltation, reset-jacobian, identity");
}

// The shooting and the monodromy need a map accurate to better than the 1e-11 closure.
integrator_options tangent_integration(const run_config& c)
{
    integrator_options io;
    io.rtol = std::min(c.rtol, 1e-12);
    io.atol = std::min(c.atol, 1e-12);
    return io;
}

json vec_json(const vec<4>& x) { return {x[0], x[1], x[2], x[3]}; }

json matrix_json(const mat<4>& m)
{
    json rows = json::array();
    for (int i = 0; i < 4; ++i) rows.push_back({m(i, 0), m(i, 1), m(i, 2), m(i, 3)});
    return rows;
}

// "a:b:n" -> n values from a to b (the sweep command's convention, analysis/sweep.hpp).
std::vector<double> sweep_values(const sweep_request& s)
{
    if (s.param.empty() || s.range.empty()) throw input_error("a sweep needs both --param and --range a:b:n");
    check_parameter_name(wake_impact(), s.param, "--param");
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (;;) {
        const auto colon = s.range.find(':', start);
        parts.push_back(s.range.substr(start, colon == std::string::npos ? std::string::npos : colon - start));
        if (colon == std::string::npos) break;
        start = colon + 1;
    }
    if (parts.size() != 3) throw input_error("--range '" + s.range + "' must be a:b:n (from a to b, n points)");
    const double a = parse_number(parts[0], "--range start");
    const double b = parse_number(parts[1], "--range end");
    const double n = parse_number(parts[2], "--range points");
    if (n < 1 || n != std::floor(n) || n > 1e7)
        throw input_error("--range '" + s.range + "': n must be an integer in [1, 1e7]");
    return grid_values(a, b, static_cast<long>(n));
}

json points_json(const std::vector<timed_state<4>>& pts)
{
    json a = json::array();
    for (const auto& p : pts) a.push_back(vec_json(p.x));
    return a;
}

void write_sweep_points(const std::filesystem::path& path, const std::string& param, const std::vector<json>& recs)
{
    csv_writer w(path, {param, "y", "ydot", "x", "xdot"});
    for (const auto& r : recs)
        for (const auto& p : r["points"])
            w.row({r["value"].get<double>(), p[0].get<double>(), p[1].get<double>(), p[2].get<double>(), p[3].get<double>()});
    w.close();
}

double number_or_nan(const json& j) { return j.is_number() ? j.get<double>() : std::nan(""); }

// Runs the jobs of a stability sweep and writes DIR (kind `kind`) when all are done.
int run_stability_sweep(const run_config& c, const sweep_request& s, const std::vector<double>& values,
                        json spec, const char* kind, const std::function<json(const wake_impact&)>& analyse,
                        const std::function<void(const std::vector<json>&, json&, std::string&, staged_output*)>& report)
{
    const wake_impact base = c.model();
    const sweep_plan plan = make_sweep_plan(static_cast<long>(values.size()), "fixed", "up", input_spelling::cli);
    check_sweep_starts(base, s.param, values, c.ic, plan, input_spelling::cli);
    job_command cmd;
    spec["config"] = c.to_json();
    spec["param"] = s.param;
    spec["range"] = s.range;
    cmd.spec = std::move(spec);
    cmd.schedule = plan.schedule();
    cmd.out = c.out ? std::optional<std::filesystem::path>(*c.out) : std::nullopt;
    cmd.run = [&](long job, const json*) {
        const double v = values[static_cast<std::size_t>(job)];
        json rec = analyse(base.with(s.param, v));
        rec["value"] = v;
        return rec;
    };
    json summary;
    std::string text;
    cmd.finish = [&](const std::vector<json>& recs, const std::filesystem::path* dir) {
        if (!dir) {
            report(recs, summary, text, nullptr);
            return;
        }
        staged_output out(*dir);
        report(recs, summary, text, &out);
        json record = record_header(kind, c);
        record["result"] = summary;
        record["files"] = summary["files"];
        finish_output(out, kind, c, record);
        text += "output written to " + *c.out + "\n";
    };
    const auto res = run_job_command(cmd, s.jobs);
    if (res.complete) print(c, summary, text);
    return res.exit_code;
}


// Figures 14 and 15: the multipliers at every value, with the section points of each run.
int run_floquet_sweep(const floquet_args& a, const run_config& c, const floquet_options& fo)
{
    const auto values = sweep_values(a.sweep);
    const std::string& param = a.sweep.param;
    json spec = {{"command", "floquet"},
                 {"tol", a.tol},
                 {"newton_tol", a.newton_tol},
                 {"newton_iterations", a.newton_iterations},
                 {"impact_map", a.impact_map}};
    auto analyse = [&](const wake_impact& m) {
        const auto r = with_method(c.method, [&]<template <int> class M>() { return floquet_analysis<M>(m, c.ic, fo); });
        const bool have = r.status == floquet_status::ok || r.status == floquet_status::not_converged;
        json mults = json::array();
        for (const auto& mu : r.multipliers) mults.push_back({mu.real(), mu.imag()});
        std::string outcome_text = to_string(r.status);
        if (r.status == floquet_status::flow_failed) outcome_text += " (" + r.flow_outcome + ")";
        return json{{"label", r.label},
                    {"outcome", outcome_text},
                    {"period", have ? json(r.period) : json(nullptr)},
                    {"impacts_per_period", have ? json(r.impacts_per_period) : json(nullptr)},
                    {"multipliers", mults},
                    {"trivial_error", have ? finite_or_null(r.trivial_error) : json(nullptr)},
                    {"max_nontrivial_modulus", have ? finite_or_null(r.max_nontrivial_modulus) : json(nullptr)},
                    {"closure", r.section_returns > 0 ? finite_or_null(r.closure) : json(nullptr)},
                    {"points", points_json(r.section_points)}};
    };
    auto report = [&](const std::vector<json>& recs, json& summary, std::string& text, staged_output* out) {
        std::map<std::string, long> counts;
        json per_value = json::array();
        long unstable = 0;
        for (const auto& r : recs) {
            ++counts[r["label"].get<std::string>()];
            per_value.push_back({{"value", r["value"]}, {"label", r["label"]}, {"outcome", r["outcome"]},
                                 {"period", r["period"]}, {"impacts_per_period", r["impacts_per_period"]},
                                 {"multipliers", r["multipliers"]}, {"trivial_error", r["trivial_error"]}});
            if (r["max_nontrivial_modulus"].is_number() && r["max_nontrivial_modulus"].get<double>() >= 1.0) ++unstable;
        }
        json label_counts = json::object();
        std::string counts_text;
        for (const auto& [k, v] : counts) {
            label_counts[k] = v;
            counts_text += (counts_text.empty() ? "" : ", ") + k + " " + std::to_string(v);
        }
        summary = {{"command", "floquet"}, {"param", param}, {"values", recs.size()},
                   {"label_counts", label_counts}, {"unstable", unstable}, {"points", per_value},
                   {"files", {"labels.csv", "multipliers.csv", "points.csv", "run.json"}},
                   {"out", c.out ? json(*c.out) : json(nullptr)}};
        text = "floquet sweep of " + param + " over " + std::to_string(recs.size()) + " values: " + counts_text +
               "; " + std::to_string(unstable) + " periodic orbit(s) with a multiplier outside the unit circle\n";
        if (!out) return;
        csv_writer lab(out->file("labels.csv"),
                       {param, "label", "period", "impacts", "trivial_error", "max_nontrivial_modulus", "closure", "outcome"});
        csv_writer mu(out->file("multipliers.csv"), {param, "index", "re", "im", "modulus", "trivial"});
        for (const auto& r : recs) {
            const double v = r["value"].get<double>();
            lab.text_row({format_double(v), r["label"].get<std::string>(), format_double(number_or_nan(r["period"])),
                          format_double(number_or_nan(r["impacts_per_period"])), format_double(number_or_nan(r["trivial_error"])),
                          format_double(number_or_nan(r["max_nontrivial_modulus"])), format_double(number_or_nan(r["closure"])),
                          r["outcome"].get<std::string>()});
            const auto& ms = r["multipliers"];
            for (std::size_t i = 0; i < ms.size(); ++i) {
                const double re = ms[i][0].get<double>(), im = ms[i][1].get<double>();
                mu.row({v, static_cast<double>(i), re, im, std::hypot(re, im), i == 0 ? 1.0 : 0.0});
            }
        }
        lab.close();
        mu.close();
        write_sweep_points(out->file("points.csv"), param, recs);
    };
    return run_stability_sweep(c, a.sweep, values, std::move(spec), "floquet_sweep", analyse, report);
}

// Figures 16 and 17: the exponents at every value, with section points of the same orbits.
int run_lyapunov_sweep(const lyapunov_args& a, const run_config& c, lyapunov_options lo)
{
    const auto values = sweep_values(a.sweep);
    const std::string& param = a.sweep.param;
    lo.record_points = c.record;
    json spec = {{"command", "lyapunov"}, {"tdm", a.tdm}, {"r0", a.r0}, {"t0", a.t0},
                 {"impacts", a.impacts}, {"time", a.time}, {"warmup", a.warmup}};
    auto analyse = [&](const wake_impact& m) {
        const auto r = with_method(c.method, [&]<template <int> class M>() { return lyapunov_spectrum<M>(m, c.ic, lo); });
        const bool have = r.status == lyapunov_status::ok || r.status == lyapunov_status::time_limit;
        json exps = json::array();
        if (have)
            for (int i = 0; i < 4; ++i) exps.push_back(r.exponents[i]);
        std::string outcome_text = to_string(r.status);
        if (r.status == lyapunov_status::flow_failed) outcome_text += " (" + r.flow_outcome + ")";
        return json{{"outcome", outcome_text},
                    {"exponents", exps},
                    {"lle", have ? finite_or_null(r.exponents[0]) : json(nullptr)},
                    {"lle_standard_error", have ? finite_or_null(r.lle_standard_error) : json(nullptr)},
                    {"impacts", r.impacts},
                    {"time", r.time},
                    {"misses", r.misses},
                    {"points", points_json(r.section_points)}};
    };
    auto report = [&](const std::vector<json>& recs, json& summary, std::string& text, staged_output* out) {
        json per_value = json::array();
        long positive = 0;
        for (const auto& r : recs) {
            per_value.push_back({{"value", r["value"]}, {"outcome", r["outcome"]}, {"lle", r["lle"]},
                                 {"lle_standard_error", r["lle_standard_error"]}, {"exponents", r["exponents"]}});
            if (r["lle"].is_number() && r["lle_standard_error"].is_number() &&
                r["lle"].get<double>() > 3.0 * r["lle_standard_error"].get<double>())
                ++positive;
        }
        summary = {{"command", "lyapunov"}, {"param", param}, {"values", recs.size()}, {"tdm", a.tdm},
                   {"positive", positive}, {"points", per_value},
                   {"files", {"exponents.csv", "points.csv", "run.json"}},
                   {"out", c.out ? json(*c.out) : json(nullptr)}};
        text = "lyapunov sweep of " + param + " over " + std::to_string(recs.size()) + " values (" + a.tdm +
               "): largest exponent above 3 standard errors at " + std::to_string(positive) + "\n";
        if (!out) return;
        csv_writer w(out->file("exponents.csv"), {param, "lambda1", "lambda2", "lambda3", "lambda4", "lle_standard_error",
                                                  "impacts", "time", "misses", "outcome"});
        for (const auto& r : recs) {
            std::vector<std::string> row{format_double(r["value"].get<double>())};
            for (int i = 0; i < 4; ++i)
                row.push_back(format_double(r["exponents"].size() == 4 ? r["exponents"][i].get<double>() : std::nan("")));
            row.push_back(format_double(number_or_nan(r["lle_standard_error"])));
            row.push_back(std::to_string(r["impacts"].get<long>()));
            row.push_back(format_double(r["time"].get<double>()));
            row.push_back(std::to_string(r["misses"].get<long>()));
            row.push_back(r["outcome"].get<std::string>());
            w.text_row(row);
        }
        w.close();
        write_sweep_points(out->file("points.csv"), param, recs);
    };
    return run_stability_sweep(c, a.sweep, values, std::move(spec), "lyapunov_sweep", analyse, report);
}

int run_floquet(const floquet_args& a)
{
    const run_config c = resolve(a.common);
    if (c.section != section_choice::maxima)
        throw input_error("--section " + std::string(to_string(c.section)) +
                          ": floquet uses the section maxima (v = 0, v decreasing); valid: maxima");
    if (c.record < 2) throw input_error("--record must be >= 2 section points for floquet (got " + std::to_string(c.record) + ")");
    if (!(a.tol > 0.0) || !std::isfinite(a.tol))
        throw input_error("--tol must be > 0 (got " + format_double(a.tol) + ")");
    if (!(a.newton_tol > 0.0) || !std::isfinite(a.newton_tol))
        throw input_error("--newton-tol must be > 0 (got " + format_double(a.newton_tol) + ")");
    if (a.newton_iterations < 0 || a.newton_iterations > 1000)
        throw input_error("--newton-iterations must be in [0, 1000] (got " + std::to_string(a.newton_iterations) + ")");
    floquet_options fo;
    fo.protocol = c.protocol();
    fo.period_tolerance = a.tol;
    fo.shooting.tolerance = a.newton_tol;
    fo.shooting.max_iterations = a.newton_iterations;
    fo.shooting.map.flow.integration = tangent_integration(c);
    fo.jump = parse_impact_map(a.impact_map);
    if (a.sweep.wanted()) return run_floquet_sweep(a, c, fo);
    std::optional<staged_output> out;
    if (c.out) {
        out.emplace(*c.out);
        fo.sample_dt = 0.01;
    }
    const wake_impact model = c.model();
    const auto r = with_method(c.method, [&]<template <int> class M>() {
        return floquet_analysis<M>(model, c.ic, fo);
    });

    const bool have = r.status == floquet_status::ok || r.status == floquet_status::not_converged;
    json mults = json::array();
    json moduli = json::array();
    for (const auto& mu : r.multipliers) {
        mults.push_back({mu.real(), mu.imag()});
        moduli.push_back(std::abs(mu));
    }
    std::string outcome_text = to_string(r.status);
    if (r.status == floquet_status::flow_failed) outcome_text += " (" + r.flow_outcome + ")";
    json summary = {{"command", "floquet"},
                    {"label", r.label},
                    {"outcome", outcome_text},
                    {"period", have ? json(r.period) : json(nullptr)},
                    {"section_returns", r.section_returns > 0 ? json(r.section_returns) : json(nullptr)},
                    {"impacts_per_period", have ? json(r.impacts_per_period) : json(nullptr)},
                    {"multipliers", mults},
                    {"moduli", moduli},
                    {"trivial_index", have ? json(0) : json(nullptr)},
                    {"trivial_error", have ? finite_or_null(r.trivial_error) : json(nullptr)},
                    {"trivial_residual", have ? finite_or_null(r.trivial_residual) : json(nullptr)},
                    {"max_nontrivial_modulus", have ? finite_or_null(r.max_nontrivial_modulus) : json(nullptr)},
                    {"stable", have ? json(r.stable()) : json(nullptr)},
                    {"closure", r.section_returns > 0 ? finite_or_null(r.closure) : json(nullptr)},
                    {"initial_closure", r.section_returns > 0 ? finite_or_null(r.initial_closure) : json(nullptr)},
                    {"newton_iterations", r.newton_iterations},
                    {"orbit_point", have ? vec_json(r.orbit_point) : json(nullptr)},
                    {"det_monodromy", have ? finite_or_null(r.det_monodromy) : json(nullptr)},
                    {"liouville_det", have ? finite_or_null(r.liouville_det) : json(nullptr)},
                    {"impact_map", to_string(r.jump)},
                    {"tangent_rtol", fo.shooting.map.flow.integration.rtol},
                    {"stats", {{"protocol", stats_json(r.protocol_stats)}, {"tangent", stats_json(r.tangent_stats)}}},
                    {"out", c.out ? json(*c.out) : json(nullptr)}};
    if (out) {
        json record = record_header("floquet", c);
        record["result"] = summary;
        record["result"]["monodromy"] = have ? matrix_json(r.monodromy) : json(nullptr);
        record["files"] = {"multipliers.csv", "orbit.csv", "impacts.csv", "run.json"};
        csv_writer w(out->file("multipliers.csv"), {"index", "re", "im", "modulus", "trivial"});
        for (std::size_t i = 0; i < r.multipliers.size(); ++i)
            w.row({static_cast<double>(i), r.multipliers[i].real(), r.multipliers[i].imag(),
                   std::abs(r.multipliers[i]), i == 0 ? 1.0 : 0.0});
        w.close();
        write_points(out->file("orbit.csv"), r.orbit);
        write_impacts(out->file("impacts.csv"), r.impacts);
        finish_output(*out, "floquet", c, record);
    }

    std::string text = r.label == outcome_text || r.status == floquet_status::ok
                           ? r.label + "\n"
                           : r.label + " (" + outcome_text + ")\n";
    if (have) {
        text += "period T = " + format_double(r.period) + " (" + std::to_string(r.section_returns) +
                (r.section_returns == 1 ? " maximum, " : " maxima, ") + std::to_string(r.impacts_per_period) +
                " impact(s)), closure " +
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
    } else if (r.status == floquet_status::aperiodic) {
        text += "no periodic orbit within the period tolerance " + format_double(a.tol) +
                ": no multipliers (use `vimpact lyapunov`)\n";
    }
    if (c.out) text += "output written to " + *c.out + "\n";
    print(c, summary, text);
    return 0;
}

int run_lyapunov(const CLI::App& app, const lyapunov_args& a)
{
    if (app.get_option("--section")->count() > 0)
        throw input_error("--section is not used by lyapunov (a sweep records the maxima, the paper's Sigma)");
    if (!a.sweep.wanted() && app.get_option("--record")->count() > 0)
        throw input_error("--record is used by lyapunov only in a sweep (--param, --range), for the bifurcation diagram");
    const run_config c = resolve(a.common);
    lyapunov_options lo;
    lo.tdm = parse_lyapunov_tdm(a.tdm);
    if (!(a.r0 > 0.0 && a.r0 < 1.0) || !std::isfinite(a.r0))
        throw input_error("--r0 = " + format_double(a.r0) + " is outside its valid range (0, 1)");
    if (!(a.t0 > 0.0) || !std::isfinite(a.t0))
        throw input_error("--t0 = " + format_double(a.t0) + " is outside its valid range (0, inf)");
    if (a.impacts < 1) throw input_error("--impacts must be >= 1 (got " + std::to_string(a.impacts) + ")");
    if (!(a.time >= 0.0) || !std::isfinite(a.time))
        throw input_error("--time must be >= 0 (got " + format_double(a.time) + "; 0: average over --impacts)");
    if (a.warmup < 0) throw input_error("--warmup must be >= 0 intervals (got " + std::to_string(a.warmup) + ")");
    lo.r0 = a.r0;
    lo.t0 = a.t0;
    lo.impacts = a.impacts;
    lo.time = a.time;
    lo.warmup_intervals = a.warmup;
    lo.transient_impacts = c.transient;
    lo.flow = c.protocol().flow;
    if (a.sweep.wanted()) return run_lyapunov_sweep(a, c, lo);
    std::optional<staged_output> out;
    if (c.out) out.emplace(*c.out);
    const wake_impact model = c.model();
    const auto r = with_method(c.method, [&]<template <int> class M>() {
        return lyapunov_spectrum<M>(model, c.ic, lo);
    });

    const bool have = r.status == lyapunov_status::ok || r.status == lyapunov_status::time_limit;
    json exps = json::array();
    if (have)
        for (int i = 0; i < 4; ++i) exps.push_back(r.exponents[i]);
    std::string outcome_text = to_string(r.status);
    if (r.status == lyapunov_status::flow_failed) outcome_text += " (" + r.flow_outcome + ")";
    const double rate = r.time > 0.0 ? static_cast<double>(r.impacts) / r.time : 0.0;
    json summary = {{"command", "lyapunov"},
                    {"outcome", outcome_text},
                    {"tdm", to_string(r.tdm)},
                    {"exponents", exps},
                    {"lle", have ? finite_or_null(r.exponents[0]) : json(nullptr)},
                    {"lle_standard_error", have ? finite_or_null(r.lle_standard_error) : json(nullptr)},
                    {"sum", have ? finite_or_null(r.exponents.sum()) : json(nullptr)},
                    {"sum_rule", have ? finite_or_null(r.sum_rule) : json(nullptr)},
                    {"divergence_average", have ? finite_or_null(r.divergence_average) : json(nullptr)},
                    {"impact_rate", rate},
                    {"impacts", r.impacts},
                    {"time", r.time},
                    {"t_start", r.t_start},
                    {"intervals", r.intervals},
                    {"misses", r.misses},
                    {"impacting", r.impacting},
                    {"r0", a.r0},
                    {"t0", a.t0},
                    {"warmup", a.warmup},
                    {"stats", {{"transient", stats_json(r.transient_stats)}, {"tangent", stats_json(r.stats)}}},
                    {"out", c.out ? json(*c.out) : json(nullptr)}};
    if (out) {
        json record = record_header("lyapunov", c);
        record["result"] = summary;
        record["files"] = {"convergence.csv", "run.json"};
        // Running estimates per QR column (the columns converge to the descending order).
        csv_writer w(out->file("convergence.csv"), {"t", "lambda1", "lambda2", "lambda3", "lambda4"});
        vec<4> sum = vec<4>::Zero();
        for (const auto& s : r.history) {
            sum += s.growth;
            const double elapsed = s.t - r.t_start;
            w.row({s.t, sum[0] / elapsed, sum[1] / elapsed, sum[2] / elapsed, sum[3] / elapsed});
        }
        w.close();
        finish_output(*out, "lyapunov", c, record);
    }

    std::string text = "outcome " + outcome_text + ", mapping at impacts: " + to_string(r.tdm) + "\n";
    if (have) {
        text += "exponents:";
        for (int i = 0; i < 4; ++i) text += " " + fixed(r.exponents[i], 6);
        text += "\nlargest " + fixed(r.exponents[0], 6) + " +- " + fixed(r.lle_standard_error, 2) +
                " (standard error of 8 block means)\n";
        text += "averaged over " + std::to_string(r.impacts) + " impacts, t = " + fixed(r.time, 8) + " (" +
                std::to_string(r.intervals) + " intervals of t0 = " + fixed(a.t0, 6) + ")\n";
        if (std::isfinite(r.sum_rule))
            text += "sum " + fixed(r.exponents.sum(), 10) + ", <div F> + rate ln|det S| = " + fixed(r.sum_rule, 10) + "\n";
        if (r.misses > 0)
            text += std::to_string(r.misses) +
                    (r.tdm == lyapunov_tdm::trajectory ? " perturbed orbit-intervals with a different impact count\n"
                                                       : " deviations missing the barrier to second order\n");
    }
    if (c.out) text += "output written to " + *c.out + "\n";
    print(c, summary, text);
    return 0;
}

void add_sweep_options(CLI::App& app, sweep_request& s, const std::string& what)
{
    app.add_option("--param", s.param, "Sweep: the parameter to vary (Ur, sigma, r, ...); " + what);
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
    f->add_option("--tol", a->tol, "Period tolerance for the label (default 1e-8)");
    f->add_option("--newton-tol", a->newton_tol, "Closure |P^k(z) - z| to reach by Newton shooting (default 1e-11)");
    f->add_option("--newton-iterations", a->newton_iterations, "Newton steps allowed (default 20)");
    f->add_option("--impact-map", a->impact_map,
                  "Tangent jump at impacts: saltation (default; correct), reset-jacobian or identity "
                  "(both wrong, to show why saltation is needed)");
    add_sweep_options(*f, a->sweep, "multipliers (Figures 14, 15)");
    return {f, [a] { return run_floquet(*a); }};
}

cli_command add_lyapunov_command(CLI::App& app)
{
    auto a = std::make_shared<lyapunov_args>();
    auto* l = app.add_subcommand("lyapunov",
                                 "Lyapunov spectrum by the paper's Algorithm 2: deviation vectors re-orthonormalised "
                                 "every t0, mapped through impacts by --tdm");
    add_common_options(*l, a->common);
    l->add_option("--tdm", a->tdm,
                  "Mapping at impacts: saltation (default; linear), second-order (SPEC 4, finite deviations) "
                  "or trajectory (two-trajectory method)");
    l->add_option("--r0", a->r0, "Size of the deviation vectors (default 1e-4)");
    l->add_option("--t0", a->t0, "Re-orthonormalisation interval (default pi)");
    l->add_option("--impacts", a->impacts, "Average over this many impacts after the warm-up (default 800)");
    l->add_option("--time", a->time, "Average over this much time instead of --impacts (default 0: use --impacts)");
    l->add_option("--warmup", a->warmup, "Intervals of t0 not counted while the vectors align (default 16)");
    add_sweep_options(*l, a->sweep, "exponents (Figures 16, 17; --record maxima per value for the diagram)");
    return {l, [a, l] { return run_lyapunov(*l, *a); }};
}

}  // namespace vimpact::cli
