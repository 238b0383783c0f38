// The many-job commands over a grid: sweep (bifurcation diagram), map (periodicity map),
// basins (basins of attraction) and response (surface-free response curves). Each resolves
// names to indices, makes one library call through a job_session, and writes its files from
// the typed result.
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <utility>

#include "commands.hpp"
#include "declared_options.hpp"
#include "job_runner.hpp"
#include "output.hpp"
#include "parse.hpp"
#include "vimpact/analysis/basins.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/map.hpp"
#include "vimpact/analysis/response.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/core/names.hpp"
#include "vimpact/integrate/tangent_integration.hpp"
#include "vimpact/io/csv_writer.hpp"
#include "vimpact/io/state_columns.hpp"
#include "vimpact/physical/si_units.hpp"

namespace fs = std::filesystem;

namespace vimpact::cli {
namespace {

// Column names of per-surface values of `prefix` (P_graze, margin): one surface, the prefix
// alone; several, the prefix and the surface name.
std::vector<std::string> surface_columns(const model_info& info, const std::string& prefix)
{
    std::vector<std::string> out;
    for (const auto& s : info.surfaces) out.push_back(info.surfaces.size() == 1 ? prefix : prefix + "_" + s.name);
    return out;
}

std::vector<std::string> grazing_columns(const model& m, int parameter)
{
    if (parameter < 0) return {};
    return surface_columns(m.info(), m.info().parameters[static_cast<std::size_t>(parameter)].name + "_graze");
}


// With --si: the SI columns of a run of `m` (the statistics in SI).
void append_si_statistics(std::vector<double>& cells, const run_config& c, const model& m, const impact_statistics& s)
{
    const auto values = impact_statistics_values(in_si(s, scales_at(*c.si, m)));
    cells.insert(cells.end(), values.begin(), values.end());
}

// ---------------------------------------------------------------- sweep

struct sweep_args {
    common_args common;
    job_args jobs;
    std::string param, range;
    sweep_options options;  // what it declares
    std::string grazing;
    std::string color_by = "none";
    CLI::Option* grazing_option = nullptr;
};

int run_sweep(const sweep_args& a)
{
    run_config c = resolve(a.common);
    c.plot_options["color_by"] = a.color_by;
    job_session session(a.jobs, c.out);
    const model& m = c.model;
    const auto& info = c.info();
    sweep_options o = a.options;
    const axis_values axis = resolve_axis(c, a.param, parse_range(a.range, "--range"), "--param");
    o.parameter = axis.parameter;
    o.values = axis.values;
    warn_validity(c, {m.with_parameter(o.parameter, o.values.front()), m.with_parameter(o.parameter, o.values.back())});
    o.initial_state = c.ic;
    o.protocol = c.protocol;
    if (a.grazing_option->count() > 0) {
        o.grazing_parameter = a.grazing.empty() ? first_grazing_parameter(m) : parameter_index(m, a.grazing, "--grazing");
        if (o.grazing_parameter < 0)
            throw input_error("--grazing: model " + m.name() + " has no parameter that moves a surface or switch without "
                              "entering the vector field; name one with --grazing P");
    }
    const std::string& pname = info.parameters[static_cast<std::size_t>(o.parameter)].name;
    // Without --grazing the columns of the model's usual grazing parameter stay, empty (nan).
    const int gp = o.grazing_parameter >= 0 ? o.grazing_parameter : first_grazing_parameter(m);
    std::vector<std::string> ph{"branch", pname};
    append(ph, state_columns(info));
    // With --si the section points also in SI, each at its point's scales (a cylinder's follow U).
    const auto tables_at = [&](double value) { return si_tables_of(c, m.with_parameter(o.parameter, value)); };
    const bool si_points = c.si.has_value();
    if (!axis.si_name.empty()) ph.push_back(axis.si_name);
    if (si_points) append(ph, state_si_columns(*tables_at(o.values.front()), info));
    // labels.csv: one row per point as the library describes it, then the SI columns.
    const table_context labels_context = table_context_for(info, pname, gp);
    std::vector<std::string> lh;
    if (!axis.si_name.empty()) lh.push_back(axis.si_name);
    if (c.si) append(lh, si_statistics_columns());

    // The points stream in job order: rows to --out DIR, or labels to the summary without it.
    json labels = json::array(), labels_down = json::array();
    label_tally tally;
    std::size_t npoints = 0;
    long unsettled = 0;
    streamed_output stream(c);
    streamed_table pts(stream, "points.csv", ph,
                       series_schema("points", "labels.csv", {{"branch", "branch"}, {pname, "value"}}, state_columns(info),
                                     {ph.begin() + 2 + info.dim(), ph.end()}));
    record_table<sweep_point> lab(stream, "labels.csv", labels_context, {}, lh);
    std::vector<double> row(ph.size());
    auto each = [&](long, const sweep_point& p) {
        tally.add(p.label.label);
        npoints += p.points.size();
        if (!p.label.settled) ++unsettled;
        if (!c.out) {
            (p.branch == 0 ? labels : labels_down).push_back({p.value, p.label.label});
            return;
        }
        row[0] = p.branch;
        row[1] = p.value;
        const auto si = si_points ? tables_at(p.value) : std::nullopt;
        for (std::size_t i = 0; i < p.points.size(); ++i) {
            for (int k = 0; k < p.points.dim(); ++k) row[static_cast<std::size_t>(k) + 2] = p.points.x(i, k);
            row.resize(static_cast<std::size_t>(p.points.dim()) + 2);
            if (!axis.si_name.empty()) row.push_back(axis.si_at(c, p.value));
            if (si) append_state_si(row, *si, p.points.x(i));
            pts.row(row);
        }
        std::vector<double> cells;
        if (axis.si()) cells.push_back(axis.si_at(c, p.value));
        if (c.si) append_si_statistics(cells, c, m.with_parameter(o.parameter, p.value), p.statistics);
        lab.row({}, p, cells);
    };
    const sweep_result res = sweep(m, o, session.options(), each);
    if (!session.complete(res.jobs)) return session.exit_code();

    const json counts = tally.counts();
    json summary = {{"command", "sweep"},         {"param", pname},          {"values", o.values.size()},
                    {"ic_mode", to_string(o.start)}, {"direction", to_string(o.direction)}, {"section_points", npoints},
                    {"label_counts", counts},     {"unsettled", unsettled},  {"batch", res.jobs.batch},
                    {"statistics_columns", impact_statistics_names()}, {"out", out_path(c)}};
    // Each point's label: in labels.csv with --out (the summary stays the same size whatever
    // the number of points), in the summary without it.
    if (!c.out) {
        summary["labels"] = labels;
        if (!labels_down.empty()) summary[o.direction == sweep_direction::down ? "labels" : "labels_down"] = labels_down;
    }
    if (o.grazing_parameter >= 0)
        summary["grazing_param"] = info.parameters[static_cast<std::size_t>(o.grazing_parameter)].name;
    if (!axis.si_name.empty()) summary["si_param"] = axis.si_name;
    if (c.si) summary["si"] = si_json(*c.si, m);
    std::string text = "sweep of " + pname + " over " + std::to_string(o.values.size()) + " values (" +
                       std::string(to_string(o.start)) + " starts): " + counts_text(counts) + "\n" + unsettled_text(unsettled);
    return stream.finish(session, "sweep", "sweep", summary, text);
}

// ---------------------------------------------------------------- map

struct map_args {
    common_args common;
    job_args jobs;
    std::string x, y;
    map_options options;  // what it declares
};

int run_map(const map_args& a)
{
    const run_config c = resolve(a.common);
    job_session session(a.jobs, c.out);
    const model& m = c.model;
    const auto& info = c.info();
    const named_range ax = parse_named_range(a.x, "--x"), ay = parse_named_range(a.y, "--y");
    const axis_values sx = resolve_axis(c, ax.name, ax.values, "--x"), sy = resolve_axis(c, ay.name, ay.values, "--y");
    map_options o = a.options;
    o.x = {sx.parameter, sx.values};
    o.y = {sy.parameter, sy.values};
    const auto at = [&](std::size_t ix, std::size_t iy) {
        return m.with_parameter(o.x.parameter, o.x.values[ix]).with_parameter(o.y.parameter, o.y.values[iy]);
    };
    if (c.si) warn_validity(c, {at(0, 0), at(o.x.values.size() - 1, o.y.values.size() - 1)});
    o.initial_state = c.ic;
    o.protocol = c.protocol;
    // The axes by the model's parameters (an SI axis adds its own columns).
    const named_range mx{info.parameters[static_cast<std::size_t>(o.x.parameter)].name, o.x.values};
    const named_range my{info.parameters[static_cast<std::size_t>(o.y.parameter)].name, o.y.values};
    const std::size_t nx = mx.values.size(), ny = my.values.size();
    // labels.csv: the cell's parameter values, the cell as the library describes it, the SI columns.
    std::vector<std::string> lh;
    for (const auto* axis : {&sx, &sy})
        if (!axis->si_name.empty()) lh.push_back(axis->si_name);
    if (c.si) append(lh, si_statistics_columns());

    // The cells stream in job order: rows to --out DIR, or labels to the summary without it.
    json rows = json::array(), row = json::array();
    label_tally tally;
    long unsettled = 0;
    streamed_output stream(c);
    record_table<map_cell> lab(stream, "labels.csv", table_context_for(info, "", -1), {mx.name, my.name}, lh);
    auto each = [&](long job, const map_cell& cell) {
        tally.add(cell.label.label);
        if (!cell.label.settled) ++unsettled;
        if (!c.out) {
            row.push_back(cell.label.label);
            if (row.size() == nx) rows.push_back(std::exchange(row, json::array()));
            return;
        }
        const auto j = static_cast<std::size_t>(job);
        std::vector<double> cells;
        if (!sx.si_name.empty()) cells.push_back(sx.si_values[j % nx]);
        if (!sy.si_name.empty()) cells.push_back(sy.si_values[j / nx]);
        if (c.si) append_si_statistics(cells, c, at(j % nx, j / nx), cell.statistics);
        lab.row({mx.values[j % nx], my.values[j / nx]}, cell, cells);
    };
    const map_result res = map2d(m, o, session.options(), each);
    if (!session.complete(res.jobs)) return session.exit_code();

    const json counts = tally.counts();
    json summary = {{"command", "map"},       {"x", mx.name},          {"y", my.name},
                    {"shape", {ny, nx}},      {"x_values", mx.values.values()}, {"y_values", my.values.values()},
                    {"label_counts", counts}, {"unsettled", unsettled}, {"batch", res.jobs.batch},
                    {"statistics_columns", impact_statistics_names()}, {"out", out_path(c)}};
    // Each cell's label: in labels.csv with --out (the summary stays the same size whatever
    // the number of cells), in the summary without it.
    if (!c.out) summary["labels"] = rows;
    if (c.si) summary["si"] = si_json(*c.si, m);
    int gp = -1;
    std::string other;
    json grazing = json::array();
    if (res.grazing_axis >= 0) {
        gp = res.grazing_axis == 0 ? o.x.parameter : o.y.parameter;
        other = res.grazing_axis == 0 ? my.name : mx.name;
        for (std::size_t k = 0; k < res.grazing_other.size(); ++k) {
            json e = json::array({res.grazing_other[k]});
            for (const double g : res.grazing_values[k]) e.push_back(finite_or_null(g));
            for (const double g : res.grazing_switch_values[k]) e.push_back(finite_or_null(g));
            grazing.push_back(std::move(e));
        }
        summary["grazing"] = grazing;
        summary["grazing_param"] = info.parameters[static_cast<std::size_t>(gp)].name;
        summary["grazing_surfaces"] = json::array();
        for (const auto& s : info.surfaces) summary["grazing_surfaces"].push_back(s.name);
        summary["grazing_switches"] = json::array();
        for (const auto& s : info.switches) summary["grazing_switches"].push_back(s.name);
    }
    std::string text = "map " + mx.name + " x " + my.name + " (" + std::to_string(nx) + " x " + std::to_string(ny) +
                       "): " + counts_text(counts) + "\n" + unsettled_text(unsettled);
    if (c.out) {
        std::optional<streamed_table> g;
        if (gp >= 0) {
            std::vector<std::string> gh{other};
            append(gh, grazing_columns(m, gp));
            const std::size_t surfaces_end = gh.size();
            for (const auto& s : info.switches) gh.push_back(info.parameters[static_cast<std::size_t>(gp)].name + "_graze_" + s.name);
            g.emplace(stream, "grazing.csv", gh, json());
            for (std::size_t k = 0; k < res.grazing_other.size(); ++k) {
                std::vector<double> grow{res.grazing_other[k]};
                grow.insert(grow.end(), res.grazing_values[k].begin(), res.grazing_values[k].end());
                grow.resize(surfaces_end, std::nan(""));
                grow.insert(grow.end(), res.grazing_switch_values[k].begin(), res.grazing_switch_values[k].end());
                grow.resize(gh.size(), std::nan(""));
                g->row(grow);
            }
        }
        text += stream.commit("map", "map", summary);
        session.finish();
    }
    print(c, summary, text);
    return 0;
}

// ---------------------------------------------------------------- basins

struct basins_args {
    common_args common;
    job_args jobs;
    std::string x, y;
    basins_options options;  // what it declares
};

int run_basins(const basins_args& a)
{
    const run_config c = resolve(a.common);
    job_session session(a.jobs, c.out);
    const model& m = c.model;
    const auto& info = c.info();
    const named_range ax = parse_named_range(a.x, "--x"), ay = parse_named_range(a.y, "--y");
    basins_options o = a.options;
    o.x_state = state_index(m, ax.name, "--x");
    o.y_state = state_index(m, ay.name, "--y");
    o.x_values = ax.values;
    o.y_values = ay.values;
    o.initial_state = c.ic;
    o.protocol = c.protocol;
    const std::size_t nx = ax.values.size(), ny = ay.values.size();
    warn_validity(c, {m});
    // With --si: the initial displacement or velocity of each axis also in SI (the axes that are
    // one), at the model's scales.
    const auto si = si_tables_of(c, m);
    const auto si_factor = [&](int state) {
        return si ? si->scales.of(si->dimensions.at(static_cast<std::size_t>(state))) : std::nan("");
    };
    const double fx = si_factor(o.x_state), fy = si_factor(o.y_state);
    // cells.csv: the start's two values, the cell as the library describes it, their SI values.
    std::vector<std::string> h;
    if (std::isfinite(fx)) h.push_back(ax.name + "_si");
    if (std::isfinite(fy)) h.push_back(ay.name + "_si");

    // The cells stream in job order to cells.csv; the summary counts.
    long excluded = 0, unsettled = 0;
    streamed_output stream(c);
    record_table<basin_cell> cells(stream, "cells.csv", table_context_for(info, "", -1), {ax.name, ay.name}, h);
    auto each = [&](long job, const basin_cell& b) {
        if (!b.admissible) ++excluded;
        if (!b.label.settled) ++unsettled;
        if (!c.out) return;
        const auto j = static_cast<std::size_t>(job);
        const double x = ax.values[j % nx], y = ay.values[j / nx];
        std::vector<double> si_cells;
        if (std::isfinite(fx)) si_cells.push_back(x * fx);
        if (std::isfinite(fy)) si_cells.push_back(y * fy);
        cells.row({x, y}, b, si_cells);
    };
    const basins_result res = basins(m, o, session.options(), each);
    if (!session.complete(res.jobs)) return session.exit_code();

    json table = json::array(), labels = json::array();
    for (std::size_t i = 0; i < res.attractors.size(); ++i) {
        const auto& e = res.attractors[i];
        json pts = json::array();
        for (const auto& p : e.signature.cycle) pts.push_back(vector_json(p));
        table.push_back({{"id", i},
                         {"label", e.signature.label},
                         {"cells", e.members},
                         {"section_points", pts},
                         {"box", {vector_json(e.signature.lo), vector_json(e.signature.hi)}}});
        labels.push_back(e.signature.label);
    }
    json summary = {{"command", "basins"},
                    {"x", ax.name},
                    {"y", ay.name},
                    {"shape", {ny, nx}},
                    {"x_values", ax.values.values()},
                    {"y_values", ay.values.values()},
                    {"attractors", {{"count", res.attractors.size()}, {"labels", labels}, {"table", table}}},
                    {"inadmissible_cells", excluded},
                    {"unsettled", unsettled},
                    {"batch", res.jobs.batch},
                    {"out", out_path(c)}};
    if (c.si) summary["si"] = si_json(*c.si, m);
    std::string text = std::to_string(res.attractors.size()) + " attractor(s) on the " + std::to_string(nx) + " x " +
                       std::to_string(ny) + " grid of initial " + ax.name + ", " + ay.name + ":\n";
    for (const auto& t : table)
        text += "  " + std::to_string(t["id"].get<int>()) + ": " + t["label"].get<std::string>() + ", " +
                std::to_string(t["cells"].get<long>()) + " cells\n";
    if (excluded) text += "  (" + std::to_string(excluded) + " cells start beyond a surface and are excluded)\n";
    text += unsettled_text(unsettled);
    return stream.finish(session, "basins", "basins", summary, text);
}

// ---------------------------------------------------------------- response

struct response_args {
    common_args common;
    job_args jobs;
    std::string param, range, curves, variable;
    response_options options;  // what it declares: the surface-free run's
};

// "A=14,eps=0.35;A=12,eps=0.3": each curve a list of NAME=VALUE.
std::vector<std::vector<std::pair<int, double>>> parse_curves(const std::string& text, const model& m)
{
    std::vector<std::vector<std::pair<int, double>>> out;
    if (text.empty()) return out;
    for (const auto& curve : split(text, ';')) {
        std::vector<std::pair<int, double>> c;
        for (const auto& item : split(curve, ',')) {
            const auto eq = item.find('=');
            if (eq == std::string::npos || eq == 0)
                throw input_error("--curves item '" + item + "' must be NAME=VALUE (curves: 'A=14,eps=0.35;A=12,eps=0.3')");
            const std::string name = item.substr(0, eq);
            const int p = parameter_index(m, name, "--curves");
            for (const auto& [q, v] : c)
                if (q == p) throw input_error("--curves: '" + name + "' is set twice in the curve '" + curve + "'");
            c.emplace_back(p, parse_number(item.substr(eq + 1), "--curves " + name));
        }
        out.push_back(std::move(c));
    }
    return out;
}

int run_response(const response_args& a)
{
    const run_config c = resolve(a.common);
    job_session session(a.jobs, c.out);
    const model& m = c.model;
    const auto& info = c.info();
    response_options o = a.options;
    const axis_values axis = resolve_axis(c, a.param, parse_range(a.range, "--range"), "--param");
    o.parameter = axis.parameter;
    o.values = axis.values;
    o.curves = parse_curves(a.curves, m);
    o.variable = a.variable.empty() ? 0 : state_index(m, a.variable, "--variable");
    o.initial_state = c.ic;
    o.grazing.integration = tangent_integration(c.protocol.flow.integration);
    o.grazing.method = c.protocol.method;
    o.grazing.parameter = first_grazing_parameter(m);
    const std::string& pname = info.parameters[static_cast<std::size_t>(o.parameter)].name;
    const std::string& vname = info.state[static_cast<std::size_t>(o.variable)].name;
    // The summary's per-surface values: grazing values where the parameter moves a surface, else
    // the margins (a parameter that moves a switch only: its values are in response.csv).
    const bool surface_grazing = o.grazing.parameter >= 0 && surface_moved_by(m, o.grazing.parameter) >= 0;
    const auto gcols = surface_grazing ? grazing_columns(m, o.grazing.parameter) : surface_columns(info, "margin");
    // The parameters any curve sets, in the model's order: one column each.
    std::vector<int> curve_params;
    for (const auto& curve : o.curves)
        for (const auto& [p, v] : curve)
            if (std::find(curve_params.begin(), curve_params.end(), p) == curve_params.end()) curve_params.push_back(p);
    std::sort(curve_params.begin(), curve_params.end());
    const std::size_t ncurves = std::max<std::size_t>(1, o.curves.size());
    std::vector<vimpact::model> ends;
    for (std::size_t k = 0; k < ncurves; ++k)
        for (const double v : {o.values.front(), o.values.back()})
            ends.push_back(response_model(m, o, static_cast<int>(k), v));
    warn_validity(c, ends);
    // With --si: the amplitude in metres (the measured variable a displacement), the frequency
    // in hertz and the grazing values as the smallest gap without impact, per surface, in metres.
    const physical_dimension vdim = c.si ? state_dimensions(m).at(static_cast<std::size_t>(o.variable))
                                         : physical_dimension::none;
    const bool si_gaps = c.si && surface_grazing;

    // The points stream in job order (curve by curve): rows to --out DIR; each curve's
    // arrays go to the summary only without it (with it they are in response.csv).
    struct curve_tally {
        json amplitude = json::array(), frequency = json::array();
        json amplitude_si = json::array(), frequency_si = json::array();
        std::vector<json> graze, clearance_si;
        long unconverged = 0;
        double peak = -1.0, peak_si = -1.0;
    };
    std::vector<curve_tally> tallies(ncurves);
    for (auto& t : tallies) {
        t.graze.assign(gcols.size(), json::array());
        if (si_gaps) t.clearance_si.assign(gcols.size(), json::array());
    }
    // response.csv: the curve's parameter values, the point as the library describes it, the SI columns.
    std::vector<std::string> lead;
    for (const int p : curve_params) lead.push_back(info.parameters[static_cast<std::size_t>(p)].name);
    table_context context = table_context_for(info, pname, o.grazing.parameter);
    context.variable = vname;
    std::vector<std::string> h;
    const auto ccols = si_gaps ? surface_columns(info, "clearance_si") : std::vector<std::string>{};
    if (axis.si()) h.push_back(axis.si_name);
    if (c.si) {
        if (vdim != physical_dimension::none) append(h, {"amplitude_si", vname + "_max_si", vname + "_min_si"});
        h.emplace_back("frequency_si");
        append(h, ccols);
    }
    // A point's SI values: the amplitude (NaN unless the variable has a dimension), its maximum
    // and minimum, the frequency, and the clearance to each surface.
    struct si_point {
        double amplitude = std::nan(""), maximum = std::nan(""), minimum = std::nan(""), frequency = std::nan("");
        std::vector<double> clearance;
    };
    auto in_si = [&](const response_point& r, const model& at) {
        si_point q;
        const physical_scales k = scales_at(*c.si, at);
        if (vdim != physical_dimension::none) {
            q.amplitude = r.amplitude * k.of(vdim);
            q.maximum = r.maximum * k.of(vdim);
            q.minimum = r.minimum * k.of(vdim);
        }
        q.frequency = r.frequency * k.frequency();
        if (si_gaps)
            for (std::size_t s = 0; s < gcols.size(); ++s) {
                const double g = s < r.grazing.size() ? r.grazing[s] : std::nan("");
                q.clearance.push_back(std::isfinite(g)
                                          ? gap_to(*c.si, at.with_parameter(o.grazing.parameter, g), static_cast<int>(s))
                                          : std::nan(""));
            }
        return q;
    };
    streamed_output stream(c);
    record_table<response_point> w(stream, "response.csv", context, lead, h);
    auto each = [&](long, const response_point& r) {
        auto& t = tallies[static_cast<std::size_t>(r.curve)];
        t.unconverged += r.converged ? 0 : 1;
        if (std::isfinite(r.amplitude)) t.peak = std::max(t.peak, r.amplitude);
        const model at = response_model(m, o, r.curve, r.value);
        const si_point q = c.si ? in_si(r, at) : si_point{};
        if (std::isfinite(q.amplitude)) t.peak_si = std::max(t.peak_si, q.amplitude);
        if (!c.out) {
            const auto& graze = surface_grazing ? r.grazing : r.margin;
            t.amplitude.push_back(finite_or_null(r.amplitude));
            t.frequency.push_back(finite_or_null(r.frequency));
            for (std::size_t s = 0; s < gcols.size(); ++s)
                t.graze[s].push_back(finite_or_null(s < graze.size() ? graze[s] : std::nan("")));
            if (c.si) {
                t.amplitude_si.push_back(finite_or_null(q.amplitude));
                t.frequency_si.push_back(finite_or_null(q.frequency));
                for (std::size_t s = 0; s < q.clearance.size(); ++s) t.clearance_si[s].push_back(finite_or_null(q.clearance[s]));
            }
            return;
        }
        std::vector<double> lead_cells, si_cells;
        for (const int p : curve_params) lead_cells.push_back(at.parameter(p));
        if (axis.si()) si_cells.push_back(axis.si_at(c, r.value));
        if (c.si) {
            if (vdim != physical_dimension::none) si_cells.insert(si_cells.end(), {q.amplitude, q.maximum, q.minimum});
            si_cells.push_back(q.frequency);
            si_cells.insert(si_cells.end(), q.clearance.begin(), q.clearance.end());
        }
        w.row(lead_cells, r, si_cells);
    };
    const response_result res = response(m, o, session.options(), each);
    if (!session.complete(res.jobs)) return session.exit_code();

    json curves = json::array();
    std::string text;
    for (std::size_t k = 0; k < ncurves; ++k) {
        json set = json::object();
        std::vector<std::string> described;
        if (k < o.curves.size())
            for (const auto& [p, v] : o.curves[k]) {
                set[info.parameters[static_cast<std::size_t>(p)].name] = v;
                described.push_back(info.parameters[static_cast<std::size_t>(p)].name + " = " + format_double(v));
            }
        auto& t = tallies[k];
        json cj = {{"parameters", set}, {"not_converged", t.unconverged}};
        if (!c.out) {  // with --out the values are response.csv's rows: run.json stays the same size
            cj["values"] = o.values.values();
            if (axis.si()) cj["si_values"] = axis.si_values.values();
            cj["amplitude"] = std::move(t.amplitude);
            cj["frequency"] = std::move(t.frequency);
            for (std::size_t s = 0; s < gcols.size(); ++s) cj[gcols[s]] = std::move(t.graze[s]);
            if (c.si) {
                if (vdim != physical_dimension::none) cj["amplitude_si"] = std::move(t.amplitude_si);
                cj["frequency_si"] = std::move(t.frequency_si);
                for (std::size_t s = 0; s < ccols.size(); ++s) cj[ccols[s]] = std::move(t.clearance_si[s]);
            }
        }
        curves.push_back(std::move(cj));
        text += (described.empty() ? std::string("response") : join(described)) + ": peak amplitude of " + vname + " " +
                format_double(t.peak) +
                (t.peak_si >= 0.0 ? " (" + format_double(t.peak_si) + " " + std::string(si_unit(vdim)) + ")"
                                  : std::string()) +
                (t.unconverged ? " (" + std::to_string(t.unconverged) + " points not converged)" : std::string()) + "\n";
    }
    json summary = {{"command", "response"},
                    {"param", pname},
                    {"variable", vname},
                    {"grazing_param", o.grazing.parameter >= 0
                                          ? json(info.parameters[static_cast<std::size_t>(o.grazing.parameter)].name)
                                          : json(nullptr)},
                    {"curves", curves},
                    {"out", out_path(c)}};
    if (axis.si()) summary["si_param"] = axis.si_name;
    if (c.si) summary["si"] = si_json(*c.si, m);
    return stream.finish(session, "response", "response", summary, text);
}

}  // namespace

cli_command add_sweep_command(CLI::App& app)
{
    auto a = std::make_shared<sweep_args>();
    auto* s = app.add_subcommand("sweep", "Bifurcation diagram: section points and labels over a range of one parameter");
    add_common_options(*s, a->common);
    add_si_option(*s, a->common);
    add_job_options(*s, a->jobs);
    s->add_option("--param", a->param,
                  "Parameter to vary (`vimpact models` lists a model's parameters; with --si also U [m/s] or gap [m])")
        ->required();
    s->add_option("--range", a->range, "Values a:b:n (from a to b, n points)")->required();
    add_declared_options(*s, a->options);
    a->grazing_option = s->add_option("--grazing", a->grazing,
                                      "Also the grazing value of parameter P (default: the first that moves a surface "
                                      "without entering the vector field) at each point, per surface")
                            ->expected(0, 1);
    s->add_option("--color-by", a->color_by,
                  "With --out: colour the diagram's points by none (default: black) or period (each value's period "
                  "label, with a legend)")
        ->check(CLI::IsMember({"none", "period"}));
    return {s, [a] { return run_sweep(*a); }};
}

cli_command add_map_command(CLI::App& app)
{
    auto a = std::make_shared<map_args>();
    auto* s = app.add_subcommand("map", "Periodicity map: the label (P0, PN, aperiodic, failure) over a grid of two parameters");
    add_common_options(*s, a->common);
    add_si_option(*s, a->common);
    add_job_options(*s, a->jobs);
    s->add_option("--x", a->x, "Horizontal axis P:a:b:n (with --si P may be U [m/s] or gap [m])")->required();
    s->add_option("--y", a->y, "Vertical axis Q:c:d:m")->required();
    add_declared_options(*s, a->options);
    return {s, [a] { return run_map(*a); }};
}

cli_command add_basins_command(CLI::App& app)
{
    auto a = std::make_shared<basins_args>();
    auto* s = app.add_subcommand("basins", "Basins of attraction over a grid of initial states");
    add_common_options(*s, a->common);
    add_si_option(*s, a->common);
    add_job_options(*s, a->jobs);
    s->add_option("--x", a->x,
                  "Horizontal axis S:a:b:n, S a state variable of the model (the others from --ic; in model units "
                  "also with --si)")
        ->required();
    s->add_option("--y", a->y, "Vertical axis T:c:d:m")->required();
    add_declared_options(*s, a->options);
    return {s, [a] { return run_basins(*a); }};
}

cli_command add_response_command(CLI::App& app)
{
    auto a = std::make_shared<response_args>();
    auto* s = app.add_subcommand("response",
                                 "Surface-free response (lock-in curves): amplitude, frequency and grazing values over a range");
    add_common_options(*s, a->common);
    add_si_option(*s, a->common);
    add_job_options(*s, a->jobs);
    s->add_option("--param", a->param,
                  "Parameter to vary (one that enters the vector field; with --si also U [m/s])")
        ->required();
    s->add_option("--range", a->range, "Values a:b:n")->required();
    s->add_option("--curves", a->curves,
                  "Several curves, each a list of parameter values: 'A=14,eps=0.35;A=12,eps=0.3' (default: one curve at "
                  "the configured values)");
    s->add_option("--variable", a->variable, "The state variable measured (default the model's first)");
    add_declared_options(*s, a->options);
    return {s, [a] { return run_response(*a); }};
}

}  // namespace vimpact::cli
