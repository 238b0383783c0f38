// The continue command: numerical continuation of periodic orbits (stable and unstable) in one
// parameter, their bifurcations, branch switching at period doublings, and the curves of
// bifurcation points in a second parameter (docs/continuation.md). One library call each;
// optionally the brute-force diagram or map beside it, for the picture.
#include <algorithm>
#include <cmath>
#include <memory>

#include "commands.hpp"
#include "declared_options.hpp"
#include "interrupts.hpp"
#include "output.hpp"
#include "parse.hpp"
#include "vimpact/analysis/bifurcation_curve.hpp"
#include "vimpact/analysis/continuation.hpp"
#include "vimpact/analysis/map.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/integrate/tangent_integration.hpp"
#include "vimpact/io/continuation_json.hpp"
#include "vimpact/io/csv_writer.hpp"
#include "vimpact/io/state_columns.hpp"
#include "vimpact/model/model_phrases.hpp"
#include "vimpact/physical/si_units.hpp"

namespace vimpact::cli {
namespace {

struct continue_args {
    common_args common;
    std::string param, range;
    continuation_options options;  // what it declares; the rest from the arguments here
    std::string ics;
    std::string param2, range2;
    std::string curve_types = "fold,period_doubling,grazing";
    long diagram = 0;
    std::string map;
    int threads = 0;
    CLI::Option* curves_option = nullptr;
};

// "a:b": the range of a continued parameter.
std::pair<double, double> parse_interval(const std::string& text, const std::string& what)
{
    const auto parts = split(text, ':');
    if (parts.size() != 2) throw input_error(what + " '" + text + "' must be a:b (from a towards b)");
    const double a = parse_number(parts[0], what), b = parse_number(parts[1], what);
    if (a == b) throw input_error(what + " '" + text + "' is empty: a must differ from b");
    return {a, b};
}

value_grid as_grid(std::pair<double, double> interval) { return std::vector<double>{interval.first, interval.second}; }

// With --si and the parameter an SI quantity: " (U = 4 m/s)" for its value v, else empty.
std::string si_text(const run_config& c, const axis_values& axis, double v)
{
    if (!axis.si()) return {};
    return " (" + axis.si_name + " = " + format_double(axis.si_at(c, v)) + (axis.si_name == "U" ? " m/s)" : " m)");
}

std::string orbit_name(int returns) { return "P" + std::to_string(returns); }

std::string mu_text(const std::vector<std::complex<double>>& mu)
{
    std::string t;
    for (const auto& m : mu) {
        if (!t.empty()) t += ", ";
        t += format_double(m.real());
        if (m.imag() != 0.0) t += (m.imag() < 0 ? " - " : " + ") + format_double(std::abs(m.imag())) + "i";
    }
    return t;
}

// Columns of the multipliers: mu0_re, mu0_im, ... (mu0 the trivial one).
std::vector<std::string> multiplier_columns(int dim)
{
    std::vector<std::string> h;
    for (int i = 0; i < dim; ++i) {
        h.push_back("mu" + std::to_string(i) + "_re");
        h.push_back("mu" + std::to_string(i) + "_im");
    }
    return h;
}

void push_multipliers(std::vector<double>& row, const std::vector<std::complex<double>>& mu, int dim)
{
    for (int i = 0; i < dim; ++i) {
        const bool have = i < static_cast<int>(mu.size());
        row.push_back(have ? mu[static_cast<std::size_t>(i)].real() : std::nan(""));
        row.push_back(have ? mu[static_cast<std::size_t>(i)].imag() : std::nan(""));
    }
}

void push_state(std::vector<double>& row, const Eigen::VectorXd& x)
{
    for (Eigen::Index k = 0; k < x.size(); ++k) row.push_back(x[k]);
}

std::vector<bifurcation_type> parse_types(const std::string& text)
{
    std::vector<bifurcation_type> types;
    for (const auto& name : split(text, ',')) {
        const bifurcation_type t = parse_name(name, std::array{bifurcation_type::fold, bifurcation_type::period_doubling,
                                                               bifurcation_type::grazing},
                                              "--curves");
        if (std::find(types.begin(), types.end(), t) == types.end()) types.push_back(t);
    }
    return types;
}

int run_continue(const continue_args& a)
{
    run_config c = resolve(a.common);
    const model& m = c.model;
    const auto& info = c.info();
    if (a.param.empty() || a.range.empty()) throw input_error("continue needs --param P and --range a:b");
    continuation_options o = a.options;
    // With --si the parameter may be U [m/s] or gap [m], the range in SI.
    const axis_values axis = resolve_axis(c, a.param, as_grid(parse_interval(a.range, "--range")), "--param");
    o.parameter = axis.parameter;
    o.start = axis.values.front();
    o.end = axis.values.back();
    o.protocol = c.protocol;
    check_options(o);  // before anything runs
    o.from_attractor = o.returns == 0;
    o.arclength.integration = tangent_integration(c.protocol.flow.integration);
    o.cancel = &interrupt_flag();
    const model m0 = m.with_parameter(o.parameter, o.start);
    warn_validity(c, {m0, m.with_parameter(o.parameter, o.end)});
    std::vector<Eigen::VectorXd> starts{c.ic};
    if (!a.ics.empty())
        for (const auto& s : split(a.ics, ';')) {
            const auto x = parse_numbers(s, "--ics");
            check_state_size(m, static_cast<Eigen::Index>(x.size()), "--ics");
            starts.emplace_back(Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size())));
        }
    for (const auto& x : starts)
        if (const int s = violated_surface(m0, x); s >= 0)
            throw input_error("initial state lies beyond surface " + info.surfaces[static_cast<std::size_t>(s)].name +
                              " at " + a.param + " = " + format_double(axis.si() ? axis.si_values.front() : o.start));
    const bool two = !a.param2.empty() || !a.range2.empty();
    curve_options co;
    axis_values axis2;
    if (two) {
        if (a.param2.empty() || a.range2.empty()) throw input_error("--param2 needs --range2 c:d, and --range2 needs --param2");
        axis2 = resolve_axis(c, a.param2, as_grid(parse_interval(a.range2, "--range2")), "--param2");
        co.parameter2 = axis2.parameter;
        co.lo2 = axis2.values.front();
        co.hi2 = axis2.values.back();
        if (co.lo2 > co.hi2) std::swap(co.lo2, co.hi2);
        co.types = parse_types(a.curve_types);
        co.arclength = o.arclength;
        // The curves start at the model's value of the second parameter: with --si, that and
        // the range are metres or m/s to the user, and the refusal says so in them.
        if (axis2.si() && !second_parameter_in_range(m, co)) {
            const double q = m.parameters()[static_cast<std::size_t>(co.parameter2)];
            const std::string unit = axis2.si_name == "U" ? "m/s" : "m";
            throw input_error("--range2 " + a.range2 + " (" + axis2.si_name + ", " + unit + ") does not hold the run's " +
                              axis2.si_name + " = " + format_double(axis2.si_at(c, q)) + " " + unit +
                              " (set by --si or the model's default), where the curves start: give a range around it");
        }
        validate(m, o, co);
    } else {
        if (a.curves_option->count() > 0)
            throw input_error("--curves chooses the curves of --param2: give --param2 Q and --range2 c:d with it");
        validate(m, o);
    }
    if (a.diagram < 0 || a.diagram > 100000) throw input_error("--diagram must be in [0, 100000] (got " + std::to_string(a.diagram) + ")");
    if (a.diagram > 0 && !c.out)
        throw input_error("--diagram N draws the brute-force diagram in the picture of --out DIR: give --out");
    if (!a.map.empty() && !two) throw input_error("--map NX,NY draws the brute-force map under the curves of --param2");
    if (!a.map.empty() && !c.out)
        throw input_error("--map NX,NY draws the brute-force map in the picture of --out DIR: give --out");
    long map_nx = 0, map_ny = 0;
    if (!a.map.empty()) {
        const auto n = split(a.map, ',');
        if (n.size() != 2) throw input_error("--map '" + a.map + "' must be NX,NY (cells along --param and --param2)");
        map_nx = parse_count(n[0], "--map");
        map_ny = parse_count(n[1], "--map");
        if (map_nx < 2 || map_ny < 2 || map_nx * map_ny > 1'000'000)
            throw input_error("--map needs 2 <= NX, NY and NX * NY <= 1000000 (got " + a.map + ")");
    }

