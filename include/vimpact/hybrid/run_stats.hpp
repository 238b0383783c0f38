#pragma once
// Counters every run reports, whatever its outcome.
#include <algorithm>
#include <limits>
#include <vector>

#include "vimpact/core/record.hpp"

namespace vimpact {

struct run_stats {
    long steps = 0;            // accepted steps
    long rejected = 0;         // rejected trial steps
    long rhs_calls = 0;        // vector-field evaluations (including interpolant stages)
    long impacts = 0;          // on every surface
    std::vector<long> impacts_by_surface;
    long sections = 0;         // section crossings located
    long switchings = 0;       // crossings of switching surfaces
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
        switchings += s.switchings;
        sticking_phases += s.sticking_phases;
        sticking_time += s.sticking_time;
        h_min = std::min(h_min, s.h_min);
        h_max = std::max(h_max, s.h_max);
        t_final = s.t_final;
    }
};

template <class V, record_of<run_stats> S>
void describe(V& v, S& s)
{
    v(field{"steps", "accepted steps"}, s.steps);
    v(field{"rejected", "rejected trial steps"}, s.rejected);
    v(field{"rhs_calls", "vector-field evaluations"}, s.rhs_calls);
    v(field{"impacts", "impacts on every surface, transient included"}, s.impacts);
    v(field{"impacts_by_surface", "impacts on each surface", "", field_span::per_surface, "impacts_{surface}"},
      s.impacts_by_surface);
    v(field{"sections", "section crossings located"}, s.sections);
    v(field{"switchings", "crossings of switching surfaces"}, s.switchings);
    v(field{"sticking_phases", "chatter sequences ended by a contact phase"}, s.sticking_phases);
    v(field{"sticking_time", "time in contact phases", "t"}, s.sticking_time);
    v(field{"h_min", "smallest accepted step", "t"}, s.h_min);
    v(field{"h_max", "largest accepted step", "t"}, s.h_max);
    v(field{"t_final", "time at the end of the run", "t"}, s.t_final);
}

}  // namespace vimpact
