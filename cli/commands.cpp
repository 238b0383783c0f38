#include "commands.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>

#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/io/build_info.hpp"
#include "vimpact/io/csv_writer.hpp"
#include "vimpact/io/staged_output.hpp"

namespace vimpact::cli {
namespace {

using json = nlohmann::json;

json stats_json(const run_stats& s)
{
    return {{"steps", s.steps},
            {"rejected", s.rejected},
            {"rhs_calls", s.rhs_calls},
            {"impacts", s.impacts},
            {"sections", s.sections},
            {"sticking_phases", s.sticking_phases},
            {"sticking_time", s.sticking_time},
            {"h_min", std::isfinite(s.h_min) ? json(s.h_min) : json(nullptr)},
            {"h_max", s.h_max},
            {"t_final", s.t_final}};
}

// Calls f.template operator()<Method>() for the configured integrator.
template <class F>
decltype(auto) with_method(const std::string& method, F&& f)
{
    if (method == "dopri5") return f.template operator()<dopri5>();
    return f.template operator()<dop853>();
}

json record_header(const char* command, const run_config& c)
{
    json j;
    j["command"] = command;
    j["version"] = std::string(version());
    j["git_hash"] = std::string(git_hash());
    j["config"] = c.to_json();
    return j;
}

void write_json(const std::filesystem::path& p, const json& j)
{
    std::ofstream out(p);
    out << j.dump(2) << '\n';
    if (!out) throw std::runtime_error("cannot write " + p.string());
}

void write_points(const std::filesystem::path& p, const std::vector<timed_state<4>>& pts)
{
    csv_writer w(p, {"t", "y", "ydot", "x", "xdot"});
    for (const auto& s : pts) w.row({s.t, s.x[0], s.x[1], s.x[2], s.x[3]});
    w.close();
}

void write_impacts(const std::filesystem::path& p, const std::vector<impact_event<4>>& imps)
{
    csv_writer w(p, {"t", "y", "ydot_before", "ydot_after", "x", "xdot"});
    for (const auto& e : imps) w.row({e.t, e.pre[0], e.pre[1], e.post[1], e.pre[2], e.pre[3]});
    w.close();
}

// Runs the plotting module of python/vimpact on a staged directory. A missing matplotlib
// is reported, not fatal: the numbers are the result, the picture is a view of them.
bool make_plot(const char* kind, const std::filesystem::path& dir)
{
    const std::string pydir(python_dir());
    const std::string interp(python_interpreter());
    const pid_t pid = ::fork();
    if (pid < 0) return false;
    if (pid == 0) {
        const char* old = std::getenv("PYTHONPATH");
        const std::string path = old && *old ? pydir + ":" + old : pydir;
        ::setenv("PYTHONPATH", path.c_str(), 1);
        ::setenv("MPLBACKEND", "Agg", 1);
        const int stderr_copy = ::dup(2);
        ::dup2(stderr_copy, 1);  // keep stdout clean for --json
        std::string d = dir.string();
        const char* argv[] = {interp.c_str(), "-m", "vimpact.plot", kind, d.c_str(), nullptr};
        ::execv(interp.c_str(), const_cast<char* const*>(argv));
        std::_Exit(127);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

void finish_output(staged_output& out, const char* kind, const run_config& c, json& record)
{
    const auto record_path = out.file("run.json");
    write_json(record_path, record);  // the plot reads it
    if (c.plot) {
        if (make_plot(kind, out.staging_dir())) {
            record["files"].push_back("plot.png");
            write_json(record_path, record);
        } else {
            std::cerr << "vimpact: warning: the PNG could not be made (python3 with matplotlib needed)\n";
        }
    }
    out.commit();
}

void print(const run_config& c, const json& summary, const std::string& text)
{
    if (c.json) std::cout << summary.dump() << '\n';
    else std::cout << text;
}

}  // namespace

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

}  // namespace vimpact::cli
