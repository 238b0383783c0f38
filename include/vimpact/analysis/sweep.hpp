#pragma once
// Bifurcation diagrams: the protocol and its period label at every value of one parameter.
//
// Starts: fixed (every point from the same initial state, the paper's way) or followed (each
// point from the final state of the previous one, continue_from below, so that a branch is
// followed up and down; with direction both, the two branches run in parallel). Optionally the
// grazing value of a parameter that moves the surfaces, per surface and per switch, at every
// point.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "vimpact/core/names.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/value_grid.hpp"
#include "vimpact/jobs/job_options.hpp"

namespace vimpact {

enum class sweep_direction { up, down, both };

constexpr std::string_view to_string(sweep_direction d)
{
    switch (d) {
        case sweep_direction::up: return "up";
        case sweep_direction::down: return "down";
        case sweep_direction::both: return "both";
    }
    return "unknown";
}
inline constexpr std::array<sweep_direction, 3> all_sweep_directions{sweep_direction::up, sweep_direction::down,
                                                                    sweep_direction::both};

// Where each point starts: fixed (every point from the same initial state) or follow (from
// the final state of the previous point).
enum class sweep_start { fixed, follow };

constexpr std::string_view to_string(sweep_start s) { return s == sweep_start::follow ? "follow" : "fixed"; }
inline constexpr std::array<sweep_start, 2> all_sweep_starts{sweep_start::fixed, sweep_start::follow};

struct sweep_options {
    int parameter = 0;
    value_grid values;              // a:b:n kept as a range (core/value_grid.hpp)
    Eigen::VectorXd initial_state;  // empty: the model's
    sweep_start start = sweep_start::fixed;
    sweep_direction direction = sweep_direction::up;  // both: needs follow
    protocol_options protocol{};
    double period_tolerance = default_period_tolerance;
    int grazing_parameter = -1;     // >= 0: its grazing value per surface at every point
};

// The options a user sets by name (core/option.hpp); the axis and the grazing parameter are
// resolved against the model by each front end.
template <class V, record_of<sweep_options> O>
void declare(V& v, O& o)
{
    v(option{"ic_mode", "where each point starts: fixed, from the initial state (the paper's way; it must be "
                        "admissible at every point), or follow, from the previous point's final state (hysteresis, "
                        "coexisting attractors)"},
      o.start, all_sweep_starts);
    v(option{"direction", "order of the values; both (follow only) runs the upward and downward branches in parallel"},
      o.direction, all_sweep_directions);
    v(period_tolerance_option, o.period_tolerance);
}

struct sweep_point {
    int branch = 0;                 // 0 up, 1 down
    double value = 0.0;
    period_label label;
    outcome status = outcome::ok;
    state_series points;            // the recorded section points
    Eigen::VectorXd final_state;
    std::vector<double> grazing;    // per surface (grazing_parameter >= 0), NaN where none
    std::vector<double> switch_grazing;  // per switch, the same
    run_stats stats;
    impact_statistics statistics;   // of the recorded window
};

// One row of labels.csv, one journal line, one entry of each of Python's arrays.
template <class V, record_of<sweep_point> P>
void describe(V& v, P& p)
{
    v(field{"branch", "0 up, 1 down"}, p.branch);
    v(field{"value", "the swept parameter's value", "parameter", field_span::one, "{axis}"}, p.value);
    describe(v, p.label);
    v(field{"outcome", "ok, or how the run ended early"}, p.status);
    v(field{"grazing", "grazing value of the grazing parameter per surface (NaN: none or not asked)", "parameter",
            field_span::per_surface, "{grazing}_graze"},
      p.grazing);
    v(field{"switch_grazing", "grazing value of the grazing parameter per switch (NaN: none or not asked)", "parameter",
            field_span::per_switch, "{grazing}_graze_{switch}"},
      p.switch_grazing);
    v.group(field{"statistics", "impact statistics of the recorded window"}, p.statistics);
    v(field{"points", "the recorded section points", "state", field_span::series}, p.points);
    v(field{"final_state", "the state at the end of the run (the next start when followed)", "state",
            field_span::per_state, {}, false},
      p.final_state);
    v.group(field{"stats", "counters of the run", "", field_span::one, {}, false}, p.stats);
}

struct sweep_result {
    std::vector<sweep_point> points;  // job order: up then down branch interleaved when both
    job_report jobs;
};

// Throws input_error for bad options or an inadmissible start.
// With `each`, the points go to it in job order as the run goes (jobs/job_options.hpp,
// Streaming) and `points` stays empty.
sweep_result sweep(const model& m, const sweep_options& o, const job_options& j = {},
                   const job_stream<sweep_point>& each = {});

// n values from a to b inclusive, evenly spaced (n = 1: a): value_grid::range(a, b, n)
// enumerated, for a caller that wants them all (a run's options take the range itself).
// n is limited to 1e8 (more points than any run can use).
std::vector<double> grid_values(double a, double b, long n);

// The final state of one point as the start of the next: unchanged when admissible for the
// next point's surfaces; otherwise put on the surface it violates (a Newton projection along
// the gap's gradient) and, if it moves into it, mapped by that surface's reset (an impact),
// so the orbit continues as closely as the moved surface allows.
Eigen::VectorXd continue_from(const model& next, const Eigen::VectorXd& x);

}  // namespace vimpact
