#pragma once
// Periodicity maps: the period label over a grid of two parameters, every cell from the same
// initial state; optionally the grazing line of a parameter that moves the surfaces (one of
// the axes) as a function of the other axis.
#include <vector>

#include <Eigen/Core>

#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/jobs/job_options.hpp"
#include "vimpact/core/value_grid.hpp"

namespace vimpact {

struct map_axis {
    int parameter = 0;
    value_grid values;
};

struct map_options {
    map_axis x, y;
    Eigen::VectorXd initial_state;  // empty: the model's
    protocol_options protocol{};
    double period_tolerance = default_period_tolerance;
    bool grazing = false;  // the grazing line: the axis parameter that moves the surfaces against the other
};

// The options a user sets by name (core/option.hpp); the axes are resolved by each front end.
template <class V, record_of<map_options> O>
void declare(V& v, O& o)
{
    v(period_tolerance_option, o.period_tolerance);
    v(option{"grazing", "also the grazing line: the grazing value per surface of the axis parameter that moves the "
                        "surfaces without entering the vector field, against the other axis"},
      o.grazing);
}

struct map_cell {
    period_label label;
    outcome status = outcome::ok;
    long steps = 0;
    impact_statistics statistics;  // of the recorded window
};

// One row of labels.csv (after the cell's two parameter values), one entry of Python's arrays.
template <class V, record_of<map_cell> C>
void describe(V& v, C& c)
{
    describe(v, c.label);
    v(field{"outcome", "ok, or how the run ended early"}, c.status);
    v(field{"steps", "accepted steps", "", field_span::one, {}, false}, c.steps);
    v.group(field{"statistics", "impact statistics of the recorded window"}, c.statistics);
}

struct map_result {
    std::vector<map_cell> cells;  // job order: cell (ix, iy) is job ix + nx iy (a complete run)
    // The grazing line: for each value of the other axis, the grazing value of the axis
    // parameter per surface and per switch (NaN where none).
    int grazing_axis = -1;        // 0: x is the grazing parameter, 1: y
    std::vector<double> grazing_other;
    std::vector<std::vector<double>> grazing_values;
    std::vector<std::vector<double>> grazing_switch_values;  // per switch, the same
    job_report jobs;
};

// With `each`, the cells go to it in job order as the run goes (jobs/job_options.hpp,
// Streaming) and `cells` stays empty.
map_result map2d(const model& m, const map_options& o, const job_options& j = {},
                 const job_stream<map_cell>& each = {});

}  // namespace vimpact
