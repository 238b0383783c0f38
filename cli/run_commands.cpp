// The single-run commands: simulate, period, grazing.
#include <cmath>
#include <memory>
#include <optional>

#include "commands.hpp"
#include "declared_options.hpp"
#include "interrupts.hpp"
#include "output.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/integrate/tangent_integration.hpp"
#include "vimpact/physical/si_units.hpp"

namespace vimpact::cli {
namespace {

struct simulate_args {
    common_args common;
    double sample_dt = 0.05;
};
struct period_args {
    common_args common;
    double tol = default_period_tolerance;
};
struct grazing_args {
    common_args common;
    grazing_options options;  // what it declares; the integration from the protocol's
    std::string param;
};

void check_positive(double v, const std::string& what)
{
    if (!(v > 0.0) || !std::isfinite(v)) throw input_error(what + " must be > 0 (got " + format_double(v) + ")");
}

std::string written_to(const run_config& c) { return c.out ? "output written to " + c.out->string() + "\n" : ""; }

int run_simulate(const simulate_args& a)
{
    run_config c = resolve(a.common);
    if (c.si) c.plot_options["units"] = "si";  // the picture in seconds, metres, m/s
    check_positive(a.sample_dt, "--dt");
    check_admissible(c);
    protocol_options po = c.protocol;
    if (c.out) po.sample_dt = a.sample_dt;
    warn_validity(c, {c.model});
    const simulation r = simulate(c.model, c.ic, po);

    const auto& info = c.info();
    const json stats = summary_json(r.stats, info);
    json summary = {{"command", "simulate"},
                    {"outcome", std::string(to_string(r.status))},
                    {"impacts", r.stats.impacts},
                    {"impacts_by_surface", stats["impacts_by_surface"]},
                    {"impacts_recorded", r.impacts.size()},
                    {"impacting", r.impacting},
                    {"section_points", r.points.size()},
                    {"t_record_start", r.t_record_start},
                    {"t_record_end", r.t_record_end},
                    {"t_final", r.stats.t_final},
                    {"impact_statistics", summary_json(r.statistics, info)},
                    {"final_state", vector_json(r.final_state)},
                    {"stats", stats},
                    {"out", out_path(c)}};
    // A model with switching surfaces: their crossings too.
    const bool switches = !info.switches.empty();
    if (switches) summary["switchings_recorded"] = r.switchings.size();
    const std::string si_text = add_si_results(summary, c, c.model, r.statistics);
    if (c.out)
        write_run(c, "simulate", summary, [&](staged_output& out) {
            const auto si = si_tables_of(c, c.model);  // the SI columns with --si
            write_states(out.file("timeseries.csv"), r.series, info, si ? &*si : nullptr);
            write_impacts(out.file("impacts.csv"), r.impacts, c.model, si ? &*si : nullptr);
            write_states(out.file("sections.csv"), r.points, info, si ? &*si : nullptr);
            json files{"timeseries.csv", "impacts.csv", "sections.csv"};
            if (switches) {
                write_switchings(out.file("switchings.csv"), r.switchings, info);
                files.push_back("switchings.csv");
            }
            return files;
        });
    const std::string text = "outcome " + std::string(to_string(r.status)) + ", " + std::to_string(r.stats.impacts) +
                             " impacts, " +
                             (switches ? std::to_string(r.stats.switchings) + " crossings of switches, " : std::string()) +
                             std::to_string(r.points.size()) + " section points recorded from t = " +
                             format_double(r.t_record_start) + " to t = " + format_double(r.stats.t_final) + "\n" +
                             "steps " + std::to_string(r.stats.steps) + " (rejected " +
                             std::to_string(r.stats.rejected) + "), rhs calls " + std::to_string(r.stats.rhs_calls) +
                             "\n" + statistics_text(r.statistics) + si_text + written_to(c);
    print(c, summary, text);
    return 0;
}

int run_period(const period_args& a)
{
    run_config c = resolve(a.common);
    if (c.si) c.plot_options["units"] = "si";  // the section points in metres and m/s
    check_admissible(c);
    warn_validity(c, {c.model});
    const classified_run r = run_and_classify(c.model, c.ic, c.protocol, a.tol);
    const period_label& lab = r.label;
    const auto& info = c.info();
    // One period of section points: the first variable alone (the paper's y at the section)
    // and the whole states.
    json first = json::array(), cycle = json::array();
    for (int i = 0; i < lab.period; ++i) {
        first.push_back(r.run.points.x(static_cast<std::size_t>(i), 0));
        cycle.push_back(vector_json(r.run.points.x(static_cast<std::size_t>(i))));
    }
    json summary = summary_json(lab, info);
    if (lab.period < 0) null_keys(summary, {"period"});
    summary.update({{"command", "period"},
                    {"tolerance", a.tol},
                    {"outcome", std::string(to_string(r.run.status))},
                    {"section_" + info.state.front().name, first},
                    {"cycle", cycle},
                    {"points", r.run.points.size()},
                    {"impact_statistics", summary_json(r.run.statistics, info)},
                    {"stats", summary_json(r.run.stats, info)},
                    {"out", out_path(c)}});
    const std::string si_text = add_si_results(summary, c, c.model, r.run.statistics);
    if (c.out)
        write_run(c, "period", summary, [&](staged_output& out) {
            const auto si = si_tables_of(c, c.model);  // the SI columns with --si
            write_states(out.file("sections.csv"), r.run.points, info, si ? &*si : nullptr);
            write_impacts(out.file("impacts.csv"), r.run.impacts, c.model, si ? &*si : nullptr);
            return json{"sections.csv", "impacts.csv"};
        });
    std::string text = lab.label;
    if (lab.period > 0)
        text += " (" + std::to_string(lab.impacts_per_period) + " impact(s) per period, closure " +
                format_double(lab.closure) + ")";
    text += "\n" + statistics_text(r.run.statistics) + si_text + unsettled_text(lab.settled ? 0 : 1) + written_to(c);
    print(c, summary, text);
    return 0;
}

int run_grazing(const grazing_args& a)
{
    const run_config c = resolve(a.common);
    check_options(a.options);  // before the run
    const model& m = c.model;
    const auto& info = c.info();
    grazing_options go = a.options;
    go.integration = tangent_integration(c.protocol.flow.integration);
    go.method = c.protocol.method;
    // The parameter whose grazing value each surface reports: --param, or each surface's own.
    go.parameter = a.param.empty() ? each_surface_gap_parameter : parameter_index(m, a.param, "--param");
    warn_validity(c, {m});
    const grazing_result g = grazing(m, c.ic, go);
    // With --si, the grazing value of the gap parameter as a gap in metres: the smallest gap
    // to the surface without impact.
    const int si_gap = c.si && first_gap_parameter(m) >= 0 ? si_parameter(*c.si, m, "gap") : -1;

    json surfaces = json::array(), switches = json::array();
    std::string text;
    // One surface's or switch's entry; `surface` >= 0 for a surface (its SI gap).
    const auto add = [&](json& list, const surface_grazing& s, const std::string& name, int surface) {
        const int p = s.parameter;
        const std::string pname = p >= 0 ? info.parameters[static_cast<std::size_t>(p)].name : "";
        list.push_back({{"name", name},
                        {"parameter", p >= 0 ? json(pname) : json(nullptr)},
                        {"parameter_value", finite_or_null(s.parameter_value)},
                        {"margin", finite_or_null(s.margin)},
                        {"converged", s.converged},
                        {"change", finite_or_null(s.change)},
                        {"t", s.t},
                        {"minima", s.minima},
                        {"state", s.x.size() ? vector_json(s.x) : json(nullptr)}});
        text += (surface >= 0 ? "" : "switch ") + name + ": ";
        if (p >= 0) text += pname + "_graze = " + format_double(s.parameter_value) + ", ";
        text += "margin " + format_double(s.margin);
        if (surface >= 0 && si_gap >= 0 && p == si_gap && std::isfinite(s.parameter_value)) {
            const double gap = gap_to(*c.si, m.with_parameter(p, s.parameter_value), surface);
            list.back()["gap_si"] = finite_or_null(gap);
            text += ", smallest gap without impact " + format_double(gap) + " m";
        }
        if (!s.converged) text += " (NOT converged: last change " + format_double(s.change) + ")";
        text += "\n";
    };
    for (std::size_t i = 0; i < g.surfaces.size(); ++i) add(surfaces, g.surfaces[i], info.surfaces[i].name, static_cast<int>(i));
    for (std::size_t k = 0; k < g.switches.size(); ++k) add(switches, g.switches[k], info.switches[k].name, -1);
    json summary = {{"command", "grazing"},
                    {"surfaces", surfaces},
                    {"converged", g.converged},
                    {"outcome", std::string(to_string(g.status))},
                    {"stats", summary_json(g.stats, info)},
                    {"out", out_path(c)}};
    if (!g.switches.empty()) summary["switches"] = switches;
    if (c.si) summary["si"] = si_json(*c.si, m);
    // The first grazing value as NAME_graze: of the first surface, or the first switch.
    const auto& first = g.surfaces.empty() ? g.switches.front() : g.surfaces.front();
    if (first.parameter >= 0)
        summary[info.parameters[static_cast<std::size_t>(first.parameter)].name + "_graze"] =
            finite_or_null(first.parameter_value);
    if (c.out) {
        throw_if_interrupted();  // before anything is written
        staged_output out(*c.out);
        json record = record_header("grazing", c);
        record["result"] = summary;
        record["note"] = "grazing runs the surface-free (and switch-free) system: the positions of the surfaces do not "
                         "change the orbit";
        finish_output(out, "", c, record);  // no picture
    }
    text += written_to(c);
    print(c, summary, text);
    return 0;
}

}  // namespace

cli_command add_simulate_command(CLI::App& app)
{
    auto a = std::make_shared<simulate_args>();
    auto* s = app.add_subcommand("simulate",
                                 "Run the protocol: discard a transient of impacts, record section points and the time series");
    add_common_options(*s, a->common);
    add_si_option(*s, a->common);
    s->add_option("--dt", a->sample_dt, "Time-series sampling interval with --out (default 0.05)");
    return {s, [a] { return run_simulate(*a); }};
}

cli_command add_period_command(CLI::App& app)
{
    auto a = std::make_shared<period_args>();
    auto* p = app.add_subcommand("period", "Classify the attractor: P0, P1, P2, ..., aperiodic");
    add_common_options(*p, a->common);
    add_si_option(*p, a->common);
    add_declared_option(*p, period_tolerance_option, a->tol);
    return {p, [a] { return run_period(*a); }};
}

cli_command add_grazing_command(CLI::App& app)
{
    auto a = std::make_shared<grazing_args>();
    auto* g = app.add_subcommand("grazing",
                                 "Grazing: where the surface-free attracting orbit just touches each impact surface, and the "
                                 "switch-free one each switch");
    add_common_options(*g, a->common);
    add_si_option(*g, a->common);
    add_declared_options(*g, a->options);
    g->add_option("--param", a->param,
                  "Report the grazing value of this parameter for every surface and switch (default: per surface or "
                  "switch, the first parameter that moves it without entering the vector field)");
    return {g, [a] { return run_grazing(*a); }};
}

}  // namespace vimpact::cli
