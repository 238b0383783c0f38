#pragma once
// What every command shares when it reports: JSON pieces, the run record (run.json), CSV
// files of states and impacts named by the model, the PNG made by `python3 -m vimpact.plot`,
// and stdout.
#include <filesystem>
#include <initializer_list>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>


#include "common_options.hpp"
#include "interrupts.hpp"
#include "job_runner.hpp"
#include "vimpact/analysis/impact_statistics.hpp"
#include "vimpact/core/state_series.hpp"
#include "vimpact/hybrid/run_stats.hpp"
#include "vimpact/io/csv_writer.hpp"
#include "vimpact/io/record_table.hpp"
#include "vimpact/io/staged_output.hpp"
#include "vimpact/io/summary_json.hpp"

namespace vimpact::cli {

using json = nlohmann::json;

json vector_json(const Eigen::VectorXd& v);
json matrix_json(const Eigen::MatrixXd& m);

// A result's summary is summary_json of its record (vimpact/io/summary_json.hpp) and what the
// command adds. Sets `keys` of a summary to null: values a result does not have (a period without a
// periodic orbit).
void null_keys(json& summary, std::initializer_list<const char*> keys);
// A summary's "out": --out DIR, or null without it.
json out_path(const run_config& c);
// The model as run: name, source, identity, parameter values by name, state, surface and
// section names, and the meaning and unit of every state variable and parameter (the
// pictures' axis labels).
json model_json(const vimpact::model& m);

// The SI inputs of a run and what they give at the model `m`: `inputs` (by key, defaults
// filled in), `parameters` (the model's dimensionless values they set), `values` (U, Re,
// mass_ratio, gap and the scales: si_values) and `warnings`.
json si_json(const si_input& in, const vimpact::model& m);
// One line on the impact statistics for the text output, in the model's units, or in SI
// (`si`: per metre of a cylinder's length when `per_metre`).
std::string statistics_text(const impact_statistics& s, bool si = false, bool per_metre = false);
// With --si: summary["si"] of a run of `m`: si_json's values and warnings, and `columns`, the
// SI columns of its tables of states and of impacts with their units (si_columns_json).
void add_si_summary(json& summary, const run_config& c, const vimpact::model& m);
// With --si: add_si_summary and summary["impact_statistics_si"] of a run of `m`; returns the
// text line in SI (empty without --si).
std::string add_si_results(json& summary, const run_config& c, const vimpact::model& m, const impact_statistics& s);
// The SI columns of sweep and map tables: the statistics' names with the suffix _si.
std::vector<std::string> si_statistics_columns();

// The text of label counts (label_tally::counts): "P1 3, P2 4".
std::string counts_text(const json& counts);

// run.json's common part: command, version, git hash, the model, the state names and the
// variable the pictures show first, the configuration, and the picture's options when the
// command has any.
json record_header(const std::string& command, const run_config& c);
void write_json(const std::filesystem::path& p, const json& j);

// With --si, what a run's state tables add in SI: the model's scales at the run's parameters
// and which state variables are displacements and velocities (physical/state_dimensions.hpp).
struct si_tables {
    physical_scales scales;
    std::vector<physical_dimension> dimensions;
    std::string energy_unit;  // J, or J/m for a cylinder (per metre of its length)
};
std::optional<si_tables> si_tables_of(const run_config& c, const vimpact::model& m);
// The SI columns those tables get, with their units: t_si (s), NAME_si of each displacement
// (m) and velocity (m/s); with `impacts`, those of the impact columns and normal_velocity_si,
// rebound_velocity_si (m/s) and energy_si.
json si_columns_json(const si_tables& si, const vimpact::model& m, bool impacts);

// A state's displacements and velocities in SI beside the model's values in the tables of a
// sweep or a continuation, whose points each have their own parameters (a cylinder's velocity
// scale follows U): the NAME_si columns, and one state's values at the scales of `si`
// (si_tables_of the model at that point).
std::vector<std::string> state_si_columns(const si_tables& si, const model_info& info);
void append_state_si(std::vector<double>& row, const si_tables& si, const Eigen::Ref<const Eigen::VectorXd>& x);

// t and one column per state variable; with `si`, then t_si and NAME_si of each displacement
// and velocity.
void write_states(const std::filesystem::path& p, const state_series& s, const model_info& info,
                  const si_tables* si = nullptr);
// t, the impact columns of the model (io/state_columns.hpp), the surface's name, and each
// impact's normal_velocity, rebound_velocity and energy (analysis/impact_statistics.hpp); with
// `si`, then t_si, the impact columns' NAME_si of each displacement and velocity,
// normal_velocity_si, rebound_velocity_si and energy_si.
void write_impacts(const std::filesystem::path& p, const impact_series& s, const vimpact::model& m,
                   const si_tables* si = nullptr);

// The crossings of switching surfaces: t, the state before (each variable's name) and after
// (NAME_after: a reset's image, else the same), and the switch's name.
void write_switchings(const std::filesystem::path& p, const impact_series& s, const model_info& info);

// Draws DIR's picture with vimpact.plot (KIND DIR FORMAT: png, pdf, svg) in an isolated
// interpreter (-I: no module of the working directory, no PYTHON* variables; the package from
// the build's python directory) started in DIR. Returns what failed, in one line, or nothing
// when the picture was made. A failure is reported, not fatal: the numbers are the result,
// the picture is a view of them.
std::optional<std::string> make_plot(const std::string& kind, const std::filesystem::path& dir,
                                     const std::string& format);

// Writes run.json and config.toml (record["files"] gets them, and the picture when made),
// makes the picture of `kind` (none for an empty kind) unless --no-plot, and commits the
// directory.
void finish_output(staged_output& out, const std::string& kind, const run_config& c, json& record);

// Writes --out DIR: the files `write(out)` makes (it returns their names), run.json with the
// summary as its result (`command` names the run there) and the PNG of `plot`.
template <class Write>
void write_run(const run_config& c, const std::string& command, const std::string& plot, const json& summary,
               Write&& write)
{
    throw_if_interrupted();  // before anything is written
    staged_output out(*c.out);
    json record = record_header(command, c);
    record["result"] = summary;
    record["files"] = write(out);
    finish_output(out, plot, c, record);
}
template <class Write>
void write_run(const run_config& c, const std::string& kind, const json& summary, Write&& write)
{
    write_run(c, kind, kind, summary, std::forward<Write>(write));
}

class streamed_table;

// --out DIR of a many-job run, filled while its results stream in job order (the library's
// job_stream): the staging directory is made at the first row of one of its tables, so a
// shard that does not complete the run and the MPI ranks other than 0 write nothing, and the
// tables are written row by row, so memory does not grow with the number of jobs. Without
// commit() (a stop, an error) nothing is written.
class streamed_output {
public:
    explicit streamed_output(const run_config& c) : m_config(c) {}
    // The staging directory, made on the first call; null without --out.
    staged_output* get();
    // Closes the tables (a table without rows keeps its header), writes run.json (the summary
    // as its result, the tables and the standard files), config.toml and the picture of
    // `plot`, and commits DIR. Returns the text output's line saying where.
    std::string commit(const std::string& command, const std::string& plot, const json& summary);
    // The end of a complete many-job run: with --out, DIR committed (commit) and the journal
    // removed; then the summary or the text printed. Returns the exit code, 0.
    int finish(job_session& session, const std::string& command, const std::string& plot, const json& summary,
               std::string text);

private:
    friend class streamed_table;
    const run_config& m_config;
    std::optional<staged_output> m_out;
    std::vector<streamed_table*> m_tables;  // in the order run.json's `files` lists them
};

// A CSV file of a streamed run, opened at its first row (streamed_output); run.json's
// `tables` describes it with `schema` (table_schema, series_schema, spectrum_schema; null:
// not described).
class streamed_table {
public:
    streamed_table(streamed_output& out, std::string file, std::vector<std::string> header, json schema);
    streamed_table(const streamed_table&) = delete;  // the stream keeps its address
    streamed_table& operator=(const streamed_table&) = delete;
    void row(const std::vector<double>& cells) { open().row(cells); }
    void text_row(const std::vector<std::string>& cells) { open().text_row(cells); }

private:
    friend class streamed_output;
    csv_writer& open();
    streamed_output& m_out;
    std::string m_file;
    std::vector<std::string> m_header;
    json m_schema;
    std::optional<csv_writer> m_csv;
};

// run.json's description of a table's columns: the `lead` ones a command puts first (a
// cell's parameter values) and the `trail` ones it adds (SI values), by name only, around
// the record's (what each holds).
json table_schema(const std::vector<std::string>& lead, const std::vector<column_schema>& columns,
                  const std::vector<std::string>& trail);

// run.json's description of a table of a series field of records (their section points):
// per row, the `keys` columns (name, field) that say which record the point belongs to (the
// records are in `records`, in order), then the state columns, then the `extra` ones.
json series_schema(const std::string& field, const std::string& records,
                   const std::vector<std::pair<std::string, std::string>>& keys, const std::vector<std::string>& states,
                   const std::vector<std::string>& extra);

// run.json's description of a table of a spectrum field of records (their multipliers): per
// row, the `keys` columns, then index, re and im of one value (at most `width` per record),
// then the `extra` ones.
json spectrum_schema(const std::string& field, const std::string& records,
                     const std::vector<std::pair<std::string, std::string>>& keys, int width,
                     const std::vector<std::string>& extra);

// A streamed table of records of type R, one row each (io/record_table.hpp), between the
// `lead` and `trail` columns of the command.
template <class R>
class record_table {
public:
    record_table(streamed_output& out, const std::string& file, table_context context, std::vector<std::string> lead,
                 std::vector<std::string> trail)
        : m_context(std::move(context)), m_table(out, file, header(lead, trail), schema(lead, trail))
    {
    }
    void row(const std::vector<std::string>& lead, const R& r, const std::vector<std::string>& trail)
    {
        std::vector<std::string> cells = lead;
        const auto mine = record_cells(r, m_context);
        cells.insert(cells.end(), mine.begin(), mine.end());
        cells.insert(cells.end(), trail.begin(), trail.end());
        m_table.text_row(cells);
    }
    // Lead and trail columns that are numbers (parameter values, SI values).
    void row(const std::vector<double>& lead, const R& r, const std::vector<double>& trail)
    {
        row(texts(lead), r, texts(trail));
    }

private:
    std::vector<std::string> header(std::vector<std::string> lead, const std::vector<std::string>& trail) const
    {
        for (const auto& c : record_columns<R>(m_context)) lead.push_back(c.name);
        lead.insert(lead.end(), trail.begin(), trail.end());
        return lead;
    }
    json schema(const std::vector<std::string>& lead, const std::vector<std::string>& trail) const
    {
        return table_schema(lead, record_columns<R>(m_context), trail);
    }
    static std::vector<std::string> texts(const std::vector<double>& values)
    {
        std::vector<std::string> out;
        for (const double v : values) out.push_back(format_double(v));
        return out;
    }
    table_context m_context;
    streamed_table m_table;
};

// Labels counted as results stream: label -> count.
class label_tally {
public:
    void add(const std::string& label) { ++m_counts[label]; }
    [[nodiscard]] json counts() const;

private:
    std::map<std::string, long> m_counts;
};

// The warning of runs whose record has not settled (period_label::settled: still converging
// onto a periodic orbit, or periodic only in its last half), a line for the text output;
// empty when all settled.
std::string unsettled_text(long unsettled);

// --json: the summary on one line; otherwise the text.
void print(const run_config& c, const json& summary, const std::string& text);

std::string join(const std::vector<std::string>& items, const std::string& sep = ", ");
void append(std::vector<std::string>& to, const std::vector<std::string>& more);

}  // namespace vimpact::cli
