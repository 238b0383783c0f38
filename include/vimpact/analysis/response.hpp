#pragma once
// The surface-free response (lock-in curves): over a range of one parameter, and for one or
// more curves (sets of other parameter values), the surface-free run of the grazing analysis
// and what it measures: the largest and smallest extremum of a state variable, its amplitude
// max(|max|, |min|), its angular frequency, and each surface's grazing margin (or value of a
// grazing parameter).
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "vimpact/analysis/grazing.hpp"
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

struct response_point {
    int curve = 0;
    double value = 0.0;
    double amplitude = std::numeric_limits<double>::quiet_NaN();
    double maximum = std::numeric_limits<double>::quiet_NaN();
    double minimum = std::numeric_limits<double>::quiet_NaN();
    double frequency = std::numeric_limits<double>::quiet_NaN();  // angular, in the model's time
    std::vector<double> grazing;    // per surface: the grazing parameter's value, or the margin
    bool converged = false;
    outcome status = outcome::ok;
    run_stats stats;
};

struct response_result {
    std::vector<response_point> points;  // job order: curve-major
    job_report jobs;
};

// With `each`, the points go to it in job order as the run goes (jobs/job_options.hpp,
// Streaming) and `points` stays empty.
response_result response(const model& m, const response_options& o, const job_options& j = {},
                         const job_stream<response_point>& each = {});

}  // namespace vimpact
