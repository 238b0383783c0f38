// The stability commands: floquet and lyapunov (docs/stability.md).
#include "stability_commands.hpp"

#include <cmath>
#include <complex>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>
#include <string>

#include "output.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/io/csv_writer.hpp"
#include "vimpact/stability/floquet.hpp"
#include "vimpact/stability/lyapunov.hpp"

namespace vimpact::cli {
namespace {

struct floquet_args {
    common_args common;
    double tol = 1e-8;
    double newton_tol = 1e-11;
    int newton_iterations = 20;
    std::string impact_map = "saltation";
};

struct lyapunov_args {
    common_args common;
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
    for (const char* name : {"--record", "--section"})
        if (app.get_option(name)->count() > 0)
            throw input_error(std::string(name) + " is not used by lyapunov (it records no section points)");
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
    return {l, [a, l] { return run_lyapunov(*l, *a); }};
}

}  // namespace vimpact::cli
