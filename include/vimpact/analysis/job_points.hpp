#pragma once
// The per-job computations of the job commands (sweep, map, basins, response) and the checks
// of their inputs, written once for every front end: the command line (cli/sweep_commands.cpp)
// and the Python module (python/bindings/). A front end parses its own syntax (ranges a:b:n,
// keyword arguments), runs the jobs through run_jobs (jobs/job_loop.hpp) and formats the
// records; what a job computes, and which inputs are refused with which message, is here.
//
// Messages name an input the way the caller spells it (input_spelling): "--ic-mode" on the
// command line, "ic_mode" in Python; otherwise the text is the same.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vimpact/analysis/attractor.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/jobs/job_loop.hpp"
#include "vimpact/model/forced_impact_oscillator.hpp"
#include "vimpact/model/wake_impact.hpp"

namespace vimpact {

// ---------------------------------------------------------------- naming inputs in messages

enum class input_spelling { cli, python };

// "ic_mode" -> "--ic-mode" (cli) or "ic_mode" (python).
inline std::string input_name(input_spelling s, std::string_view name)
{
    if (s == input_spelling::python) return std::string(name);
    std::string out = "--";
    for (const char ch : name) out += ch == '_' ? '-' : ch;
    return out;
}

// ---------------------------------------------------------------- models by parameter name

inline const auto& parameter_table(const wake_impact&) { return wake_impact_parameter_table(); }
inline const auto& parameter_table(const forced_impact_oscillator&) { return forced_impact_parameter_table(); }

// The model with one parameter changed (validated: throws input_error when out of range).
template <class Model>
Model with_parameter(const Model& m, std::string_view name, double value)
{
    auto p = m.params();
    set_parameter(p, parameter_table(m), name, value);
    return Model(p);
}

// Throws "<what>: unknown parameter 'Q' (valid: ...)" unless `name` is a parameter of the model.
template <class Model>
void check_parameter_name(const Model& m, std::string_view name, const std::string& what)
{
    if (!find_parameter(parameter_table(m), name))
        throw input_error(what + ": unknown parameter '" + std::string(name) + "' (valid: " +
                          parameter_names(parameter_table(m)) + ")");
}

// Names of the state components that can be the axes of a basin grid.
inline std::span<const std::string_view> state_axis_names(const wake_impact&)
{
    static constexpr std::string_view names[] = {"y", "ydot", "x", "xdot"};
    return names;
}
inline std::span<const std::string_view> state_axis_names(const forced_impact_oscillator&)
{
    static constexpr std::string_view names[] = {"y", "ydot", "theta"};
    return names;
}

// Index of a state component by name; throws "<what>: 'z' is not one of y, ydot, x, xdot".
template <class Model>
int state_axis_index(const Model& m, std::string_view name, const std::string& what)
{
    const auto names = state_axis_names(m);
    const auto it = std::find(names.begin(), names.end(), name);
    if (it != names.end()) return static_cast<int>(it - names.begin());
    std::string valid;
    for (const auto& n : names) valid += (valid.empty() ? "" : ", ") + std::string(n);
    throw input_error(what + ": '" + std::string(name) + "' is not one of " + valid);
}

// The initial state a front end uses when none is given: the paper's (y, ydot, x, xdot) =
// (0, 0, 0, 0.1) for the wake model (SPEC section 1); rest at phase 0 for the forced oscillator.
inline vec<4> default_initial_state(const wake_impact&) { return {0.0, 0.0, 0.0, 0.1}; }
inline vec<3> default_initial_state(const forced_impact_oscillator&) { return {0.0, 0.0, 0.0}; }

// A start is admissible when it lies above the barrier, or on it and not moving into it.
template <sticking_model Model>
bool admissible_start(const Model& m, const vec<Model::dim>& x)
{
    return !(m.guard(x) < 0.0 || (m.guard(x) == 0.0 && x[Model::velocity] < 0.0));
}

// ---------------------------------------------------------------- shared checks and options

// The integrator, chosen at run time; with_integration_method calls
// f.template operator()<Method>() for it.
enum class integration_method { dop853, dopri5 };

inline integration_method parse_integration_method(std::string_view text, input_spelling s)
{
    if (text == "dop853") return integration_method::dop853;
    if (text == "dopri5") return integration_method::dopri5;
    throw input_error(input_name(s, "method") + " '" + std::string(text) + "' is not one of dop853, dopri5");
}

template <class F>
decltype(auto) with_integration_method(integration_method m, F&& f)
{
    if (m == integration_method::dopri5) return f.template operator()<dopri5>();
    return f.template operator()<dop853>();
}

inline section_choice parse_section_choice(std::string_view text, input_spelling s)
{
    if (text == "maxima") return section_choice::maxima;
    if (text == "minima") return section_choice::minima;
    if (text == "impacts") return section_choice::impacts;
    throw input_error(input_name(s, "section") + " '" + std::string(text) + "' is not one of maxima, minima, impacts");
}

// The paper's period tolerance for Figures 2 and 5 (Figure 4 used 1e-5).
inline constexpr double default_period_tolerance = 1e-8;

inline void check_period_tolerance(double tol, input_spelling s)
{
    if (!(tol > 0.0) || !std::isfinite(tol))
        throw input_error(input_name(s, "tol") + " must be > 0 (got " + format_double(tol) + ")");
}

// The grazing run inside a job (a sweep's grazing line, a map's, a response point): the
// barrier-free flow at the job's tolerances, never looser than 1e-12, since the grazing
// value is wanted to about 1e-9.
inline grazing_options job_grazing_options(const integrator_options& protocol_integration,
                                           double transient_time = grazing_options{}.transient_time)
{
    grazing_options go;
    go.integration.rtol = std::min(protocol_integration.rtol, 1e-12);
    go.integration.atol = std::min(protocol_integration.atol, 1e-12);
    go.transient_time = transient_time;
    return go;
}

// The tangent (variational) runs of the stability analyses: Newton shooting closes an orbit
// to 1e-11 only if the map is that accurate, so never looser than 1e-12 (the command line's
// rule in cli/stability_commands.cpp, tangent_integration).
inline integrator_options tangent_integration_options(const integrator_options& protocol_integration)
{
    integrator_options io;
    io.rtol = std::min(protocol_integration.rtol, 1e-12);
    io.atol = std::min(protocol_integration.atol, 1e-12);
    return io;
}

// ---------------------------------------------------------------- sweep

enum class sweep_direction { up, down, both };

// Which job is which point: job j of a sweep over n values is value index `index` on branch
// `branch` (0 up, 1 down). Fixed starts: independent jobs in the sweep's direction. Followed
// branches: one chain per direction; with both directions the chains interleave (job 2k is
// the k-th point up, job 2k + 1 the k-th point down), so the two run in parallel.
struct sweep_plan {
    long values = 0;
    bool follow = false;
    sweep_direction direction = sweep_direction::up;

