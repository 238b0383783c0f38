// The job-loop commands: sweep (bifurcation diagram), map (periodicity map), basins (basins of
// attraction) and response (barrier-free lock-in curves). Each builds a list of jobs, runs
// them through run_job_command, and writes its files from the records in job order.
#include "sweep_commands.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "job_runner.hpp"
#include "output.hpp"
#include "vimpact/analysis/attractor.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/job_points.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/io/csv_writer.hpp"

namespace fs = std::filesystem;

namespace vimpact::cli {
namespace {

// ---------------------------------------------------------------- grids and axes

struct axis {
    std::string name;
    std::vector<double> values;
};

// "a:b:n" -> n values from a to b.
std::vector<double> parse_range(const std::string& text, const std::string& what)
{
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (;;) {
        const auto colon = text.find(':', start);
        parts.push_back(text.substr(start, colon == std::string::npos ? std::string::npos : colon - start));
        if (colon == std::string::npos) break;
        start = colon + 1;
    }
    if (parts.size() != 3) throw input_error(what + " '" + text + "' must be a:b:n (from a to b, n points)");
    const double a = parse_number(parts[0], what + " start");
    const double b = parse_number(parts[1], what + " end");
    const double n = parse_number(parts[2], what + " points");
    if (n < 1 || n != std::floor(n) || n > 1e7)
        throw input_error(what + " '" + text + "': n must be an integer in [1, 1e7]");
    return grid_values(a, b, static_cast<long>(n));
}

void check_parameter(const std::string& name, const std::string& what)
{
    check_parameter_name(wake_impact(), name, what);
}

// "NAME:a:b:n" -> a named axis; NAME is a model parameter (map) or a state component (basins).
axis parse_axis(const std::string& text, const std::string& what, bool state_component)
{
    const auto colon = text.find(':');
    if (colon == std::string::npos || colon == 0)
        throw input_error(what + " '" + text + "' must be NAME:a:b:n");
    axis ax{text.substr(0, colon), parse_range(text.substr(colon + 1), what)};
    if (state_component) (void)state_axis_index(wake_impact(), ax.name, what);
    else check_parameter(ax.name, what);
    return ax;
}

json state_json(const vec<4>& x) { return {x[0], x[1], x[2], x[3]}; }
vec<4> state_from(const json& j) { return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>(), j[3].get<double>()}; }

// Grazing value of `model` (barrier-free, so independent of sigma), as the `grazing` command
// computes it.
grazing_result<4> grazing_of(const wake_impact& model, const run_config& c)
{
    const grazing_options go = job_grazing_options(c.protocol().flow.integration);
    return with_method(c.method, [&]<template <int> class M>() { return grazing_value<M>(model, c.ic, go); });
}

classified_run<4> classify_at(const wake_impact& model, const vec<4>& x0, const run_config& c, double tol)
{
    return with_method(c.method, [&]<template <int> class M>() {
        return run_and_classify<M>(model, x0, c.protocol(), tol);
    });
}

json label_fields(const classified_run<4>& r)
{
    return {{"label", r.label.label},
            {"period", r.label.period},
            {"impacts", r.label.impacts_per_period},
            {"closure", r.label.closure},
            {"outcome", std::string(to_string(r.run.status))},
            {"steps", r.run.stats.steps}};
}

void check_tol(double tol) { check_period_tolerance(tol, input_spelling::cli); }

json label_counts(const std::vector<json>& records)
{
    std::map<std::string, long> counts;
    for (const auto& r : records) ++counts[r["label"].get<std::string>()];
    json j = json::object();
    for (const auto& [k, v] : counts) j[k] = v;
    return j;
}

std::string counts_text(const json& counts)
{
    std::string t;
    for (const auto& [k, v] : counts.items()) t += (t.empty() ? "" : ", ") + k + " " + std::to_string(v.get<long>());
    return t;
}

// Finishes --out DIR: the record, the files listed, the PNG of `kind`.
void write_run(const fs::path& dir, const char* kind, const run_config& c, json summary,
               const std::function<std::vector<std::string>(staged_output&)>& write_files)
{
    staged_output out(dir);
    json record = record_header(kind, c);
    auto files = write_files(out);
    record["result"] = std::move(summary);
    files.push_back("run.json");
    record["files"] = files;
    finish_output(out, kind, c, record);
}

// ---------------------------------------------------------------- sweep

struct sweep_args {
    common_args common;
    job_args jobs;
    std::string param;
    std::string range;
    std::string ic_mode = "fixed";
    std::string direction = "up";
    double tol = default_period_tolerance;
    bool grazing = false;
};

int run_sweep(const sweep_args& a)
{
    const run_config c = resolve(a.common);
    check_parameter(a.param, "--param");
    const auto values = parse_range(a.range, "--range");
    check_tol(a.tol);
    const long n = static_cast<long>(values.size());
    const sweep_plan plan = make_sweep_plan(n, a.ic_mode, a.direction, input_spelling::cli);
    const wake_impact base = c.model();
    check_sweep_starts(base, a.param, values, c.ic, plan, input_spelling::cli);

    job_command cmd;
    cmd.spec = {{"command", "sweep"}, {"config", c.to_json()}, {"param", a.param}, {"range", a.range},
                {"ic_mode", a.ic_mode}, {"direction", a.direction}, {"tol", a.tol}, {"grazing", a.grazing}};
    cmd.schedule = plan.schedule();
    cmd.out = c.out ? std::optional<fs::path>(*c.out) : std::nullopt;
    cmd.run = [&](long job, const json* prev) {
        const auto [branch, i] = plan.at(job);
        const double v = values[static_cast<std::size_t>(i)];
        const wake_impact m = base.with(a.param, v);
        const vec<4> previous_final = prev ? state_from((*prev)["final_state"]) : vec<4>::Zero();
        const vec<4> x0 = sweep_start(m, prev ? &previous_final : nullptr, c.ic);
        const auto r = classify_at(m, x0, c, a.tol);
        json rec = label_fields(r);
        rec["value"] = v;
        rec["branch"] = branch;
        json pts = json::array();
        for (const auto& p : r.run.points) pts.push_back(state_json(p.x));
        rec["points"] = std::move(pts);
        rec["final_state"] = state_json(r.run.final_state);
        if (a.grazing) rec["sigma_graze"] = finite_or_null(grazing_of(m, c).sigma_graze);
        return rec;
    };
    json summary;
    std::string text;
    cmd.finish = [&](const std::vector<json>& recs, const fs::path* dir) {
        json labels = json::array(), labels_down = json::array();
        long npoints = 0;
        for (const auto& r : recs) {
            (r["branch"] == 0 ? labels : labels_down).push_back({r["value"], r["label"]});
            npoints += static_cast<long>(r["points"].size());
        }
        const json counts = label_counts(recs);
        summary = {{"command", "sweep"}, {"param", a.param}, {"values", n}, {"ic_mode", a.ic_mode},
                   {"direction", a.direction}, {"section_points", npoints}, {"label_counts", counts},
                   {"labels", labels}, {"out", c.out ? json(*c.out) : json(nullptr)}};
        if (!labels_down.empty()) summary[a.direction == "down" ? "labels" : "labels_down"] = labels_down;
        text = "sweep of " + a.param + " over " + std::to_string(n) + " values (" + a.ic_mode + " starts): " +
               counts_text(counts) + "\n";
        if (!dir) return;
        write_run(*dir, "sweep", c, summary, [&](staged_output& out) {
            csv_writer pts(out.file("points.csv"), {"branch", a.param, "y", "ydot", "x", "xdot"});
            csv_writer lab(out.file("labels.csv"), {"branch", a.param, "label", "period", "impacts", "closure", "outcome", "sigma_graze"});
            for (const auto& r : recs) {
                const double v = r["value"].get<double>(), b = r["branch"].get<int>();
                for (const auto& p : r["points"]) pts.row({b, v, p[0].get<double>(), p[1].get<double>(), p[2].get<double>(), p[3].get<double>()});
                const bool g = r.contains("sigma_graze") && r["sigma_graze"].is_number();
                lab.text_row({format_double(b), format_double(v), r["label"].get<std::string>(),
                              std::to_string(r["period"].get<int>()), std::to_string(r["impacts"].get<long>()),
                              format_double(r["closure"].get<double>()), r["outcome"].get<std::string>(),
                              g ? format_double(r["sigma_graze"].get<double>()) : std::string("nan")});
            }
            pts.close();
            lab.close();
            return std::vector<std::string>{"points.csv", "labels.csv"};
        });
        text += "output written to " + *c.out + "\n";
    };
    const auto res = run_job_command(cmd, a.jobs);
    if (res.complete) print(c, summary, text);
    return res.exit_code;
}

// ---------------------------------------------------------------- map

struct map_args {
    common_args common;
    job_args jobs;
    std::string x, y;
    double tol = default_period_tolerance;
    bool grazing = false;
};

int run_map(const map_args& a)
{
    const run_config c = resolve(a.common);
    const axis ax = parse_axis(a.x, "--x", false), ay = parse_axis(a.y, "--y", false);
    check_map_axes(ax.name, ay.name, input_spelling::cli);
    check_tol(a.tol);
    const long nx = static_cast<long>(ax.values.size()), ny = static_cast<long>(ay.values.size());
    const wake_impact base = c.model();
    check_map_starts(base, ax.name, ax.values, ay.name, ay.values, c.ic, input_spelling::cli);
    const grazing_line graze = map_grazing_line(a.grazing, ax.name, ay.name, input_spelling::cli);

    job_command cmd;
    cmd.spec = {{"command", "map"}, {"config", c.to_json()}, {"x", a.x}, {"y", a.y}, {"tol", a.tol}, {"grazing", a.grazing}};
    cmd.schedule = {nx * ny, 0};
    cmd.out = c.out ? std::optional<fs::path>(*c.out) : std::nullopt;
    cmd.run = [&](long job, const json*) {
        const long ix = job % nx, iy = job / nx;
        const wake_impact m = map_model(base, ax.name, ax.values[static_cast<std::size_t>(ix)], ay.name,
                                        ay.values[static_cast<std::size_t>(iy)]);
        json rec = label_fields(classify_at(m, c.ic, c, a.tol));
        if (computes_grazing(graze, ix, iy))
            rec["sigma_graze"] = finite_or_null(grazing_of(m, c).sigma_graze);
        return rec;
    };
    json summary;
    std::string text;
    cmd.finish = [&](const std::vector<json>& recs, const fs::path* dir) {
        json rows = json::array();
        for (long iy = 0; iy < ny; ++iy) {
            json row = json::array();
            for (long ix = 0; ix < nx; ++ix) row.push_back(recs[static_cast<std::size_t>(iy * nx + ix)]["label"]);
            rows.push_back(std::move(row));
        }
        json grazing = json::array();
        for (const auto& r : recs)
            if (r.contains("sigma_graze")) {
                const long job = r["job"].get<long>();
                const double other = graze == grazing_line::along_x ? ax.values[static_cast<std::size_t>(job % nx)]
                                                     : ay.values[static_cast<std::size_t>(job / nx)];
                grazing.push_back({other, r["sigma_graze"]});
            }
        const json counts = label_counts(recs);
        summary = {{"command", "map"}, {"x", ax.name}, {"y", ay.name}, {"shape", {ny, nx}},
                   {"x_values", ax.values}, {"y_values", ay.values}, {"label_counts", counts},
                   {"labels", rows}, {"out", c.out ? json(*c.out) : json(nullptr)}};
        if (a.grazing) summary["grazing"] = grazing;
        text = "map " + ax.name + " x " + ay.name + " (" + std::to_string(nx) + " x " + std::to_string(ny) +
               "): " + counts_text(counts) + "\n";
        if (!dir) return;
        write_run(*dir, "map", c, summary, [&](staged_output& out) {
            csv_writer lab(out.file("labels.csv"), {ax.name, ay.name, "label", "period", "impacts", "outcome"});
            for (const auto& r : recs) {
                const long job = r["job"].get<long>();
                lab.text_row({format_double(ax.values[static_cast<std::size_t>(job % nx)]),
                              format_double(ay.values[static_cast<std::size_t>(job / nx)]),
                              r["label"].get<std::string>(), std::to_string(r["period"].get<int>()),
                              std::to_string(r["impacts"].get<long>()), r["outcome"].get<std::string>()});
            }
            lab.close();
            std::vector<std::string> files{"labels.csv"};
            if (a.grazing) {
                csv_writer g(out.file("grazing.csv"), {graze == grazing_line::along_x ? ax.name : ay.name, "sigma_graze"});
                for (const auto& e : grazing)
                    g.row({e[0].get<double>(), e[1].is_number() ? e[1].get<double>() : std::nan("")});
                g.close();
                files.push_back("grazing.csv");
            }
            return files;
        });
        text += "output written to " + *c.out + "\n";
    };
    const auto res = run_job_command(cmd, a.jobs);
    if (res.complete) print(c, summary, text);
    return res.exit_code;
}

// ---------------------------------------------------------------- basins

struct basins_args {
    common_args common;
    job_args jobs;
    std::string x, y;
    double tol = default_period_tolerance;
    double match_tol = attractor_match_options{}.tolerance;
};

json vector_json(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

Eigen::VectorXd vector_from(const json& j)
{
    const auto v = j.get<std::vector<double>>();
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

int run_basins(const basins_args& a)
{
    const run_config c = resolve(a.common);
    const axis ax = parse_axis(a.x, "--x", true), ay = parse_axis(a.y, "--y", true);
    const wake_impact model = c.model();
    const int sx = state_axis_index(model, ax.name, "--x"), sy = state_axis_index(model, ay.name, "--y");
    check_basin_axes(sx, sy, ax.name, input_spelling::cli);
    check_tol(a.tol);
    check_match_tolerance(a.match_tol, input_spelling::cli);
    const long nx = static_cast<long>(ax.values.size()), ny = static_cast<long>(ay.values.size());
    auto ic_of = [&](long job) {
        return basin_start(c.ic, sx, ax.values[static_cast<std::size_t>(job % nx)], sy,
                           ay.values[static_cast<std::size_t>(job / nx)]);
    };

    job_command cmd;
    cmd.spec = {{"command", "basins"}, {"config", c.to_json()}, {"x", a.x}, {"y", a.y}, {"tol", a.tol}, {"match_tol", a.match_tol}};
    cmd.schedule = {nx * ny, 0};
    cmd.out = c.out ? std::optional<fs::path>(*c.out) : std::nullopt;
    cmd.run = [&](long job, const json*) {
        const vec<4> x0 = ic_of(job);
        if (!admissible_start(model, x0)) return json{{"label", "inadmissible"}, {"period", -1}, {"outcome", "none"}};
        const auto r = classify_at(model, x0, c, a.tol);
        const auto sig = signature_of(model, r);
        json rec = label_fields(r);
        json cyc = json::array();
        for (const auto& p : sig.cycle) cyc.push_back(vector_json(p));
        rec["cycle"] = cyc;
        if (sig.lo.size()) {
            rec["lo"] = vector_json(sig.lo);
            rec["hi"] = vector_json(sig.hi);
        }
        return rec;
    };
    json summary;
    std::string text;
    cmd.finish = [&](const std::vector<json>& recs, const fs::path* dir) {
        attractor_catalogue cat({.tolerance = a.match_tol});
        // The signatures back from the records (they went through the journal on a resume).
        std::vector<attractor_signature> sigs(recs.size());
        std::vector<const attractor_signature*> runs(recs.size(), nullptr);
        for (std::size_t k = 0; k < recs.size(); ++k) {
            const auto& r = recs[k];
            if (r["label"] == "inadmissible") continue;
            attractor_signature& s = sigs[k];
            s.label = r["label"].get<std::string>();
            s.period = r["cycle"].empty() ? -1 : r["period"].get<int>();
            for (const auto& p : r["cycle"]) s.cycle.push_back(vector_from(p));
            if (r.contains("lo")) {
                s.lo = vector_from(r["lo"]);
                s.hi = vector_from(r["hi"]);
            }
            runs[k] = &s;
        }
        const std::vector<int> ids = identify_attractors(runs, cat);
        json table = json::array(), labels = json::array();
        for (std::size_t i = 0; i < cat.entries().size(); ++i) {
            const auto& e = cat.entries()[i];
            json pts = json::array();
            for (const auto& p : e.signature.cycle) pts.push_back(vector_json(p));
            table.push_back({{"id", i}, {"label", e.signature.label}, {"cells", e.members}, {"section_points", pts}});
            labels.push_back(e.signature.label);
        }
        const long excluded = std::count(ids.begin(), ids.end(), -1);
        summary = {{"command", "basins"}, {"x", ax.name}, {"y", ay.name}, {"shape", {ny, nx}},
                   {"attractors", {{"count", cat.entries().size()}, {"labels", labels}, {"table", table}}},
                   {"inadmissible_cells", excluded}, {"out", c.out ? json(*c.out) : json(nullptr)}};
        text = std::to_string(cat.entries().size()) + " attractor(s) on the " + std::to_string(nx) + " x " +
               std::to_string(ny) + " grid of initial " + ax.name + ", " + ay.name + ":\n";
        for (const auto& t : table)
            text += "  " + std::to_string(t["id"].get<int>()) + ": " + t["label"].get<std::string>() + ", " +
                    std::to_string(t["cells"].get<long>()) + " cells\n";
        if (excluded) text += "  (" + std::to_string(excluded) + " cells start below the barrier and are excluded)\n";
        if (!dir) return;
        write_run(*dir, "basins", c, summary, [&](staged_output& out) {
            csv_writer cells(out.file("cells.csv"), {ax.name, ay.name, "attractor", "label"});
            for (std::size_t k = 0; k < recs.size(); ++k) {
                const long job = static_cast<long>(k);
                cells.text_row({format_double(ax.values[static_cast<std::size_t>(job % nx)]),
                                format_double(ay.values[static_cast<std::size_t>(job / nx)]),
                                std::to_string(ids[k]), recs[k]["label"].get<std::string>()});
            }
            cells.close();
            return std::vector<std::string>{"cells.csv"};
        });
        text += "output written to " + *c.out + "\n";
    };
    const auto res = run_job_command(cmd, a.jobs);
    if (res.complete) print(c, summary, text);
    return res.exit_code;
}

// ---------------------------------------------------------------- response

struct response_args {
    common_args common;
    job_args jobs;
    std::string param;
    std::string range;
    std::string curves;
    double transient_time = 1000.0;
};

std::vector<std::pair<double, double>> parse_curves(const std::string& text, const wake_impact_parameters& p)
{
    std::vector<std::pair<double, double>> out;
    if (text.empty()) return {{p.A, p.eps}};
    std::size_t start = 0;
    for (;;) {
        const auto comma = text.find(',', start);
        const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        const auto colon = item.find(':');
        if (colon == std::string::npos) throw input_error("--curves item '" + item + "' must be A:eps");
        out.emplace_back(parse_number(item.substr(0, colon), "--curves A"), parse_number(item.substr(colon + 1), "--curves eps"));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return out;
}

int run_response(const response_args& a)
{
    const run_config c = resolve(a.common);
    check_parameter(a.param, "--param");
    check_response_param(a.param, input_spelling::cli);
    const auto values = parse_range(a.range, "--range");
    const auto curves = parse_curves(a.curves, c.params);
    check_transient_time(a.transient_time, input_spelling::cli);
    const long n = static_cast<long>(values.size()), nc = static_cast<long>(curves.size());
    const wake_impact base = c.model();
    for (const auto& [A, eps] : curves) (void)base.with("A", A).with("eps", eps);  // validates

    job_command cmd;
    cmd.spec = {{"command", "response"}, {"config", c.to_json()}, {"param", a.param}, {"range", a.range},
                {"curves", a.curves}, {"transient_time", a.transient_time}};
    cmd.schedule = {n * nc, 0};
    cmd.out = c.out ? std::optional<fs::path>(*c.out) : std::nullopt;
    cmd.run = [&](long job, const json*) {
        const long k = job / n, i = job % n;
        const auto [A, eps] = curves[static_cast<std::size_t>(k)];
        const double v = values[static_cast<std::size_t>(i)];
        const wake_impact m = response_model(base, A, eps, a.param, v);
        const grazing_options go = job_grazing_options(c.protocol().flow.integration, a.transient_time);
        const auto p = with_method(c.method, [&]<template <int> class M>() { return run_response_point<M>(m, c.ic, go); });
        return json{{"curve", k}, {"A", A}, {"eps", eps}, {"value", v},
                    {"amplitude", finite_or_null(p.amplitude)}, {"y_max", finite_or_null(p.y_max)},
                    {"sigma_graze", finite_or_null(p.sigma_graze)}, {"frequency_ratio", finite_or_null(p.frequency_ratio)},
                    {"structure_frequency", p.structure_frequency}, {"converged", p.converged},
                    {"outcome", std::string(to_string(p.status))}};
    };
    json summary;
    std::string text;
    cmd.finish = [&](const std::vector<json>& recs, const fs::path* dir) {
        json cj = json::array();
        for (long k = 0; k < nc; ++k) {
            json amp = json::array(), fr = json::array(), gr = json::array();
            long unconverged = 0;
            for (long i = 0; i < n; ++i) {
                const auto& r = recs[static_cast<std::size_t>(k * n + i)];
                amp.push_back(r["amplitude"]);
                fr.push_back(r["frequency_ratio"]);
                gr.push_back(r["sigma_graze"]);
                unconverged += r["converged"].get<bool>() ? 0 : 1;
            }
            cj.push_back({{"A", curves[static_cast<std::size_t>(k)].first}, {"eps", curves[static_cast<std::size_t>(k)].second},
                          {"values", values}, {"amplitude", amp}, {"frequency_ratio", fr}, {"sigma_graze", gr},
                          {"not_converged", unconverged}});
            text += "A = " + format_double(curves[static_cast<std::size_t>(k)].first) + ", eps = " +
                    format_double(curves[static_cast<std::size_t>(k)].second) + ": peak amplitude " +
                    format_double(*std::max_element(amp.begin(), amp.end(), [](const json& x, const json& y) {
                        return (x.is_number() ? x.get<double>() : -1.0) < (y.is_number() ? y.get<double>() : -1.0);
                    })) + (unconverged ? " (" + std::to_string(unconverged) + " points not converged)" : "") + "\n";
        }
        summary = {{"command", "response"}, {"param", a.param}, {"curves", cj}, {"out", c.out ? json(*c.out) : json(nullptr)}};
        if (!dir) return;
        write_run(*dir, "response", c, summary, [&](staged_output& out) {
            csv_writer w(out.file("response.csv"), {"curve", "A", "eps", a.param, "amplitude", "y_max", "sigma_graze",
                                                    "frequency_ratio", "structure_frequency", "converged"});
            auto num = [](const json& j) { return j.is_number() ? j.get<double>() : std::nan(""); };
            for (const auto& r : recs)
                w.row({r["curve"].get<double>(), r["A"].get<double>(), r["eps"].get<double>(), r["value"].get<double>(),
                       num(r["amplitude"]), num(r["y_max"]), num(r["sigma_graze"]), num(r["frequency_ratio"]),
                       r["structure_frequency"].get<double>(), r["converged"].get<bool>() ? 1.0 : 0.0});
            w.close();
            return std::vector<std::string>{"response.csv"};
        });
        text += "output written to " + *c.out + "\n";
    };
    const auto res = run_job_command(cmd, a.jobs);
    if (res.complete) print(c, summary, text);
    return res.exit_code;
}

}  // namespace

cli_command add_sweep_command(CLI::App& app)
{
    auto a = std::make_shared<sweep_args>();
    auto* s = app.add_subcommand("sweep", "Bifurcation diagram: section points and labels over a range of one parameter");
    add_common_options(*s, a->common);
    add_job_options(*s, a->jobs);
    s->add_option("--param", a->param, "Parameter to vary (Ur, sigma, r, A, eps, ...)")->required();
    s->add_option("--range", a->range, "Values a:b:n (from a to b, n points)")->required();
    s->add_option("--ic-mode", a->ic_mode, "fixed (every point from --ic, the paper's way) or follow (from the previous point's final state)");
    s->add_option("--direction", a->direction, "up, down, or both (both needs --ic-mode follow)");
    s->add_option("--tol", a->tol, "Period tolerance on the section state (default 1e-8)");
    s->add_flag("--grazing", a->grazing, "Also compute the grazing value at each point (drawn on the picture)");
    return {s, [a] { return run_sweep(*a); }};
}

cli_command add_map_command(CLI::App& app)
{
    auto a = std::make_shared<map_args>();
    auto* s = app.add_subcommand("map", "Periodicity map: the label (P0, PN, aperiodic, failure) over a grid of two parameters");
    add_common_options(*s, a->common);
    add_job_options(*s, a->jobs);
    s->add_option("--x", a->x, "Horizontal axis P:a:b:n")->required();
    s->add_option("--y", a->y, "Vertical axis Q:c:d:m")->required();
    s->add_option("--tol", a->tol, "Period tolerance on the section state (default 1e-8; the paper's Fig. 4 used 1e-5)");
    s->add_flag("--grazing", a->grazing, "Draw the grazing line sigma_graze of the other parameter (sigma must be an axis)");
    return {s, [a] { return run_map(*a); }};
}

cli_command add_basins_command(CLI::App& app)
{
    auto a = std::make_shared<basins_args>();
    auto* s = app.add_subcommand("basins", "Basins of attraction over a grid of initial states");
    add_common_options(*s, a->common);
    add_job_options(*s, a->jobs);
    s->add_option("--x", a->x, "Horizontal axis S:a:b:n, S one of y, ydot, x, xdot (the others from --ic)")->required();
    s->add_option("--y", a->y, "Vertical axis T:c:d:m")->required();
    s->add_option("--tol", a->tol, "Period tolerance on the section state (default 1e-8)");
    s->add_option("--match-tol", a->match_tol, "Section points closer than this are the same attractor (default 1e-6)");
    return {s, [a] { return run_basins(*a); }};
}

cli_command add_response_command(CLI::App& app)
{
    auto a = std::make_shared<response_args>();
    auto* s = app.add_subcommand("response", "Barrier-free response (lock-in): amplitude, frequency and grazing value over a range");
    add_common_options(*s, a->common);
    add_job_options(*s, a->jobs);
    s->add_option("--param", a->param, "Parameter to vary (usually Ur)")->required();
    s->add_option("--range", a->range, "Values a:b:n")->required();
    s->add_option("--curves", a->curves, "Several (A, eps) curves: A:eps,A:eps,... (default: the configured A and eps)");
    s->add_option("--transient-time", a->transient_time, "Time discarded before measuring (default 1000)");
    return {s, [a] { return run_response(*a); }};
}

}  // namespace vimpact::cli
