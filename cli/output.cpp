#include "output.hpp"
#include "interrupts.hpp"
#include "replay.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>

#include "vimpact/core/format.hpp"
#include "vimpact/io/build_info.hpp"
#include "vimpact/io/csv_writer.hpp"
#include "vimpact/io/state_columns.hpp"

namespace vimpact::cli {

std::string join(const std::vector<std::string>& items, const std::string& sep)
{
    std::string s;
    for (std::size_t i = 0; i < items.size(); ++i) {
        if (i) s += sep;
        s += items[i];
    }
    return s;
}

json finite_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json vector_json(const Eigen::VectorXd& v)
{
    json j = json::array();
    for (Eigen::Index i = 0; i < v.size(); ++i) j.push_back(finite_or_null(v[i]));
    return j;
}

json matrix_json(const Eigen::MatrixXd& m)
{
    json rows = json::array();
    for (Eigen::Index i = 0; i < m.rows(); ++i) {
        json row = json::array();
        for (Eigen::Index k = 0; k < m.cols(); ++k) row.push_back(finite_or_null(m(i, k)));
        rows.push_back(std::move(row));
    }
    return rows;
}

json by_surface(const std::vector<long>& counts, const model_info& info)
{
    json j = json::object();
    for (std::size_t i = 0; i < info.surfaces.size(); ++i) j[info.surfaces[i].name] = i < counts.size() ? counts[i] : 0L;
    return j;
}

json stats_json(const run_stats& s, const model_info& info)
{
    return {{"steps", s.steps},
            {"rejected", s.rejected},
            {"rhs_calls", s.rhs_calls},
            {"impacts", s.impacts},
            {"impacts_by_surface", by_surface(s.impacts_by_surface, info)},
            {"sections", s.sections},
            {"sticking_phases", s.sticking_phases},
            {"sticking_time", s.sticking_time},
            {"h_min", finite_or_null(s.h_min)},
            {"h_max", s.h_max},
            {"t_final", s.t_final}};
}

json model_json(const vimpact::model& m)
{
    const auto& info = m.info();
    json surfaces = json::array(), sections = json::array(), state = json::array(), parameters = json::object();
    for (const auto& s : info.surfaces) surfaces.push_back(s.name);
    for (const auto& s : info.sections) sections.push_back(s.name);
    for (const auto& v : info.state) state.push_back({{"name", v.name}, {"meaning", v.meaning}, {"unit", v.unit}});
    for (const auto& p : info.parameters) parameters[p.name] = {{"meaning", p.meaning}, {"unit", p.unit}};
    return {{"name", info.name},
            {"source", info.source},
            {"identity", info.identity},
            {"parameters", parameters_json(m)},
            {"state_names", state_columns(info)},
            {"state_info", state},
            {"parameter_info", parameters},
            {"surfaces", surfaces},
            {"sections", sections}};
}

json label_counts(const std::vector<std::string>& labels)
{
    std::map<std::string, long> counts;
    for (const auto& l : labels) ++counts[l];
    json j = json::object();
    for (const auto& [k, v] : counts) j[k] = v;
    return j;
}

std::string counts_text(const json& counts)
{
    std::vector<std::string> parts;
    for (const auto& [k, v] : counts.items()) parts.push_back(k + " " + std::to_string(v.get<long>()));
    return join(parts);
}

json record_header(const std::string& command, const run_config& c)
{
    json j;
    j["command"] = command;
    j["version"] = std::string(version());
    j["git_hash"] = std::string(git_hash());
    j["model"] = model_json(c.model);
    j["state_names"] = state_columns(c.info());
    j["plot_variable"] = c.info().state.front().name;
    j["config"] = c.to_json();
    if (!c.plot_options.empty()) j["plot_options"] = c.plot_options;
    return j;
}

void write_json(const std::filesystem::path& p, const json& j)
{
    std::ofstream out(p);
    out << j.dump(2) << '\n';
    if (!out) throw std::runtime_error("cannot write " + p.string());
}

void write_states(const std::filesystem::path& p, const state_series& s, const model_info& info)
{
    std::vector<std::string> header{"t"};
    for (const auto& name : state_columns(info)) header.push_back(name);
    csv_writer w(p, header);
    std::vector<double> row(header.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
        row[0] = s.t(i);
        for (int k = 0; k < s.dim(); ++k) row[static_cast<std::size_t>(k) + 1] = s.x(i, k);
        w.row(row);
    }
    w.close();
}

void write_impacts(const std::filesystem::path& p, const impact_series& s, const vimpact::model& m)
{
    const auto columns = impact_columns(m);
    std::vector<std::string> header{"t"};
    for (const auto& c : columns) header.push_back(c.name);
    header.emplace_back("surface");
    csv_writer w(p, header);
    std::vector<std::string> cells(header.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
        cells[0] = format_double(s.pre.t(i));
        for (std::size_t k = 0; k < columns.size(); ++k)
            cells[k + 1] = format_double((columns[k].after ? s.post : s.pre).x(i, columns[k].variable));
        cells.back() = m.info().surfaces.at(static_cast<std::size_t>(s.surface[i])).name;
        w.text_row(cells);
    }
    w.close();
}

bool make_plot(const std::string& kind, const std::filesystem::path& dir, const std::string& format)
{
    const std::string pydir(python_dir());
    const std::string interp(python_interpreter());
    const pid_t pid = ::fork();
    if (pid < 0) return false;
    if (pid == 0) {
        if (!pydir.empty()) {
            const char* old = std::getenv("PYTHONPATH");
            std::string path = pydir;
            if (old && *old) {
                path += ":";
                path += old;
            }
            ::setenv("PYTHONPATH", path.c_str(), 1);
        }
        ::setenv("MPLBACKEND", "Agg", 1);
        ::dup2(2, 1);  // keep stdout clean for --json
        const std::string d = dir.string();
        const char* argv[] = {interp.c_str(), "-m", "vimpact.plot", kind.c_str(), d.c_str(), format.c_str(), nullptr};
        ::execv(interp.c_str(), const_cast<char* const*>(argv));
        std::_Exit(127);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

std::string unsettled_text(long unsettled)
{
    if (unsettled == 0) return {};
    return "warning: " + std::to_string(unsettled) +
           " run(s) not settled: aperiodic over the record but periodic in its last half (lengthen --transient)\n";
}

std::vector<std::string> impact_count_columns(const model_info& info)
{
    std::vector<std::string> out;
    for (const auto& s : info.surfaces) out.push_back("impacts_" + s.name);
    return out;
}

void finish_output(staged_output& out, const std::string& kind, const run_config& c, json& record)
{
    if (!record.contains("files")) record["files"] = json::array();
    record["files"].push_back("run.json");
    write_replay_config(out.file("config.toml"), c);
    record["files"].push_back("config.toml");
    const auto record_path = out.file("run.json");
    write_json(record_path, record);  // the plot reads it
    if (c.plot && !kind.empty()) {
        if (make_plot(kind, out.staging_dir(), c.plot_format)) {
            record["files"].push_back("plot." + c.plot_format);
            write_json(record_path, record);
        } else {
            throw_if_interrupted();  // the picture was cut short by Ctrl-C, not failed
            std::cerr << "vimpact: warning: the picture could not be made (python3 -m vimpact.plot " << kind
                      << " failed; the results are written)\n";
        }
    }
    throw_if_interrupted();  // results of interrupted runs are not committed (exit 130)
    out.commit();
}

staged_output* streamed_output::get()
{
    if (!m_config.out) return nullptr;
    if (!m_out) {
        throw_if_interrupted();  // before anything is written
        m_out.emplace(*m_config.out);
    }
    return &*m_out;
}

void streamed_output::commit(const std::string& command, const std::string& plot, const json& summary, json files)
{
    staged_output& out = *get();
    json record = record_header(command, m_config);
    record["result"] = summary;
    record["files"] = std::move(files);
    finish_output(out, plot, m_config, record);
}

json label_tally::counts() const
{
    json j = json::object();
    for (const auto& [k, v] : m_counts) j[k] = v;
    return j;
}

void print(const run_config& c, const json& summary, const std::string& text)
{
    throw_if_interrupted();  // a run cut short by Ctrl-C has no result to report
    if (c.json) std::cout << summary.dump() << '\n';
    else std::cout << text;
}

}  // namespace vimpact::cli
