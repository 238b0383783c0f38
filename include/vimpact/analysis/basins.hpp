#pragma once
// Basins of attraction: the protocol from every initial state of a grid over two state
// variables (the others from a base state), the attractor each start reaches identified by
// its section points (analysis/attractor.hpp). A cell whose start lies beyond a surface is
// "inadmissible" (attractor -1).
#include <vector>

#include <Eigen/Core>

#include "vimpact/analysis/attractor.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/jobs/job_options.hpp"
#include "vimpact/core/value_grid.hpp"

namespace vimpact {

struct basins_options {
    int x_state = 0, y_state = 1;   // the state variables on the axes
    value_grid x_values, y_values;
    Eigen::VectorXd initial_state;  // the other components; empty: the model's
    protocol_options protocol{};
    double period_tolerance = default_period_tolerance;
    attractor_match_options match{};
};

// The options a user sets by name (core/option.hpp); the axes are resolved by each front end.
template <class V, record_of<basins_options> O>
void declare(V& v, O& o)
{
    v(period_tolerance_option, o.period_tolerance);
    v(option{"match_tol", "cycle points of one attractor agree within this", above(0.0)}, o.match.tolerance);
    v(option{"box_fraction", "aperiodic attractors: bounding boxes agree within this fraction of their extent",
             at_least(0.0)},
      o.match.box_fraction);
}

struct basin_cell {
    bool admissible = false;
    period_label label;             // "inadmissible" when not admissible
    outcome status = outcome::ok;
    long steps = 0;
    attractor_signature signature;
    int attractor = -1;
};

// One row of cells.csv (after the start's two state values), one entry of Python's arrays.
// The signature is the journal's only (the attractors table lists each attractor's).
template <class V, record_of<basin_cell> C>
void describe(V& v, C& c)
{
    v(field{"attractor", "the attractor reached, numbered in order of first appearance (-1: a start beyond a "
                         "surface)"},
      c.attractor);
    describe(v, c.label);
    v(field{"outcome", "ok, or how the run ended early (inadmissible: a start beyond a surface)"}, c.status);
    v(field{"admissible", "the start lies on the admissible side of every surface", "", field_span::one, {}, false},
      c.admissible);
    v(field{"steps", "accepted steps", "", field_span::one, {}, false}, c.steps);
}

struct basins_result {
    std::vector<basin_cell> cells;  // job order: cell (ix, iy) is job ix + nx iy
    std::vector<attractor_catalogue::entry> attractors;  // ids in order of first appearance
    job_report jobs;
};

// With `each`, the cells (their attractor identified) go to it in job order as the run goes
// (jobs/job_options.hpp, Streaming) and `cells` stays empty.
basins_result basins(const model& m, const basins_options& o, const job_options& j = {},
                     const job_stream<basin_cell>& each = {});

// The attractor signature of a run: label, cycle or bounding box of its section points, in
// coordinates where phases are (cos, sin) pairs scaled by period / 2 pi (analysis/attractor.hpp).
attractor_signature signature_of(const model& m, const simulation& run, const period_label& label);

}  // namespace vimpact
