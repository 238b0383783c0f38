#include "output.hpp"
#include "interrupts.hpp"
#include "parse.hpp"
#include "replay.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>

#include "vimpact/analysis/period.hpp"
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

void append(std::vector<std::string>& to, const std::vector<std::string>& more)
{
    to.insert(to.end(), more.begin(), more.end());
}

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

void null_keys(json& summary, std::initializer_list<const char*> keys)
{
    for (const char* k : keys) summary[k] = nullptr;
}

json out_path(const run_config& c) { return c.out ? json(c.out->string()) : json(nullptr); }

json model_json(const vimpact::model& m)
{
    const auto& info = m.info();
    json surfaces = json::array(), sections = json::array(), switches = json::array(), state = json::array(),
         parameters = json::object();
    for (const auto& s : info.surfaces) surfaces.push_back(s.name);
    for (const auto& s : info.sections) sections.push_back(s.name);
    for (const auto& s : info.switches) switches.push_back(s.name);
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
            {"sections", sections},
            {"switches", switches}};
}

json si_json(const si_input& in, const vimpact::model& m)
{
    json inputs = json::object(), parameters = json::object(), values = json::object();
    for (const auto& [name, v] : si_inputs(in)) inputs[name] = v;
    for (const auto& [i, v] : si_parameters(m, in)) parameters[m.info().parameters[static_cast<std::size_t>(i)].name] = v;
    for (const auto& [name, v] : si_values(in, m)) values[name] = finite_or_null(v);
    return {{"inputs", inputs}, {"parameters", parameters}, {"values", values}, {"warnings", validity_warnings(in, m)}};
}

std::string statistics_text(const impact_statistics& s, bool si, bool per_metre)
{
    const auto num = [](double v) { return std::isfinite(v) ? format_double(v) : std::string("-"); };
    const std::string per = per_metre ? "/m" : "";
    std::string t = "impacts " + std::to_string(s.impacts) + " in " + num(s.duration) + (si ? " s" : "") + ", rate " +
                    num(s.rate) + (si ? " Hz" : " per unit t");
    if (s.impacts > 0)
        t += ", velocity mean " + num(s.velocity_mean) + " max " + num(s.velocity_max) + (si ? " m/s" : "") +
             ", energy per impact " + num(s.energy_per_impact) + (si ? " J" + per : "") + ", power " + num(s.power) +
             (si ? " W" + per : "");
    t += ", contact " + num(s.contact_fraction) + ", excursion " + num(s.excursion) + (si ? " m" : "");
    return t + "\n";
}

void add_si_summary(json& summary, const run_config& c, const vimpact::model& m)
{
    if (!c.si) return;
    const json si = si_json(*c.si, m);
    const si_tables tables = *si_tables_of(c, m);
    summary["si"] = {{"values", si["values"]},
                     {"warnings", si["warnings"]},
                     {"columns",
                      {{"states", si_columns_json(tables, m, false)}, {"impacts", si_columns_json(tables, m, true)}}}};
}

std::string add_si_results(json& summary, const run_config& c, const vimpact::model& m, const impact_statistics& s)
{
    if (!c.si) return {};
    add_si_summary(summary, c, m);
    const impact_statistics k = in_si(s, scales_at(*c.si, m));
    summary["impact_statistics_si"] = summary_json(k, m.info());
    return "in SI: " + statistics_text(k, true, c.si->cylinder.has_value());
}

std::vector<std::string> si_statistics_columns()
{
    std::vector<std::string> out;
    for (const char* name : impact_statistics_names()) out.push_back(std::string(name) + "_si");
    return out;
}

