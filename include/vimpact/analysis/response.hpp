#pragma once
// The surface-free response (lock-in curves): over a range of one parameter, and for one or
// more curves (sets of other parameter values), the surface-free run of the grazing analysis
// and what it measures: the largest and smallest extremum of a state variable, its amplitude
// max(|max|, |min|), its angular frequency, and each surface's and switch's grazing margin
// (or value of a grazing parameter); the switches' sides are held where the run starts.
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "vimpact/analysis/grazing.hpp"
#include "vimpact/core/record.hpp"
#include "vimpact/jobs/job_options.hpp"
#include "vimpact/core/value_grid.hpp"

namespace vimpact {

struct response_options {
    int parameter = 0;              // must enter the vector field
    value_grid values;
    // Each curve sets these parameters (index, value) before the sweep; empty: one curve at
    // the model's values.
    std::vector<std::vector<std::pair<int, double>>> curves;
    int variable = 0;               // the state variable measured
    Eigen::VectorXd initial_state;  // empty: the model's
    grazing_options grazing{};      // the run (its parameter: a grazing parameter, or -1)
};

// The options a user sets by name (core/option.hpp): the surface-free run's.
template <class V, record_of<response_options> O>
void declare(V& v, O& o)
{
    declare(v, o.grazing);
}

struct response_point {
    int curve = 0;
    double value = 0.0;
    double amplitude = std::numeric_limits<double>::quiet_NaN();
    double maximum = std::numeric_limits<double>::quiet_NaN();
    double minimum = std::numeric_limits<double>::quiet_NaN();
    double frequency = std::numeric_limits<double>::quiet_NaN();  // angular, in the model's time
    std::vector<double> grazing;    // per surface: the grazing parameter's value (NaN without one)
    std::vector<double> margin;     // per surface: the smallest gap on the orbit
    std::vector<double> switch_grazing;  // per switch: the grazing parameter's value (NaN without one)
    std::vector<double> switch_margin;   // per switch: the smallest side * h on the orbit
    bool converged = false;
    outcome status = outcome::ok;
    run_stats stats;
};

// One row of response.csv (after the curve's parameter values), one journal line, one entry
// of Python's arrays. Unit "variable": that of the measured state variable.
template <class V, record_of<response_point> P>
void describe(V& v, P& p)
{
    v(field{"curve", "the curve (its parameter values in run.json's curves)"}, p.curve);
    v(field{"value", "the varied parameter's value", "parameter", field_span::one, "{axis}"}, p.value);
    v(field{"amplitude", "max(|maximum|, |minimum|) of the measured variable", "variable"}, p.amplitude);
    v(field{"maximum", "its largest maximum over the last block of minima", "variable", field_span::one,
            "{variable}_max"},
      p.maximum);
    v(field{"minimum", "its smallest minimum over the last block", "variable", field_span::one, "{variable}_min"},
      p.minimum);
    v(field{"grazing", "grazing value of the grazing parameter per surface", "parameter", field_span::per_surface,
            "{grazing}_graze"},
      p.grazing);
    v(field{"margin", "smallest gap on the surface-free orbit per surface (negative: it crosses the surface)", "g",
            field_span::per_surface},
      p.margin);
    v(field{"switch_grazing", "grazing value of the grazing parameter per switch", "parameter", field_span::per_switch,
            "{grazing}_graze_{switch}"},
      p.switch_grazing);
    v(field{"switch_margin",
            "smallest side * h of each switch on the switch-free orbit, the side of the start (negative: it crosses "
            "the switch)",
            "", field_span::per_switch},
      p.switch_margin);
    v(field{"frequency", "angular frequency of the measured variable", "1/t"}, p.frequency);
    v(field{"converged", "the minima settled (false: a quasi-periodic response, say)"}, p.converged);
    v(field{"outcome", "ok, or how the run ended early"}, p.status);
    v.group(field{"stats", "counters of the run", "", field_span::one, {}, false}, p.stats);
}

struct response_result {
    std::vector<response_point> points;  // job order: curve-major
    job_report jobs;
};

// The model a point of a response runs: m with curve `curve`'s parameters (none beyond
// o.curves: one curve at m's values) and the swept parameter at `value`. Throws input_error
// for a value outside a parameter's range.
model response_model(const model& m, const response_options& o, int curve, double value);

// With `each`, the points go to it in job order as the run goes (jobs/job_options.hpp,
// Streaming) and `points` stays empty.
response_result response(const model& m, const response_options& o, const job_options& j = {},
                         const job_stream<response_point>& each = {});

}  // namespace vimpact
