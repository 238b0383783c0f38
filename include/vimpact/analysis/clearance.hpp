#pragma once
// Clearance design: along a range of one parameter (the paper's Ur, a flow speed), the
// smallest gap to a surface with no impact, and the response over a chart of gaps. The
// surface may be a switch (a compliant barrier): its gap is side * h, the side being that of
// the initial state, and "no impact" is no crossing.
//
// Gaps are measured from the rest state (the model's initial state) to the surface moved by
// the gap parameter G (the paper's sigma: gap = -sigma; rest_gap). At each value P of the
// flow parameter, one job of the job loop:
//  - the grazing run at P (surface-free, grazing.hpp) gives G's grazing value for that surface;
//    the clearance is the gap there: a surface farther away is never touched by the attracting
//    surface-free orbit (for the paper's barrier: -sigma_graze);
//  - the protocol runs at each gap of the chart from the same initial state and gives the
//    period label (regime: P0 no impact, PN periodic, aperiodic) and the impact statistics.
// The chart's gaps are given (model units), or fractions of each value's clearance (then a
// value whose clearance is not positive and finite has no chart cells). The aperiodic range
// of a value: its smallest and largest chart gap labelled aperiodic (NaN when none).
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/jobs/job_options.hpp"
#include "vimpact/core/value_grid.hpp"

namespace vimpact {

// 0.1, 0.2, ..., 1.3: the chart's gaps as fractions of the clearance, when none are given.
std::vector<double> default_clearance_fractions();

struct clearance_options {
    int parameter = -1;  // the flow parameter
    value_grid values;
    int gap_parameter = -1;          // -1: the first that moves a surface, else a switch (first_grazing_parameter)
    std::vector<double> gaps;        // the chart's gaps (model units); empty: fractions
    std::vector<double> fractions = default_clearance_fractions();
    Eigen::VectorXd initial_state;   // empty: the model's
    protocol_options protocol{};
    double period_tolerance = default_period_tolerance;
    grazing_options grazing = job_grazing_options(integrator_options{});
};

// What a user sets (core/option.hpp); the rest are the command's axes and the protocol.
template <class V, record_of<clearance_options> O>
void declare(V& v, O& o)
{
    v(period_tolerance_option, o.period_tolerance);
    v(option{"transient_time", "grazing runs: time discarded before minima count", at_least(0.0)},
      o.grazing.transient_time);
}

struct clearance_cell {
    static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    double gap = nan;                  // model units
    double gap_parameter_value = nan;  // G at this gap
    period_label label;
    outcome status = outcome::ok;
    impact_statistics statistics;
};

// A chart cell as a record (core/record.hpp): a row of chart.csv, a journal entry.
template <class V, record_of<clearance_cell> C>
void describe(V& v, C& c)
{
    v(field{"gap", "the gap from the rest state to the surface", "g"}, c.gap);
    v(field{"gap_value", "the gap parameter's value at this gap", "parameter", field_span::one, "{grazing}"},
      c.gap_parameter_value);
    describe(v, c.label);
    v(field{"outcome", "ok, or how the run ended early"}, c.status);
    v.group(field{"statistics", "impact statistics of the recorded window"}, c.statistics);
}

struct clearance_point {
    static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    double value = nan;            // of the flow parameter
    double grazing_value = nan;    // G at grazing
    double clearance = nan;        // the gap at grazing (model units)
    bool converged = false;        // the grazing run converged
    std::vector<clearance_cell> cells;
    double aperiodic_min = nan, aperiodic_max = nan;
};

// A value's point as a record: a row of clearance.csv. Its cells are not a field: chart.csv
// is a table of its own.
template <class V, record_of<clearance_point> P>
void describe(V& v, P& p)
{
    v(field{"value", "the flow parameter's value", "parameter", field_span::one, "{axis}"}, p.value);
    v(field{"grazing_value", "the gap parameter's grazing value", "parameter", field_span::one, "{grazing}_graze"},
      p.grazing_value);
    v(field{"clearance", "the gap at grazing: the smallest gap without impact", "g"}, p.clearance);
    v(field{"converged", "the grazing run converged"}, p.converged);
    v(field{"aperiodic_min", "the smallest chart gap labelled aperiodic (NaN: none)", "g"}, p.aperiodic_min);
    v(field{"aperiodic_max", "the largest chart gap labelled aperiodic (NaN: none)", "g"}, p.aperiodic_max);
}

struct clearance_result {
    int gap_parameter = -1;
    int surface = -1;       // the surface the gap parameter moves, or -1 and
    int switch_index = -1;  // the switch it moves
    std::vector<clearance_point> points;  // job order: the values in order
    job_report jobs;
};

// Throws input_error for bad options: no parameter that moves a surface or switch, a flow
// parameter that moves one, negative gaps or fractions.
clearance_result clearance(const model& m, const clearance_options& o, const job_options& j = {});

}  // namespace vimpact
