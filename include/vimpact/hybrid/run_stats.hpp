#pragma once
// Counters every run reports, whatever its outcome.
#include <limits>

namespace vimpact {

struct run_stats {
    long steps = 0;            // accepted steps
    long rejected = 0;         // rejected trial steps
    long rhs_calls = 0;        // vector-field evaluations (including interpolant stages)
    long impacts = 0;
    long sections = 0;         // section crossings located (maxima and minima)
    long sticking_phases = 0;  // chatter sequences ended by sticking
    double sticking_time = 0.0;
    double h_min = std::numeric_limits<double>::infinity();
    double h_max = 0.0;
    double t_final = 0.0;
};

}  // namespace vimpact
