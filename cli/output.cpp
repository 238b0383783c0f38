#include "output.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>

#include "vimpact/io/build_info.hpp"
#include "vimpact/io/csv_writer.hpp"

namespace vimpact::cli {

json finite_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

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

}  // namespace vimpact::cli