    const continuation_result r = continuation(m, starts, o, a.threads);
    throw_if_interrupted();
    std::vector<bifurcation_curve> curves;
    if (two && r.status == outcome::ok) curves = continue_bifurcations(m, r, o, co, a.threads);
    throw_if_interrupted();
    const std::string& pname = info.parameters[static_cast<std::size_t>(o.parameter)].name;
    const std::string pname2 = two ? info.parameters[static_cast<std::size_t>(co.parameter2)].name : std::string();

    std::string text = "continuation of " + pname + " from " + format_double(o.start) + si_text(c, axis, o.start) +
                       " towards " + format_double(o.end) + si_text(c, axis, o.end) + " (start: " +
                       (o.from_attractor ? "the attractor, " + r.start_label : "a point of " + orbit_name(o.returns)) +
                       ")\n";
    if (r.status != outcome::ok)
        text += "no branch: " + std::string(to_string(r.status)) +
                (r.status == outcome::aperiodic ? " (no periodic attractor at the start; give --period K and a point "
                                                  "near the orbit with --ic)"
                                                : "") +
                "\n";
    for (std::size_t b = 0; b < r.branches.size(); ++b) {
        const auto& br = r.branches[b];
        long stable = 0;
        double lo = INFINITY, hi = -INFINITY;
        for (const auto& p : br.points) {
            stable += p.stable;
            lo = std::min(lo, p.parameter);
            hi = std::max(hi, p.parameter);
        }
        text += "branch " + std::to_string(b) + ": " + orbit_name(br.returns) + " (" + std::to_string(br.returns) +
                " section return(s))" +
                (br.parent >= 0 ? ", switched from branch " + std::to_string(br.parent) + " at bifurcation " +
                                      std::to_string(br.origin)
                                : "") +
                ", " + std::to_string(br.points.size()) + " points over " + pname + " " + format_double(lo) + " .. " +
                format_double(hi) + ": " + std::to_string(stable) + " stable, " +
                std::to_string(static_cast<long>(br.points.size()) - stable) + " unstable; ends: " + end_reason(br, pname) + "\n";
    }
    if (!r.bifurcations.empty()) text += "bifurcations:\n";
    for (std::size_t i = 0; i < r.bifurcations.size(); ++i) {
        const auto& bf = r.bifurcations[i];
        text += "  " + std::to_string(i) + ": " + std::string(to_string(bf.type)) +
                (bf.surface >= 0 ? " (" + info.surfaces[static_cast<std::size_t>(bf.surface)].name + ")" : "") +
                (bf.switch_surface >= 0 ? " (switch " + info.switches[static_cast<std::size_t>(bf.switch_surface)].name + ")"
                                        : "") +
                " at " +
                pname + " = " + format_double(bf.parameter) + si_text(c, axis, bf.parameter) +
                (bf.located ? "" : " (not located to the tolerance)") +
                " on branch " + std::to_string(bf.branch);
        if (bf.switch_surface >= 0)
            text += ", crossings per period " + std::to_string(bf.crossings_before) + " -> " +
                    std::to_string(bf.crossings_after);
        else if (bf.type == bifurcation_type::grazing)
            text += ", impacts per period " + std::to_string(bf.sequence_before.size()) + " -> " +
                    std::to_string(bf.sequence_after.size());
        else
            text += ", multipliers " + mu_text(bf.point.section_multipliers);
        text += "\n";
    }
    for (std::size_t i = 0; i < curves.size(); ++i) {
        const auto& cv = curves[i];
        text += "curve " + std::to_string(i) + " of bifurcation " + std::to_string(cv.origin) + " (" +
                std::string(to_string(cv.type)) +
                (cv.switch_surface >= 0 ? " of switch " + info.switches[static_cast<std::size_t>(cv.switch_surface)].name
                                        : std::string()) +
                ") in (" + pname + ", " + pname2 + "): " +
                std::to_string(cv.points.size()) + " points";
        if (!cv.points.empty())
            text += ", " + pname2 + " " + format_double(cv.points.front().parameter2) + " .. " +
                    format_double(cv.points.back().parameter2) + "; ends " + std::string(to_string(cv.end_backward)) +
                    ", " + std::string(to_string(cv.end_forward));
        if (cv.failure != outcome::ok) text += " (" + std::string(to_string(cv.failure)) + ")";
        text += "\n";
    }
    json summary = two ? continuation_json(m, o, r, co, curves) : continuation_json(m, o, r);
    summary["command"] = "continue";
    summary["out"] = out_path(c);
    if (c.si) {
        // The SI value of an SI parameter beside its model value: param_si at every point,
        // bifurcation and curve point (param2_si for --param2).
        summary["si"] = si_json(*c.si, m);
        const auto put = [&](json& at, const char* key, const axis_values& ax) {
            if (ax.si()) at[std::string(key) + "_si"] = finite_or_null(ax.si_at(c, at[key].get<double>()));
        };
        if (axis.si()) summary["si_param"] = axis.si_name;
        if (axis2.si()) summary["si_param2"] = axis2.si_name;
        for (auto& branch : summary["branches"])
            for (auto& p : branch) put(p, "param", axis);
        for (auto& bf : summary["bifurcations"]) put(bf, "param", axis);
        if (two)
            for (auto& cv : summary["curves"])
                for (auto& p : cv["points"]) {
                    put(p, "param", axis);
                    put(p, "param2", axis2);
                }
    }

