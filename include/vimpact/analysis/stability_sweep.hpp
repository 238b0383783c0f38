#pragma once
// Floquet multipliers and Lyapunov exponents over a range of one parameter (the paper's
// Figures 14-17), one analysis per value from the same initial state, through the job loop.
#include <vector>

#include <Eigen/Core>

#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/lyapunov.hpp"
#include "vimpact/jobs/job_options.hpp"
#include "vimpact/core/value_grid.hpp"

namespace vimpact {

struct floquet_sweep_options {
    int parameter = 0;
    value_grid values;
    Eigen::VectorXd initial_state;  // empty: the model's
    floquet_options floquet{};
};

struct floquet_sweep_point {
    double value = 0.0;
    floquet_result result;  // what its describe() keeps (no monodromy, impacts or orbit samples)
    bool stable = false;    // result.stable(), the verdict every front end shows
};

template <class V, record_of<floquet_sweep_point> P>
void describe(V& v, P& p)
{
    v(field{"value", "the swept parameter's value", "parameter", field_span::one, "{axis}"}, p.value);
    describe(v, p.result);
    v(field{"stable", "converged, and every nontrivial multiplier inside the unit circle"}, p.stable);
}

struct floquet_sweep_result {
    std::vector<floquet_sweep_point> points;
    job_report jobs;
};

// With `each`, the points go to it in job order as the run goes (jobs/job_options.hpp,
// Streaming) and `points` stays empty.
floquet_sweep_result floquet_sweep(const model& m, const floquet_sweep_options& o, const job_options& j = {},
                                   const job_stream<floquet_sweep_point>& each = {});

struct lyapunov_sweep_options {
    int parameter = 0;
    value_grid values;
    Eigen::VectorXd initial_state;  // empty: the model's
    lyapunov_options lyapunov{};
};

struct lyapunov_sweep_point {
    double value = 0.0;
    lyapunov_result result;  // what its describe() keeps (no interval history)
    bool positive = false;   // result.positive_largest_exponent(), the verdict every front end shows
};

template <class V, record_of<lyapunov_sweep_point> P>
void describe(V& v, P& p)
{
    v(field{"value", "the swept parameter's value", "parameter", field_span::one, "{axis}"}, p.value);
    describe(v, p.result);
    v(field{"positive", "the largest exponent lies more than 3 standard errors above 0"}, p.positive);
}

struct lyapunov_sweep_result {
    std::vector<lyapunov_sweep_point> points;
    job_report jobs;
};

// With `each`, as floquet_sweep.
lyapunov_sweep_result lyapunov_sweep(const model& m, const lyapunov_sweep_options& o, const job_options& j = {},
                                     const job_stream<lyapunov_sweep_point>& each = {});

}  // namespace vimpact
