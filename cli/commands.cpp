// The single-run commands: simulate, period, grazing.
#include "commands.hpp"

#include <cmath>
#include <memory>
#include <optional>

#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/core/input_error.hpp"
#include "output.hpp"

namespace vimpact::cli {
namespace {

struct simulate_args {
    common_args common;
    double sample_dt = 0.05;
};
struct period_args {
    common_args common;
    double tol = 1e-8;
};
struct grazing_args {
    common_args common;
    double tol = 1e-11;
    double transient_time = 1000.0;
};

int run_simulate(const simulate_args& a)
{
    const run_config c = resolve(a.common);
    if (!(a.sample_dt > 0.0) || !std::isfinite(a.sample_dt))
        throw input_error("--dt must be > 0 (got " + format_double(a.sample_dt) + ")");
    std::optional<staged_output> out;
    if (c.out) out.emplace(*c.out);
    const wake_impact model = c.model();
    protocol_options po = c.protocol();
    if (out) po.sample_dt = a.sample_dt;
    const auto r = with_method(c.method, [&]<template <int> class M>() {
        return run_protocol<M>(model, c.ic, po);
    });

    json summary = {{"command", "simulate"},
                    {"outcome", std::string(to_string(r.status))},
                    {"impacts", r.stats.impacts},
                    {"impacts_recorded", r.impacts.size()},
                    {"impacting", r.impacting},
                    {"section_points", r.points.size()},
                    {"t_record_start", r.t_record_start},
                    {"t_final", r.stats.t_final},
                    {"final_state", {r.final_state[0], r.final_state[1], r.final_state[2], r.final_state[3]}},
                    {"stats", stats_json(r.stats)},
                    {"out", c.out ? json(*c.out) : json(nullptr)}};
    if (out) {
        json record = record_header("simulate", c);
        record["result"] = summary;
        record["files"] = {"timeseries.csv", "impacts.csv", "sections.csv", "run.json"};
        write_points(out->file("timeseries.csv"), r.series);
        write_impacts(out->file("impacts.csv"), r.impacts);
        write_points(out->file("sections.csv"), r.points);
        finish_output(*out, "simulate", c, record);
    }
    std::string text = "outcome " + std::string(to_string(r.status)) + ", " +
                       std::to_string(r.stats.impacts) + " impacts, " +
                       std::to_string(r.points.size()) + " section points recorded from t = " +
                       format_double(r.t_record_start) + " to t = " + format_double(r.stats.t_final) + "\n" +
                       "steps " + std::to_string(r.stats.steps) + " (rejected " +
                       std::to_string(r.stats.rejected) + "), rhs calls " + std::to_string(r.stats.rhs_calls) + "\n";
    if (c.out) text += "output written to " + *c.out + "\n";
    print(c, summary, text);
    return 0;
}

int run_period(const period_args& a)
{
    const run_config c = resolve(a.common);
    if (!(a.tol > 0.0) || !std::isfinite(a.tol))
        throw input_error("--tol must be > 0 (got " + format_double(a.tol) + ")");
    std::optional<staged_output> out;
    if (c.out) out.emplace(*c.out);
    const wake_impact model = c.model();
    const auto r = with_method(c.method, [&]<template <int> class M>() {
        return run_protocol<M>(model, c.ic, c.protocol());
    });
    const period_label lab = classify_period(model, r, a.tol);
    json distinct = json::array();
    if (lab.period > 0)
        for (int i = 0; i < lab.period; ++i) distinct.push_back(r.points[i].x[0]);
    json summary = {{"command", "period"},
                    {"label", lab.label},
                    {"period", lab.period >= 0 ? json(lab.period) : json(nullptr)},
                    {"impacts", lab.impacts_per_period},
                    {"closure", lab.closure},
                    {"tolerance", a.tol},
                    {"outcome", std::string(to_string(r.status))},
                    {"section_y", distinct},
                    {"points", r.points.size()},
                    {"stats", stats_json(r.stats)},
                    {"out", c.out ? json(*c.out) : json(nullptr)}};
    if (out) {
        json record = record_header("period", c);
        record["result"] = summary;
        record["files"] = {"sections.csv", "impacts.csv", "run.json"};
        write_points(out->file("sections.csv"), r.points);
        write_impacts(out->file("impacts.csv"), r.impacts);
        finish_output(*out, "period", c, record);
    }
    std::string text = lab.label;
    if (lab.period > 0)
        text += " (" + std::to_string(lab.impacts_per_period) + " impact(s) per period, closure " +
                format_double(lab.closure) + ")";
    text += "\n";
    if (c.out) text += "output written to " + *c.out + "\n";
    print(c, summary, text);
    return 0;
}

int run_grazing(const grazing_args& a)
{
    const run_config c = resolve(a.common);
    if (!(a.tol > 0.0) || !std::isfinite(a.tol)) throw input_error("--tol must be > 0");
    if (!(a.transient_time >= 0.0) || !std::isfinite(a.transient_time))
        throw input_error("--transient-time must be >= 0");
    std::optional<staged_output> out;
    if (c.out) out.emplace(*c.out);
    const wake_impact model = c.model();
    grazing_options go;
    go.tolerance = a.tol;
    go.transient_time = a.transient_time;
    // Grazing wants the minimum to 1e-9: never integrate looser than 1e-12 for it.
    go.integration.rtol = std::min(c.rtol, 1e-12);
    go.integration.atol = std::min(c.atol, 1e-12);
    const auto g = with_method(c.method, [&]<template <int> class M>() {
        return grazing_value<M>(model, c.ic, go);
    });
    json summary = {{"command", "grazing"},
                    {"sigma_graze", std::isfinite(g.sigma_graze) ? json(g.sigma_graze) : json(nullptr)},
                    {"converged", g.converged},
                    {"change", std::isfinite(g.change) ? json(g.change) : json(nullptr)},
                    {"t_graze", g.t_graze},
                    {"minima", g.minima},
                    {"outcome", std::string(to_string(g.status))},
                    {"stats", stats_json(g.stats)},
                    {"out", c.out ? json(*c.out) : json(nullptr)}};
    if (out) {
        json record = record_header("grazing", c);
        record["result"] = summary;
        record["files"] = {"run.json"};
        record["note"] = "grazing runs the barrier-free system; sigma is not used";
        write_json(out->file("run.json"), record);
        out->commit();
    }
    std::string text = "sigma_graze = " + format_double(g.sigma_graze) +
                       (g.converged ? "" : " (NOT converged: last change " + format_double(g.change) + ")") + "\n";
    if (c.out) text += "output written to " + *c.out + "\n";
    print(c, summary, text);
    return 0;
}

}  // namespace

cli_command add_simulate_command(CLI::App& app)
{
    auto a = std::make_shared<simulate_args>();
    auto* s = app.add_subcommand("simulate", "Run the protocol: discard a transient of impacts, record section points and the time series");
    add_common_options(*s, a->common);
    s->add_option("--dt", a->sample_dt, "Time-series sampling interval with --out (default 0.05)");
    return {s, [a] { return run_simulate(*a); }};
}

cli_command add_period_command(CLI::App& app)
{
    auto a = std::make_shared<period_args>();
    auto* p = app.add_subcommand("period", "Classify the attractor: P0, P1, P2, ..., aperiodic");
    add_common_options(*p, a->common);
    p->add_option("--tol", a->tol, "Period tolerance on the section state (default 1e-8)");
    return {p, [a] { return run_period(*a); }};
}

cli_command add_grazing_command(CLI::App& app)
{
    auto a = std::make_shared<grazing_args>();
    auto* g = app.add_subcommand("grazing", "Grazing value: minimum of y on the barrier-free attracting orbit");
    add_common_options(*g, a->common);
    g->add_option("--tol", a->tol, "Agreement of successive minima (default 1e-11)");
    g->add_option("--transient-time", a->transient_time, "Time discarded before minima count (default 1000)");
    return {g, [a] { return run_grazing(*a); }};
}

}  // namespace vimpact::cli