    if (c.out) {
        // The brute-force picture underneath, with the same protocol and starting state.
        std::optional<sweep_result> diagram;
        std::optional<map_result> bmap;
        std::vector<double> map_x, map_y;
        job_options jo;
        jo.threads = a.threads;
        jo.stop = &interrupt_flag();
        if (a.diagram > 0) {
            sweep_options so;
            so.parameter = o.parameter;
            so.values = value_grid::range(std::min(o.start, o.end), std::max(o.start, o.end), a.diagram);
            so.initial_state = c.ic;
            so.protocol = c.protocol;
            so.period_tolerance = o.period_tolerance;
            diagram = sweep(m, so, jo);
        }
        if (map_nx > 0) {
            map_options mo;
            map_x = grid_values(std::min(o.start, o.end), std::max(o.start, o.end), map_nx);
            map_y = grid_values(co.lo2, co.hi2, map_ny);
            mo.x = {o.parameter, map_x};
            mo.y = {co.parameter2, map_y};
            mo.initial_state = c.ic;
            mo.protocol = c.protocol;
            mo.period_tolerance = o.period_tolerance;
            bmap = map2d(m, mo, jo);
        }
        throw_if_interrupted();
        const int dim = m.dim();
        write_run(c, "continue", "continuation", summary, [&](staged_output& out) {
            json files = json::array({"branches.csv", "sections.csv", "bifurcations.csv"});
            std::vector<std::string> bh{"branch", "point", pname, "stable", "period", "impacts"};
            for (const auto& col : record_columns<period_label>(table_context_for(info, "", -1)))
                if (col.surface >= 0) bh.push_back(col.name);  // impacts_SURFACE, as the label names them
            bh.push_back("closure");
            bh.push_back("arclength");
            for (const auto& n : state_columns(info)) bh.push_back(n);
            for (const auto& n : multiplier_columns(dim)) bh.push_back(n);
            if (axis.si()) bh.push_back(axis.si_name);  // the parameter in SI, last
            // With --si the state in SI at each point's own scales (a cylinder's follow U).
            const auto tables_at = [&](double value) { return si_tables_of(c, m.with_parameter(o.parameter, value)); };
            const auto si0 = tables_at(o.start);
            if (si0) append(bh, state_si_columns(*si0, info));
            csv_writer bw(out.file("branches.csv"), bh);
            std::vector<std::string> sh{"branch", "point", "return", pname, "stable"};
            for (const auto& n : state_columns(info)) sh.push_back(n);
            if (axis.si()) sh.push_back(axis.si_name);
            if (si0) append(sh, state_si_columns(*si0, info));
            csv_writer sw(out.file("sections.csv"), sh);
            for (std::size_t b = 0; b < r.branches.size(); ++b)
                for (std::size_t k = 0; k < r.branches[b].points.size(); ++k) {
                    const auto& p = r.branches[b].points[k];
                    std::vector<double> row{static_cast<double>(b), static_cast<double>(k), p.parameter,
                                            p.stable ? 1.0 : 0.0, p.period, static_cast<double>(p.impacts())};
                    for (std::size_t s = 0; s < info.surfaces.size(); ++s)
                        row.push_back(s < p.impacts_by_surface.size() ? static_cast<double>(p.impacts_by_surface[s]) : 0.0);
                    row.push_back(p.closure);
                    row.push_back(p.arclength);
                    push_state(row, p.state);
                    push_multipliers(row, p.multipliers, dim);
                    if (axis.si()) row.push_back(axis.si_at(c, p.parameter));
                    const auto si = si0 ? tables_at(p.parameter) : std::nullopt;
                    if (si) append_state_si(row, *si, p.state);
                    bw.row(row);
                    for (std::size_t j = 0; j < p.section_points.size(); ++j) {
                        std::vector<double> srow{static_cast<double>(b), static_cast<double>(k), static_cast<double>(j),
                                                 p.parameter, p.stable ? 1.0 : 0.0};
                        push_state(srow, p.section_points.x(j));
                        if (axis.si()) srow.push_back(axis.si_at(c, p.parameter));
                        if (si) append_state_si(srow, *si, p.section_points.x(j));
                        sw.row(srow);
                    }
                }
            bw.close();
            sw.close();
            std::vector<std::string> fh{"index", "type", "branch", "after_point", pname, "located", "bracket", "surface",
                                        "switch", "period"};
            for (const auto& n : state_columns(info)) fh.push_back(n);
            for (const auto& n : multiplier_columns(dim)) fh.push_back(n);
            if (axis.si()) fh.push_back(axis.si_name);
            csv_writer fw(out.file("bifurcations.csv"), fh);
            for (std::size_t i = 0; i < r.bifurcations.size(); ++i) {
                const auto& bf = r.bifurcations[i];
                std::vector<std::string> row{std::to_string(i),
                                             std::string(to_string(bf.type)),
                                             std::to_string(bf.branch),
                                             std::to_string(bf.after_point),
                                             format_double(bf.parameter),
                                             bf.located ? "1" : "0",
                                             format_double(bf.bracket),
                                             bf.surface >= 0 ? info.surfaces[static_cast<std::size_t>(bf.surface)].name : "",
                                             bf.switch_surface >= 0
                                                 ? info.switches[static_cast<std::size_t>(bf.switch_surface)].name
                                                 : "",
                                             format_double(bf.point.period)};
                for (Eigen::Index k = 0; k < bf.point.state.size(); ++k) row.push_back(format_double(bf.point.state[k]));
                std::vector<double> mu;
                push_multipliers(mu, bf.point.multipliers, dim);
                for (const double v : mu) row.push_back(format_double(v));
                if (axis.si()) row.push_back(format_double(axis.si_at(c, bf.parameter)));
                fw.text_row(row);
            }
            fw.close();
            if (two) {
                std::vector<std::string> ch{"curve", "origin", "type", "point", pname, pname2, "period", "closure",
                                            "condition"};
                for (const auto& n : state_columns(info)) ch.push_back(n);
                for (const auto& n : multiplier_columns(dim)) ch.push_back(n);
                if (axis.si()) ch.push_back(axis.si_name);
                if (axis2.si()) ch.push_back(axis2.si_name);
                csv_writer cw(out.file("curves.csv"), ch);
                for (std::size_t i = 0; i < curves.size(); ++i)
                    for (std::size_t k = 0; k < curves[i].points.size(); ++k) {
                        const auto& p = curves[i].points[k];
                        std::vector<std::string> row{std::to_string(i), std::to_string(curves[i].origin),
                                                     std::string(to_string(curves[i].type)), std::to_string(k),
                                                     format_double(p.parameter), format_double(p.parameter2),
                                                     format_double(p.period), format_double(p.closure),
                                                     format_double(p.condition)};
                        for (Eigen::Index j = 0; j < p.state.size(); ++j) row.push_back(format_double(p.state[j]));
                        std::vector<double> mu;
                        push_multipliers(mu, p.multipliers, dim);
                        for (const double v : mu) row.push_back(format_double(v));
                        if (axis.si()) row.push_back(format_double(axis.si_at(c, p.parameter)));
                        if (axis2.si()) row.push_back(format_double(axis2.si_at(c, p.parameter2)));
                        cw.text_row(row);
                    }
                cw.close();
                files.push_back("curves.csv");
            }
            if (diagram) {
                std::vector<std::string> dh{pname, "label"};
                for (const auto& n : state_columns(info)) dh.push_back(n);
                if (axis.si()) dh.push_back(axis.si_name);
                if (si0) append(dh, state_si_columns(*si0, info));
                csv_writer dw(out.file("diagram.csv"), dh);
                for (const auto& p : diagram->points) {
                    const auto si = si0 ? tables_at(p.value) : std::nullopt;
                    for (std::size_t i = 0; i < p.points.size(); ++i) {
                        std::vector<std::string> row{format_double(p.value), p.label.label};
                        for (int k = 0; k < p.points.dim(); ++k) row.push_back(format_double(p.points.x(i, k)));
                        if (axis.si()) row.push_back(format_double(axis.si_at(c, p.value)));
                        if (si) {
                            std::vector<double> v;
                            append_state_si(v, *si, p.points.x(i));
                            for (const double x : v) row.push_back(format_double(x));
                        }
                        dw.text_row(row);
                    }
                }
                dw.close();
                files.push_back("diagram.csv");
            }
            if (bmap) {
                csv_writer mw(out.file("map.csv"), {pname, pname2, "label"});
                for (std::size_t j = 0; j < map_y.size(); ++j)
                    for (std::size_t i = 0; i < map_x.size(); ++i)
                        mw.text_row({format_double(map_x[i]), format_double(map_y[j]),
                                     bmap->cells[i + map_x.size() * j].label.label});
                mw.close();
                files.push_back("map.csv");
            }
            return files;
        });
        text += "output written to " + c.out->string() + "\n";
    }
    print(c, summary, text);
    return 0;
}

}  // namespace

