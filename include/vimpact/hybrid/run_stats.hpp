#pragma once
// Counters every run reports, whatever its outcome.
#include <algorithm>
#include <limits>
#include <vector>

namespace vimpact {

struct run_stats {
    long steps = 0;            // accepted steps
    long rejected = 0;         // rejected trial steps
    long rhs_calls = 0;        // vector-field evaluations (including interpolant stages)
    long impacts = 0;          // on every surface
    std::vector<long> impacts_by_surface;
    long sections = 0;         // section crossings located
    long sticking_phases = 0;  // chatter sequences ended by a contact phase
    double sticking_time = 0.0;
    double h_min = std::numeric_limits<double>::infinity();
    double h_max = 0.0;
    double t_final = 0.0;

    // Sums the counters of a later run into this one (t_final: the later run's).
    void add(const run_stats& s)
    {
        steps += s.steps;
        rejected += s.rejected;
        rhs_calls += s.rhs_calls;
        impacts += s.impacts;
        if (impacts_by_surface.size() < s.impacts_by_surface.size()) impacts_by_surface.resize(s.impacts_by_surface.size());
        for (std::size_t i = 0; i < s.impacts_by_surface.size(); ++i) impacts_by_surface[i] += s.impacts_by_surface[i];
        sections += s.sections;
        sticking_phases += s.sticking_phases;
        sticking_time += s.sticking_time;
        h_min = std::min(h_min, s.h_min);
        h_max = std::max(h_max, s.h_max);
        t_final = s.t_final;
    }
};

}  // namespace vimpact
