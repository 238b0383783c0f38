// The clearance command: along a range of flow speeds (or of any parameter), the smallest gap
// to the neighbouring surface with no impact (the grazing line), the gap range where the
// response is aperiodic, and a design chart of the response over gaps (analysis/clearance.hpp),
// in SI units with --si. One library call through a job_session, like sweep and map.
#include <cmath>
#include <memory>

#include "commands.hpp"
#include "declared_options.hpp"
#include "job_runner.hpp"
#include "output.hpp"
#include "parse.hpp"
#include "vimpact/analysis/clearance.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/physical/si_units.hpp"

namespace vimpact::cli {
namespace {

struct clearance_args {
    common_args common;
    job_args jobs;
    std::string speeds, param, range, gaps, fractions, gap_param;
    clearance_options options;  // what it declares
};

int run_clearance(const clearance_args& a)
{
    const run_config c = resolve(a.common);
    job_session session(a.jobs, c.out);
    const model& m = c.model;
    const auto& info = c.info();
    if (c.si && (c.si->speed || c.si->gap))
        throw input_error("clearance takes the speeds from --speeds and scans the gaps: leave U and gap out of --si");
    if (a.speeds.empty() == (a.param.empty() || a.range.empty()))
        throw input_error("clearance needs either --speeds a:b:n (m/s, with --si) or --param P with --range a:b:n");
    const bool by_speed = !a.speeds.empty();
    if (by_speed && !(c.si && c.si->cylinder))
        throw input_error("--speeds needs a cylinder in --si (D=..,m=..,fn=..,zeta=..,rho=..)");

    clearance_options o = a.options;
    value_grid speeds;  // as given, with --speeds
    if (by_speed) {
        speeds = parse_range(a.speeds, "--speeds");
        o.parameter = si_parameter(*c.si, m, "U");
        o.values = si_parameter_grid(*c.si, m, "U", speeds);
    } else {
        o.parameter = parameter_index(m, a.param, "--param");
        o.values = parse_range(a.range, "--range");
    }
    // Gaps: in metres with --si, else in the model's units (the library checks them).
    if (!a.gaps.empty()) {
        // The chart's gaps are each value's cells: a job holds them all, so a list.
        const auto gaps = parse_range(a.gaps, "--gaps").values();
        try {
            o.gaps = c.si ? gaps_in_model_units(*c.si, gaps) : gaps;
        } catch (const input_error& e) {
            throw input_error(std::string("--gaps: ") + e.what());
        }
    }
    if (!a.fractions.empty()) o.fractions = parse_range(a.fractions, "--fractions").values();
    o.gap_parameter = a.gap_param.empty() ? -1 : parameter_index(m, a.gap_param, "--gap-param");
    o.initial_state = c.ic;
    o.protocol = c.protocol;
    o.grazing = job_grazing_options(c.protocol.flow.integration, a.options.grazing.transient_time);
    o.grazing.method = c.protocol.method;
    // The calibrated range's warnings at the ends of the flow axis (the Reynolds number grows
    // with the speed): a model per value would hold the whole axis.
    const json warnings =
        warn_validity(c, {m.with_parameter(o.parameter, o.values.front()), m.with_parameter(o.parameter, o.values.back())});

    const clearance_result res = clearance(m, o, session.options());
    if (!session.complete(res.jobs)) return session.exit_code();

    const std::string pname = info.parameters[static_cast<std::size_t>(o.parameter)].name;
    const std::string gname = info.parameters[static_cast<std::size_t>(res.gap_parameter)].name;
    const std::string xname = by_speed ? "U" : pname;
    const bool si = c.si.has_value();
    // The flow axis and the gaps as reported: U [m/s] and metres with --si (the result in SI).
    const auto x_of = [&](std::size_t k) { return by_speed ? speeds[k] : o.values[k]; };
    const clearance_result shown = si ? in_si(res, *c.si, m, o.parameter) : res;

    json clearance_pairs = json::array(), aperiodic = json::array(), dimensionless = json::array();
    label_tally labels;
    // The surface the gap parameter moves, or the switch (a compliant barrier: no crossing).
    const bool on_switch = res.surface < 0;
    const std::string target = on_switch ? info.switches[static_cast<std::size_t>(res.switch_index)].name
                                         : info.surfaces[static_cast<std::size_t>(res.surface)].name;
    std::string text = "clearance over " + xname + (si ? "" : " (model units)") + ": the smallest gap to " +
                       (on_switch ? "switch " + target + " without crossing\n" : target + " without impact\n");
    for (std::size_t k = 0; k < res.points.size(); ++k) {
        const auto& p = res.points[k];
        const auto& q = shown.points[k];
        clearance_pairs.push_back({x_of(k), finite_or_null(q.clearance)});
        aperiodic.push_back({x_of(k), finite_or_null(q.aperiodic_min), finite_or_null(q.aperiodic_max)});
        json row = json::object();
        if (by_speed)
            for (const auto& [name, value] : units_at(*c.si->cylinder, speeds[k])) row[name] = finite_or_null(value);
        row[pname] = p.value;
        row[gname + "_graze"] = finite_or_null(p.grazing_value);
        row["clearance"] = finite_or_null(p.clearance);  // model units
        row["converged"] = p.converged;
        dimensionless.push_back(std::move(row));
        for (const auto& cell : p.cells) labels.add(cell.label.label);
        text += "  " + xname + " = " + format_double(x_of(k)) + ": gap " + format_double(q.clearance) +
                (si ? " m" : "") + (p.converged ? "" : " (grazing NOT converged)");
        if (std::isfinite(q.aperiodic_min))
            text += ", aperiodic for gaps " + format_double(q.aperiodic_min) + " .. " + format_double(q.aperiodic_max) +
                    (si ? " m" : "");
        text += "\n";
    }
    const json counts = labels.counts();
    text += "chart: " + counts_text(counts) + "\n";
    json summary = {{"command", "clearance"},
                    {"param", pname},
                    {"x", xname},
                    {"gap_param", gname},
                    {"surface", on_switch ? json(nullptr) : json(target)},
                    {"switch", on_switch ? json(target) : json(nullptr)},
                    {"units", si ? "si" : "model"},
                    {"clearance", clearance_pairs},
                    {"aperiodic", aperiodic},
                    {"dimensionless", dimensionless},
                    {"label_counts", counts},
                    {"statistics_columns", impact_statistics_names()},
                    {"warnings", warnings},
                    {"out", out_path(c)}};
    if (si) summary["si"] = si_json(*c.si, m);
    if (c.out) {
        // The tables: a row per value and a row per chart cell as the library describes them,
        // after the value (and speed) a cell belongs to and before the SI values.
        const table_context context = table_context_for(info, pname, res.gap_parameter);
        std::vector<std::string> lead{pname}, trail, chart_trail;
        if (by_speed) lead.emplace_back("U");
        if (si) {
            trail = {"clearance_si", "aperiodic_min_si", "aperiodic_max_si"};
            chart_trail = {"gap_si"};
            append(chart_trail, si_statistics_columns());
        }
        streamed_output stream(c);
        record_table<clearance_point> points(stream, "clearance.csv", context, {lead.begin() + 1, lead.end()}, trail);
        record_table<clearance_cell> chart(stream, "chart.csv", context, lead, chart_trail);
        for (std::size_t k = 0; k < res.points.size(); ++k) {
            const auto& p = res.points[k];
            const auto& q = shown.points[k];
            std::vector<double> speed;
            if (by_speed) speed.push_back(speeds[k]);
            points.row(speed, p, si ? std::vector<double>{q.clearance, q.aperiodic_min, q.aperiodic_max}
                                    : std::vector<double>{});
            speed.insert(speed.begin(), p.value);
            for (std::size_t i = 0; i < p.cells.size(); ++i) {
                std::vector<double> in_si;
                if (si) {
                    in_si = impact_statistics_values(q.cells[i].statistics);
                    in_si.insert(in_si.begin(), q.cells[i].gap);
                }
                chart.row(speed, p.cells[i], in_si);
            }
        }
        text += stream.commit("clearance", "clearance", summary);
        session.finish();
    }
    print(c, summary, text);
    return 0;
}

}  // namespace

cli_command add_clearance_command(CLI::App& app)
{
    auto a = std::make_shared<clearance_args>();
    auto* s = app.add_subcommand(
        "clearance",
        "Clearance design: over a range of flow speeds, the smallest gap to the neighbouring surface without impact "
        "(the grazing line), the gaps where the response is aperiodic, and a design chart of regimes, impact rate "
        "and dissipated power over gaps");
    add_common_options(*s, a->common);
    add_si_option(*s, a->common);
    add_job_options(*s, a->jobs);
    s->add_option("--speeds", a->speeds, "Flow speeds a:b:n [m/s] (needs a cylinder in --si)");
    s->add_option("--param", a->param, "Instead of --speeds: the flow parameter of any model (e.g. Ur)");
    s->add_option("--range", a->range, "Its values a:b:n (with --param)");
    s->add_option("--gaps", a->gaps,
                  "The chart's gaps a:b:n, from the rest state to the surface [m with --si, else model units] "
                  "(default: fractions of each speed's clearance)");
    s->add_option("--fractions", a->fractions,
                  "The chart's gaps as fractions of each speed's clearance, a:b:n (default 0.1:1.3:13)");
    s->add_option("--gap-param", a->gap_param,
                  "The parameter that moves the surface (default: the model's first, sigma for the wake model)");
    add_declared_options(*s, a->options);
    return {s, [a] { return run_clearance(*a); }};
}

}  // namespace vimpact::cli