    struct point {
        int branch;
        long index;
    };

    [[nodiscard]] bool both() const { return direction == sweep_direction::both; }
    [[nodiscard]] job_schedule schedule() const
    {
        return {both() ? 2 * values : values, follow ? (both() ? 2 : 1) : 0};
    }
    [[nodiscard]] point at(long job) const
    {
        if (both()) return {static_cast<int>(job % 2), job % 2 == 0 ? job / 2 : values - 1 - job / 2};
        if (direction == sweep_direction::down) return {1, values - 1 - job};
        return {0, job};
    }
};

// ic_mode "fixed" | "follow", direction "up" | "down" | "both" (both needs follow).
inline sweep_plan make_sweep_plan(long values, std::string_view ic_mode, std::string_view direction,
                                  input_spelling s)
{
    if (ic_mode != "fixed" && ic_mode != "follow")
        throw input_error(input_name(s, "ic_mode") + " '" + std::string(ic_mode) + "' is not one of fixed, follow");
    if (direction != "up" && direction != "down" && direction != "both")
        throw input_error(input_name(s, "direction") + " '" + std::string(direction) +
                          "' is not one of up, down, both");
    sweep_plan p;
    p.values = values;
    p.follow = ic_mode == "follow";
    p.direction = direction == "both" ? sweep_direction::both
                  : direction == "down" ? sweep_direction::down
                                        : sweep_direction::up;
    if (!p.follow && p.both())
        throw input_error(input_name(s, "direction") + " both needs " + input_name(s, "ic_mode") +
                          " follow (with fixed starts both directions are the same runs)");
    return p;
}

// Every point must be a valid model; fixed starts must be admissible at every point, a
// followed branch at its first point (continue_from keeps the later ones admissible).
template <sticking_model Model>
void check_sweep_starts(const Model& base, std::string_view param, std::span<const double> values,
                        const vec<Model::dim>& ic, const sweep_plan& plan, input_spelling s)
{
    for (const double v : values) {
        const Model m = with_parameter(base, param, v);
        if (!plan.follow && !admissible_start(m, ic))
            throw input_error("the initial state (y = " + format_double(ic[Model::position]) +
                              ") is below the barrier at " + std::string(param) + " = " + format_double(v) +
                              "; choose " + input_name(s, "ic") + " or a range with y >= sigma");
    }
    if (plan.follow && !values.empty() &&
        !admissible_start(with_parameter(base, param,
                                         plan.direction == sweep_direction::down ? values.back() : values.front()),
                          ic))
        throw input_error("the initial state is below the barrier at the first point of the sweep");
}

// The start of a sweep point: the fixed initial state, or the predecessor's final state
// handed over to this point's model (continue_from).
template <sticking_model Model>
vec<Model::dim> sweep_start(const Model& m, const vec<Model::dim>* previous_final, const vec<Model::dim>& ic)
{
    return previous_final ? continue_from(m, *previous_final) : ic;
}

// ---------------------------------------------------------------- map

// The grazing line of a map is sigma_graze of the parameter that is not sigma; the jobs of
// the first row (sigma on y: one per x value) or the first column compute it.
enum class grazing_line { none, along_x, along_y };

inline void check_map_axes(std::string_view x, std::string_view y, input_spelling s)
{
    if (x == y)
        throw input_error(input_name(s, "x") + " and " + input_name(s, "y") +
                          " must be different parameters (both are " + std::string(x) + ")");
}

inline grazing_line map_grazing_line(bool wanted, std::string_view x, std::string_view y, input_spelling s)
{
    if (!wanted) return grazing_line::none;
    if (y == "sigma") return grazing_line::along_x;
    if (x == "sigma") return grazing_line::along_y;
    throw input_error(input_name(s, "grazing") + " needs sigma as " + input_name(s, "x") + " or " +
                      input_name(s, "y") + " (the line is sigma_graze of the other parameter)");
}

inline bool computes_grazing(grazing_line g, long ix, long iy)
{
    return (g == grazing_line::along_x && iy == 0) || (g == grazing_line::along_y && ix == 0);
}

template <sticking_model Model>
Model map_model(const Model& base, std::string_view x, double xv, std::string_view y, double yv)
{
    return with_parameter(with_parameter(base, x, xv), y, yv);
}

template <sticking_model Model>
void check_map_starts(const Model& base, std::string_view x, std::span<const double> xs, std::string_view y,
                      std::span<const double> ys, const vec<Model::dim>& ic, input_spelling s)
{
    for (const double yv : ys)
        for (const double xv : xs)
            if (!admissible_start(map_model(base, x, xv, y, yv), ic))
                throw input_error("the initial state is below the barrier at " + std::string(x) + " = " +
                                  format_double(xv) + ", " + std::string(y) + " = " + format_double(yv) +
                                  "; choose " + input_name(s, "ic") + " or the ranges");
}

// ---------------------------------------------------------------- basins

inline void check_basin_axes(int sx, int sy, std::string_view x_name, input_spelling s)
{
    if (sx == sy)
        throw input_error(input_name(s, "x") + " and " + input_name(s, "y") +
                          " must be different state components (both are " + std::string(x_name) + ")");
}

inline void check_match_tolerance(double match_tol, input_spelling s)
{
    if (!(match_tol > 0.0)) throw input_error(input_name(s, "match_tol") + " must be > 0");
}

template <int N>
vec<N> basin_start(vec<N> ic, int sx, double xv, int sy, double yv)
{
    ic[sx] = xv;
    ic[sy] = yv;
    return ic;
}

// The attractor signature of a classified run: its label, and the cycle (the period's section
// points) or the bounding box of all recorded section points, in the model's section
// coordinates (attractor.hpp says how two signatures are compared).
template <sticking_model Model>
attractor_signature signature_of(const Model& m, const classified_run<Model::dim>& r)
{
    using coords = decltype(m.section_coordinates(vec<Model::dim>{}));
    std::vector<coords> c;
    c.reserve(r.run.points.size());
    for (const auto& p : r.run.points) c.push_back(m.section_coordinates(p.x));
    return make_signature(r.label.label, r.label.period, c);
}

// Attractor ids in job order: -1 where a cell has no run (null: an inadmissible start),
// otherwise the catalogue's id (first come, first numbered).
inline std::vector<int> identify_attractors(std::span<const attractor_signature* const> cells,
                                            attractor_catalogue& catalogue)
{
    std::vector<int> ids;
    ids.reserve(cells.size());
    for (const auto* s : cells) ids.push_back(s ? catalogue.identify(*s) : -1);
    return ids;
}

// ---------------------------------------------------------------- response

// One point of a lock-in curve: the barrier-free run of the grazing analysis and what it
// measures. amplitude = max |y| = max(|largest maximum|, |smallest minimum|); the frequency
// of y relative to the wake's; the structure's natural frequency delta = 1/(St Ur).
struct response_point {
    double amplitude = std::numeric_limits<double>::quiet_NaN();
    double y_max = std::numeric_limits<double>::quiet_NaN();
    double sigma_graze = std::numeric_limits<double>::quiet_NaN();
    double frequency_ratio = std::numeric_limits<double>::quiet_NaN();
    double structure_frequency = std::numeric_limits<double>::quiet_NaN();
    bool converged = false;
    outcome status = outcome::ok;
    run_stats stats;
};

inline void check_response_param(std::string_view param, input_spelling s)
{
    if (param == "sigma")
        throw input_error(input_name(s, "param") + " sigma: the response is barrier-free, sigma has no effect");
}

inline void check_transient_time(double transient_time, input_spelling s)
{
    if (!(transient_time >= 0.0) || !std::isfinite(transient_time))
        throw input_error(input_name(s, "transient_time") + " must be >= 0");
}

// The model of curve (A, eps) at parameter value v.
inline wake_impact response_model(const wake_impact& base, double A, double eps, std::string_view param, double v)
{
    return base.with("A", A).with("eps", eps).with(param, v);
}

template <template <int> class Method = dop853>
response_point run_response_point(const wake_impact& m, const vec<4>& x0, const grazing_options& go)
{
    const auto g = grazing_value<Method>(m, x0, go);
    response_point r;
    r.amplitude = std::max(std::abs(g.y_max), std::abs(g.sigma_graze));
    r.y_max = g.y_max;
    r.sigma_graze = g.sigma_graze;
    r.frequency_ratio = g.omega;
    r.structure_frequency = m.delta();
    r.converged = g.converged;
    r.status = g.status;
    r.stats = g.stats;
    return r;
}

}  // namespace vimpact