std::string counts_text(const json& counts)
{
    std::vector<std::string> labels;
    for (const auto& [k, v] : counts.items()) labels.push_back(k);
    std::sort(labels.begin(), labels.end(), [](const std::string& a, const std::string& b) { return label_before(a, b); });
    std::vector<std::string> parts;
    for (const auto& l : labels) parts.push_back(l + " " + std::to_string(counts[l].get<long>()));
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

std::optional<si_tables> si_tables_of(const run_config& c, const vimpact::model& m)
{
    if (!c.si) return std::nullopt;
    return si_tables{.scales = scales_at(*c.si, m),
                     .dimensions = state_dimensions(m),
                     .energy_unit = c.si->cylinder ? "J/m" : "J"};
}

namespace {

// The columns among `columns` that have an SI value: (index, dimension).
std::vector<std::pair<std::size_t, physical_dimension>> dimensioned(const std::vector<impact_column>& columns,
                                                                    const si_tables& si)
{
    std::vector<std::pair<std::size_t, physical_dimension>> out;
    for (std::size_t k = 0; k < columns.size(); ++k)
        if (const auto d = si.dimensions.at(static_cast<std::size_t>(columns[k].variable)); d != physical_dimension::none)
            out.emplace_back(k, d);
    return out;
}

// A table of states as columns: each variable once, under its name.
std::vector<impact_column> plain_columns(const model_info& info)
{
    std::vector<impact_column> out;
    for (const auto& name : state_columns(info)) out.push_back({name, static_cast<int>(out.size()), false});
    return out;
}

}  // namespace

json si_columns_json(const si_tables& si, const vimpact::model& m, bool impacts)
{
    json j = json::object();
    j["t_si"] = "s";
    const auto columns = impacts ? impact_columns(m) : plain_columns(m.info());
    for (const auto& [k, d] : dimensioned(columns, si)) j[columns[k].name + "_si"] = std::string(si_unit(d));
    if (!impacts) return j;
    j["normal_velocity_si"] = "m/s";
    j["rebound_velocity_si"] = "m/s";
    j["energy_si"] = si.energy_unit;
    return j;
}

std::vector<std::string> state_si_columns(const si_tables& si, const model_info& info)
{
    const auto columns = plain_columns(info);
    std::vector<std::string> out;
    for (const auto& [k, d] : dimensioned(columns, si)) out.push_back(columns[k].name + "_si");
    return out;
}

void append_state_si(std::vector<double>& row, const si_tables& si, const Eigen::Ref<const Eigen::VectorXd>& x)
{
    for (std::size_t k = 0; k < si.dimensions.size(); ++k)
        if (si.dimensions[k] != physical_dimension::none) row.push_back(x[static_cast<Eigen::Index>(k)] * si.scales.of(si.dimensions[k]));
}

void write_states(const std::filesystem::path& p, const state_series& s, const model_info& info, const si_tables* si)
{
    std::vector<std::string> header{"t"};
    for (const auto& name : state_columns(info)) header.push_back(name);
    const auto columns = plain_columns(info);
    const auto in_si = si ? dimensioned(columns, *si) : std::vector<std::pair<std::size_t, physical_dimension>>{};
    if (si) {
        header.emplace_back("t_si");
        for (const auto& [k, d] : in_si) header.push_back(columns[k].name + "_si");
    }
    csv_writer w(p, header);
    std::vector<double> row(header.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
        row[0] = s.t(i);
        for (int k = 0; k < s.dim(); ++k) row[static_cast<std::size_t>(k) + 1] = s.x(i, k);
        if (si) {
            std::size_t at = static_cast<std::size_t>(s.dim()) + 1;
            row[at++] = s.t(i) * si->scales.time;
            for (const auto& [k, d] : in_si) row[at++] = s.x(i, static_cast<int>(k)) * si->scales.of(d);
        }
        w.row(row);
    }
    w.close();
}

void write_impacts(const std::filesystem::path& p, const impact_series& s, const vimpact::model& m, const si_tables* si)
{
    const auto columns = impact_columns(m);
    std::vector<std::string> header{"t"};
    for (const auto& c : columns) header.push_back(c.name);
    header.emplace_back("surface");
    for (const char* name : {"normal_velocity", "rebound_velocity", "energy"}) header.emplace_back(name);
    const auto in_si = si ? dimensioned(columns, *si) : std::vector<std::pair<std::size_t, physical_dimension>>{};
    if (si) {
        header.emplace_back("t_si");
        for (const auto& [k, d] : in_si) header.push_back(columns[k].name + "_si");
        for (const char* name : {"normal_velocity_si", "rebound_velocity_si", "energy_si"}) header.emplace_back(name);
    }
    csv_writer w(p, header);
    const auto velocities = impact_velocities(m, s);
    std::vector<std::string> cells;
    for (std::size_t i = 0; i < s.size(); ++i) {
        const auto value = [&](std::size_t k) { return (columns[k].after ? s.post : s.pre).x(i, columns[k].variable); };
        cells = {format_double(s.pre.t(i))};
        for (std::size_t k = 0; k < columns.size(); ++k) cells.push_back(format_double(value(k)));
        cells.push_back(m.info().surfaces.at(static_cast<std::size_t>(s.surface[i])).name);
        for (const double v : {velocities[i].normal, velocities[i].rebound, velocities[i].energy})
            cells.push_back(format_double(v));
        if (si) {
            const physical_scales& k = si->scales;
            cells.push_back(format_double(s.pre.t(i) * k.time));
            for (const auto& [c, d] : in_si) cells.push_back(format_double(value(c) * k.of(d)));
            for (const double v : {velocities[i].normal * k.velocity(), velocities[i].rebound * k.velocity(),
                                   velocities[i].energy * k.energy()})
                cells.push_back(format_double(v));
        }
        w.text_row(cells);
    }
    w.close();
}

void write_switchings(const std::filesystem::path& p, const impact_series& s, const model_info& info)
{
    std::vector<std::string> header{"t"};
    for (const auto& v : info.state) header.push_back(v.name);
    for (const auto& v : info.state) header.push_back(v.name + "_after");
    header.emplace_back("switch");
    csv_writer w(p, header);
    std::vector<std::string> cells;
    for (std::size_t i = 0; i < s.size(); ++i) {
        cells = {format_double(s.pre.t(i))};
        for (const auto* side : {&s.pre, &s.post})
            for (int j = 0; j < info.dim(); ++j) cells.push_back(format_double(side->x(i, j)));
        cells.push_back(info.switches.at(static_cast<std::size_t>(s.surface[i])).name);
        w.text_row(cells);
    }
    w.close();
}

namespace {

// The plotting program: the package from the directory given (argv[1]), never from the
// working directory or the environment, which -I leaves out of sys.path.
constexpr const char* plot_program =
    "import sys\n"
    "d = sys.argv.pop(1)\n"
    "if d: sys.path.insert(0, d)\n"
    "from vimpact.plot import main\n"
    "sys.exit(main(sys.argv))\n";

// What a failed picture's output says, in one line: the last non-empty line (a Python
// traceback ends with the exception and its message), without control characters.
std::string last_line(const std::string& text)
{
    std::string line;
    for (const auto& l : split(text, '\n'))
        if (l.find_first_not_of(" \t\r") != std::string::npos) line = l;
    std::string clean;
    for (const char ch : line)
        if (static_cast<unsigned char>(ch) >= 0x20 && ch != 0x7f) clean += ch;
    const auto first = clean.find_first_not_of(' ');
    return first == std::string::npos ? std::string() : clean.substr(first);
}

}  // namespace

std::optional<std::string> make_plot(const std::string& kind, const std::filesystem::path& dir, const std::string& format)
{
    const std::string pydir(python_dir());
    const std::string interp(python_interpreter());
    std::error_code ec;
    const std::string d = std::filesystem::absolute(dir, ec).string();
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return "cannot make a pipe: " + std::string(std::strerror(errno));
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        return "cannot start a process: " + std::string(std::strerror(errno));
    }
    if (pid == 0) {
        ::setenv("MPLBACKEND", "Agg", 1);
        // The results' own directory: nothing of the caller's (a matplotlibrc there) is read.
        if (::chdir(d.c_str()) != 0) std::_Exit(126);
        ::dup2(fds[1], 1);  // stdout stays clean for --json
        ::dup2(fds[1], 2);
        const char* argv[] = {interp.c_str(), "-I", "-c", plot_program, pydir.c_str(), kind.c_str(), d.c_str(),
                              format.c_str(), nullptr};
        ::execv(interp.c_str(), const_cast<char* const*>(argv));
        std::_Exit(127);
    }
    ::close(fds[1]);
    // Only the end is kept: that is where Python says what failed.
    constexpr std::size_t keep = 64 * 1024;
    std::string output;
    char buf[4096];
    for (;;) {
        const ssize_t n = ::read(fds[0], buf, sizeof buf);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        output.append(buf, static_cast<std::size_t>(n));
        if (output.size() > 2 * keep) output.erase(0, output.size() - keep);
    }
    ::close(fds[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
        std::cerr << output;  // its warnings, as they were
        return std::nullopt;
    }
    const std::string program = interp + " -m vimpact.plot " + kind;
    if (WIFSIGNALED(status)) return program + " was killed by signal " + std::to_string(WTERMSIG(status));
    if (WEXITSTATUS(status) == 127) return "cannot run " + interp;
    const std::string why = last_line(output);
    return program + " failed" + (why.empty() ? std::string() : ": " + why);
}

std::string unsettled_text(long unsettled)
{
    if (unsettled == 0) return {};
    return "warning: " + std::to_string(unsettled) +
           " run(s) not settled: still converging over the record, or periodic only in its last half (lengthen "
           "--transient)\n";
}

void finish_output(staged_output& out, const std::string& kind, const run_config& c, json& record)
{
    if (!record.contains("files")) record["files"] = json::array();
    record["files"].push_back("run.json");
    // The picture that draws this directory: python3 -m vimpact.plot KIND DIR redraws it.
    if (!kind.empty()) record["plot"] = kind;
    write_replay_config(out.file("config.toml"), c);
    record["files"].push_back("config.toml");
    const auto record_path = out.file("run.json");
    write_json(record_path, record);  // the plot reads it
    if (c.plot && !kind.empty()) {
        if (const auto failure = make_plot(kind, out.staging_dir(), c.plot_format); !failure) {
            record["files"].push_back("plot." + c.plot_format);
            write_json(record_path, record);
        } else {
            throw_if_interrupted();  // the picture was cut short by Ctrl-C, not failed
            std::cerr << "vimpact: warning: the picture could not be made (" << *failure << "); the results are written to "
                      << (c.out ? c.out->string() : out.staging_dir().string()) << " (--no-plot: no picture)\n";
        }
    }
    throw_if_interrupted();  // results of interrupted runs are not committed (exit 130)
    out.commit();
}

staged_output* streamed_output::get()
{
    if (!m_config.out) return nullptr;
    // Also after Ctrl-C or SIGTERM: a stopped run still hands over the results that finished
    // before it stopped (the job loop delivers them), and the command then reports the stop
    // with the journal that keeps them; the staging directory goes without a commit.
    if (!m_out) m_out.emplace(*m_config.out);
    return &*m_out;
}

std::string streamed_output::commit(const std::string& command, const std::string& plot, const json& summary)
{
    staged_output& out = *get();
    json record = record_header(command, m_config);
    record["result"] = summary;
    record["files"] = json::array();
    json schemas = json::object();
    for (streamed_table* t : m_tables) {
        t->open().close();
        record["files"].push_back(t->m_file);
        if (!t->m_schema.is_null()) schemas[t->m_file] = t->m_schema;
    }
    if (!schemas.empty()) record["tables"] = schemas;
    finish_output(out, plot, m_config, record);
    return "output written to " + m_config.out->string() + "\n";
}

int streamed_output::finish(job_session& session, const std::string& command, const std::string& plot,
                            const json& summary, std::string text)
{
    if (m_config.out) {
        text += commit(command, plot, summary);
        session.finish();
    }
    print(m_config, summary, text);
    return 0;
}

streamed_table::streamed_table(streamed_output& out, std::string file, std::vector<std::string> header, json schema)
    : m_out(out), m_file(std::move(file)), m_header(std::move(header)), m_schema(std::move(schema))
{
    m_out.m_tables.push_back(this);
}

csv_writer& streamed_table::open()
{
    if (!m_csv) m_csv.emplace(m_out.get()->file(m_file), m_header);
    return *m_csv;
}

json table_schema(const std::vector<std::string>& lead, const std::vector<column_schema>& columns,
                  const std::vector<std::string>& trail)
{
    json cols = json::array();
    for (const auto& name : lead) cols.push_back({{"name", name}});
    for (const auto& c : columns) {
        json j = {{"name", c.name}, {"field", c.field}, {"type", c.type}, {"meaning", c.meaning}, {"unit", c.unit}};
        if (!c.group.empty()) j["group"] = c.group;
        if (c.surface >= 0) j["surface"] = c.surface;
        if (c.state >= 0) j["state"] = c.state;
        if (c.switch_index >= 0) j["switch"] = c.switch_index;
        cols.push_back(std::move(j));
    }
    for (const auto& name : trail) cols.push_back({{"name", name}});
    return {{"columns", cols}};
}

json series_schema(const std::string& field, const std::string& records,
                   const std::vector<std::pair<std::string, std::string>>& keys, const std::vector<std::string>& states,
                   const std::vector<std::string>& extra)
{
    json cols = json::array();
    for (const auto& [name, key] : keys) cols.push_back({{"name", name}, {"key", key}});
    for (std::size_t k = 0; k < states.size(); ++k) cols.push_back({{"name", states[k]}, {"field", field}, {"state", k}});
    for (const auto& name : extra) cols.push_back({{"name", name}});
    return {{"series", field}, {"records", records}, {"columns", cols}};
}

json spectrum_schema(const std::string& field, const std::string& records,
                     const std::vector<std::pair<std::string, std::string>>& keys, int width,
                     const std::vector<std::string>& extra)
{
    json cols = json::array();
    for (const auto& [name, key] : keys) cols.push_back({{"name", name}, {"key", key}});
    for (const char* name : {"index", "re", "im"}) cols.push_back({{"name", name}, {"field", field}, {"part", name}});
    for (const auto& name : extra) cols.push_back({{"name", name}});
    return {{"spectrum", field}, {"records", records}, {"width", width}, {"columns", cols}};
}

json label_tally::counts() const
{
    json j = json::object();
    for (const auto& [k, v] : m_counts) j[k] = v;
    return j;
}

void print(const run_config& c, const json& summary, const std::string& text)
{
    // Without --out a run cut short by Ctrl-C has no result to report. With --out, DIR was
    // committed before this report (and a many-job run's journal removed): a Ctrl-C or SIGTERM
    // from then on came too late to stop anything, and "interrupted; nothing written" with
    // exit 130 would send the user to resume a run whose journal is gone.
    if (!c.out) throw_if_interrupted();
    if (c.json) std::cout << summary.dump() << '\n';
    else std::cout << text;
}

}  // namespace vimpact::cli