cli_command add_continue_command(CLI::App& app)
{
    auto a = std::make_shared<continue_args>();
    auto* s = app.add_subcommand(
        "continue",
        "Continuation of periodic orbits in one parameter, stable and unstable (pseudo-arclength on the section "
        "map), with folds, period doublings, Neimark-Sacker and grazing points located; branch switching at "
        "period doublings; curves of bifurcation points in a second parameter (--param2)");
    add_common_options(*s, a->common);
    add_si_option(*s, a->common);
    s->add_option("--param", a->param, "The parameter to continue in (with --si also U [m/s] or gap [m])")->required();
    s->add_option("--range", a->range, "a:b: the branch starts at a (the attractor there, or --period) and runs towards b; "
                                      "it ends where the parameter leaves [a, b]")
        ->required();
    s->add_option("--ics", a->ics, "Further initial states, ';'-separated, each like --ic: a branch from each");
    s->add_option("--param2", a->param2, "Two-parameter mode: follow each located bifurcation in this parameter too");
    s->add_option("--range2", a->range2, "c:d: the range of --param2 (the model's value of it must lie inside)");
    a->curves_option = s->add_option(
        "--curves", a->curve_types,
        "With --param2: the bifurcation types followed, comma-separated (default fold,period_doubling,grazing)");
    // ds, as AUTO names the arclength step; --max-step is the integrator's, as in every command.
    add_declared_options(*s, a->options);
    s->add_option("--diagram", a->diagram,
                  "With --out: also the brute-force bifurcation diagram at N values (fixed starts from --ic), drawn "
                  "under the branches");
    s->add_option("--map", a->map, "With --out and --param2: also the brute-force periodicity map NX,NY under the curves");
    s->add_option("--threads", a->threads, "Worker threads for starts, switched branches and curves (0: every core)");
    return {s, [a] { return run_continue(*a); }};
}

}  // namespace vimpact::cli
