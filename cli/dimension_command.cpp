// The dimension command: the correlation dimension (Grassberger–Procaccia sum or the paper's
// centre counts) of the section points of a run of the model, or of the rows of a CSV file.
// A run's points are its recorded section states, every state variable a coordinate and a
// phase a (cos, sin) pair (state_point_table); --columns chooses among them.
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

#include "commands.hpp"
#include "declared_options.hpp"
#include "interrupts.hpp"
#include "output.hpp"
#include "parse.hpp"
#include "vimpact/analysis/correlation_dimension.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/core/names.hpp"
#include "vimpact/io/build_info.hpp"
#include "vimpact/io/csv_writer.hpp"
#include "vimpact/jobs/job_options.hpp"

namespace fs = std::filesystem;

namespace vimpact::cli {
namespace {

// Without --record (or a config file that sets it), a dimension needs far more points than
// the protocol's 200: the Eckmann–Ruelle bound allows at most 2 log10 N.
constexpr long default_dimension_record = 20000;

struct dimension_args {
    common_args common;
    std::string points_file;
    std::string columns;
    dimension_options options;  // what it declares; the radii, the fit range and the threads here
    std::string radii = "1e-4:0.06:1e-4";
    std::string fit_range;
    int threads = 1;
    double period_tol = default_period_tolerance;
};

std::array<double, 2> parse_fit_range(const std::string& text)
{
    const auto p = split(text, ':');
    if (p.size() != 2) throw input_error("--fit-range '" + text + "' must be r_min:r_max (valid: 0 < r_min < r_max)");
    const double a = parse_number(p[0], "--fit-range r_min");
    const double b = parse_number(p[1], "--fit-range r_max");
    if (!(a > 0.0) || !(b > a))
        throw input_error("--fit-range " + text + ": r_min must be > 0 and < r_max (valid: 0 < r_min < r_max)");
    return {a, b};
}

centre_count_options parse_radii(const std::string& text, centre_count_options o)
{
    const auto p = split(text, ':');
    if (p.size() != 3)
        throw input_error("--radii '" + text + "' must be r_min:r_max:step (valid: 0 < r_min <= r_max, step > 0)");
    o.r_min = parse_number(p[0], "--radii r_min");
    o.r_max = parse_number(p[1], "--radii r_max");
    o.r_step = parse_number(p[2], "--radii step");
    try {
        (void)centre_radii(o);
    } catch (const input_error& e) {
        throw input_error("--radii " + text + ": " + e.what());
    }
    return o;
}

// Everything the user asked for, checked before anything runs or is written.
dimension_options make_options(const dimension_args& a)
{
    dimension_options o = a.options;
    o.centre = parse_radii(a.radii, o.centre);
    o.correlation.threads = resolve_threads(a.threads);
    if (!a.fit_range.empty()) o.scaling.fit_range = parse_fit_range(a.fit_range);
    validate(o);
    check_period_tolerance(a.period_tol);
    return o;
}

// The model's options make no sense with --points: say so rather than ignore them.
void reject_model_options(const CLI::App& app)
{
    for (const char* name : {"--model", "--preset", "--set", "--ic", "--rtol", "--atol", "--hold-band", "--max-step", "--transient",
                             "--record", "--method", "--section", "--tol"})
        if (app.get_option(name)->count() > 0)
            throw input_error(std::string(name) + " configures a run of the model; it cannot be combined with --points");
}

json curve_summary(const dimension_result& r)
{
    const auto& f = r.fit;
    std::uint64_t pairs_lo = 0, pairs_hi = 0;
    if (f.fitted) {
        pairs_lo = r.curve.pairs[f.first];
        pairs_hi = r.curve.pairs[f.last];
    }
    json j = {{"dimension", finite_or_null(f.dimension)},
              {"fit_range", {finite_or_null(f.r_min), finite_or_null(f.r_max)}},
              {"r2", finite_or_null(f.r2)},
              {"slope_error", finite_or_null(f.slope_error)},
              {"slope_spread", finite_or_null(f.slope_spread)},
              {"scaling_region", f.automatic ? (f.found ? "automatic" : "automatic, tolerance not met") : "user"},
              {"scaling_region_found", f.found},
              {"fitted_radii", f.fitted},
              {"pairs_at_fit_range", {pairs_lo, pairs_hi}},
              {"c_at_fit_range", {f.fitted ? finite_or_null(r.curve.c(f.first)) : json(nullptr),
                                  f.fitted ? finite_or_null(r.curve.c(f.last)) : json(nullptr)}},
              {"estimator", std::string(to_string(r.estimator))},
              {"points", r.points},
              {"coordinates", r.embedding},
              {"total_pairs", r.curve.total_pairs},
              {"radii", r.curve.size()}};
    if (r.estimator == dimension_estimator::correlation_sum) {
        j["r_cap"] = finite_or_null(r.r_cap);
        j["all_pairs"] = r.all_pairs;
        j["pairs_below_cap"] = r.curve.pairs.empty() ? 0 : r.curve.pairs.back();
    } else {
        j["centres"] = r.centres;
    }
    return j;
}

void write_curve(const std::filesystem::path& p, const dimension_result& r)
{
    csv_writer w(p, {"r", "C", "pairs", "local_slope", "in_fit"});
    for (std::size_t k = 0; k < r.curve.size(); ++k) {
        const bool in = r.fit.fitted && k >= r.fit.first && k <= r.fit.last;
        w.row({r.curve.r[k], r.curve.c(k), static_cast<double>(r.curve.pairs[k]), r.fit.local_slope[k], in ? 1.0 : 0.0});
    }
    w.close();
}

void write_point_set(const std::filesystem::path& p, const point_set& ps, const std::vector<std::string>& names)
{
    csv_writer w(p, names);
    std::vector<double> row(names.size());
    for (std::size_t i = 0; i < ps.size(); ++i) {
        for (int k = 0; k < ps.dim(); ++k) row[static_cast<std::size_t>(k)] = ps.coordinate(i, k);
        w.row(row);
    }
    w.close();
}

// Rounded for reading (the JSON has every digit); + 0.0 turns -0 into 0.
std::string rounded(double v, double scale) { return format_double(std::round(v * scale) / scale + 0.0); }

std::string text_summary(const dimension_result& r, const std::string& source)
{
    const auto& f = r.fit;
    std::string t = "correlation dimension ";
    t += std::isfinite(f.dimension) ? rounded(f.dimension, 1e4) : std::string("undetermined");
    // The least-squares error understates the uncertainty; the spread of the local slopes
    // over the fit is the honest companion.
    if (std::isfinite(f.slope_error)) {
        t += " (least-squares error " + rounded(f.slope_error, 1e4);
        if (std::isfinite(f.slope_spread)) t += ", local slopes spread " + rounded(f.slope_spread, 1e3);
        t += ")";
    }
    t += "\n" + std::string(to_string(r.estimator)) + " over " + std::to_string(r.points) + " points (" +
         std::to_string(r.embedding) + " coordinates) from " + source + "\n";
    if (f.fitted) {
        t += "fit range r = " + format_double(f.r_min) + " .. " + format_double(f.r_max) + " (" + std::to_string(f.fitted) +
             " radii, ";
        t += f.automatic ? (f.found ? "automatic" : "automatic; NO range met the slope tolerance") : "user";
        t += "), r2 ";
        t += std::isfinite(f.r2) ? rounded(f.r2, 1e6) : std::string("undefined (C constant)");
        t += "\n";
    } else {
        t += "no radii usable for a fit (too few pairs above the floor)\n";
    }
    return t;
}

int run_dimension(const dimension_args& a, const CLI::App& app)
{
    const bool from_file = !a.points_file.empty();
    if (from_file) reject_model_options(app);
    run_config c = resolve(a.common);
    if (from_file && c.config_sets_run)
        throw input_error("config " + a.common.config +
                          " configures a run of the model; it cannot be combined with --points (only a table "
                          "[dimension] can)");
    c.describes_run = !from_file;
    const dimension_options opt = make_options(a);

    point_table table;
    std::vector<std::size_t> cols;
    json source;
    std::optional<simulation> run;
    std::string label;
    if (from_file) {
        try {
            table = read_point_table(a.points_file);
        } catch (const input_error& e) {
            throw input_error(std::string("--points: ") + e.what());
        }
        cols = select_columns(table.header, a.columns, "points file '" + a.points_file + "'");
    } else {
        check_admissible(c);
        // Checked on the names before the run: a wrong --columns costs nothing.
        table = state_point_table(c.info(), state_series(c.model.dim()));
        cols = select_columns(table.header, a.columns, "the section states");
        protocol_options po = c.protocol;
        // The protocol's t_max (1e6) holds about 40 000 section points of the paper's model;
        // long records need longer.
        po.flow.t_max = std::max(po.flow.t_max, 50.0 * static_cast<double>(po.transient_impacts + po.record_points));
        run = simulate(c.model, c.ic, po);
        label = classify_period(c.model, *run, a.period_tol).label;
        table = state_point_table(c.info(), run->points);
    }
    std::vector<std::string> names;
    for (const auto k : cols) names.push_back(table.header[k]);
    const point_set ps = make_point_set(table, cols);
    // Records name the file absolute, as config.toml does: they replay from anywhere.
    const std::string points_path = from_file ? fs::absolute(a.points_file).lexically_normal().string() : "";
    if (from_file)
        source = {{"kind", "file"}, {"file", points_path}, {"columns", names}, {"rows", ps.size()}};
    else
        source = {{"kind", "model"},
                  {"columns", names},
                  {"outcome", std::string(to_string(run->status))},
                  {"label", label},
                  {"period_tolerance", a.period_tol},
                  {"section", c.section_name()},
                  {"record", c.protocol.record_points},
                  {"section_points", run->points.size()},
                  {"t_final", run->stats.t_final}};
    const dimension_result r = correlation_dimension(ps, opt);

    json summary = curve_summary(r);
    summary["command"] = "dimension";
    summary["source"] = source;
    summary["theiler_window"] = opt.theiler_window;
    summary["out"] = out_path(c);
    if (c.out) {
        throw_if_interrupted();  // before anything is written
        staged_output out(*c.out);
        json record;
        if (from_file) {
            record = {{"command", "dimension"},
                      {"version", std::string(version())},
                      {"git_hash", std::string(git_hash())},
                      {"config", {{"points_file", points_path}, {"columns", names}}}};
        } else {
            record = record_header("dimension", c);
        }
        record["options"] = declared_settings(a.options);
        record["options"]["radii"] = a.radii;
        record["options"]["fit_range"] = a.fit_range;
        record["result"] = summary;
        record["files"] = {"points.csv", "correlation.csv"};
        write_point_set(out.file("points.csv"), ps, names);
        write_curve(out.file("correlation.csv"), r);
        if (run) {
            write_states(out.file("sections.csv"), run->points, c.info());
            record["files"].push_back("sections.csv");
        }
        finish_output(out, "dimension", c, record);
    }
    std::string text =
        text_summary(r, from_file ? "'" + a.points_file + "'"
                                  : "a run (" + label + ", outcome " + std::string(to_string(run->status)) + ")");
    if (c.out) text += "output written to " + c.out->string() + "\n";
    print(c, summary, text);
    return 0;
}

}  // namespace

cli_command add_dimension_command(CLI::App& app)
{
    auto a = std::make_shared<dimension_args>();
    a->common.protocol.record_points = default_dimension_record;  // the command's own default, shown by --help
    auto* s = app.add_subcommand("dimension",
                                 "Correlation dimension of the section points of a run (default --record 20000) or of a CSV file");
    add_common_options(*s, a->common);
    s->add_option("--points", a->points_file, "CSV file of points (header line, one point per row) instead of a run");
    s->add_option("--columns", a->columns,
                  "Coordinates used, comma-separated column names (run: every state variable, a phase PHI as PHI_cos, "
                  "PHI_sin; file: all but 't')");
    add_declared_options(*s, a->options);
    s->add_option("--radii", a->radii, "centres estimator: radii r_min:r_max:step (default 1e-4:0.06:1e-4, the paper's)");
    s->add_option("--fit-range", a->fit_range, "Fit over r_min:r_max instead of the automatic scaling region");
    s->add_option("--threads", a->threads, "correlation_sum: threads, 0 = all cores (default 1; same result)");
    add_declared_option(*s, period_tolerance_option, a->period_tol);
    return {s, [a, s] { return run_dimension(*a, *s); }};
}

}  // namespace vimpact::cli
