#pragma once
// How hard and how often a run hits its surfaces: the impact statistics of a protocol run's
// recorded window, for any model, in the model's units (physical/si_units.hpp converts them).
//
// Definitions (docs/model.md, "Impact statistics"). For impact k on surface i, with x- the
// state just before the reset and x+ = R_i(x-) the state just after:
//   normal velocity   v_k = -dg_i/dt(x-) = -grad g_i(x-) . F(x-)   (> 0: the approach speed)
//   rebound velocity  u_k =  dg_i/dt(x+) =  grad g_i(x+) . F(x+)
//   energy dissipated e_k = (v_k^2 - u_k^2) / 2
// per unit of the mass whose motion the gap measures. For Newton's law u = r v this is the
// textbook (1 - r^2) m v^2 / 2 with m = 1; for a collision of two bodies along the gap it is
// the kinetic energy lost, per unit of their reduced mass. The paper's model measures the gap
// in diameters and its structural equation is per unit of the total (structural plus added)
// mass, so e_k times that mass and the velocity scale squared is joules per metre of tube.
// Over the recorded window [t_record_start, t_final] (duration T):
//   rate              impacts / T
//   velocity_*        min, mean, root mean square and max of v_k (NaN without impacts)
//   energy_per_impact mean of e_k (NaN without impacts)
//   power             sum of e_k / T, the mean dissipated power
//   contact_fraction  time in a contact phase (at rest on a surface, after a chatter) / T
//   excursion         the largest gap reached: max over the window and over the surfaces of
//                     g_i(x(t)), the farthest the motion gets from any surface it must not
//                     penetrate (for the paper's barrier: max y - sigma, in diameters);
//                     excursion_by_surface gives it per surface.
#include <limits>
#include <vector>

#include "vimpact/core/record.hpp"
#include "vimpact/core/state_series.hpp"

namespace vimpact {

class model;
struct simulation;

struct impact_statistics {
    static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    long impacts = 0;
    double duration = 0.0;
    double rate = 0.0;
    double velocity_min = nan, velocity_mean = nan, velocity_rms = nan, velocity_max = nan;
    double energy_per_impact = nan;
    double power = 0.0;
    double contact_fraction = 0.0;
    double excursion = nan;
    std::vector<double> excursion_by_surface;
};

// Units: t the model's time, g its gap; energies per unit of the mass the gap measures.
template <class V, record_of<impact_statistics> S>
void describe(V& v, S& s)
{
    v(field{"impacts_recorded", "impacts in the recorded window"}, s.impacts);
    v(field{"duration", "length of the recorded window", "t"}, s.duration);
    v(field{"impact_rate", "impacts per unit time", "1/t"}, s.rate);
    v(field{"impact_velocity_min", "smallest normal velocity -dg/dt before an impact", "g/t"}, s.velocity_min);
    v(field{"impact_velocity_mean", "mean normal velocity", "g/t"}, s.velocity_mean);
    v(field{"impact_velocity_rms", "root mean square normal velocity", "g/t"}, s.velocity_rms);
    v(field{"impact_velocity_max", "largest normal velocity", "g/t"}, s.velocity_max);
    v(field{"energy_per_impact", "mean energy dissipated per impact, (v^2 - u^2)/2", "(g/t)^2"}, s.energy_per_impact);
    v(field{"power", "energy dissipated per unit time", "(g/t)^2/t"}, s.power);
    v(field{"contact_fraction", "fraction of the window spent at rest on a surface"}, s.contact_fraction);
    v(field{"excursion", "largest gap reached over the window and the surfaces", "g"}, s.excursion);
    v(field{"excursion_by_surface", "largest gap reached, per surface", "g", field_span::per_surface,
            "excursion_{surface}"},
      s.excursion_by_surface);
}

// One impact's normal velocity v, rebound velocity u and dissipated energy e (definitions
// above).
struct impact_velocity {
    double normal = 0.0, rebound = 0.0, energy = 0.0;
};

std::vector<impact_velocity> impact_velocities(const model& m, const impact_series& impacts);

// The statistics of a run's recorded window (simulate() fills simulation::statistics with
// them; a front end never computes them itself).
impact_statistics compute_impact_statistics(const model& m, const simulation& run);

// The statistics that are one number each, as the front ends name them (describe above):
// their names, the values of `s` in that order, and the inverse (excursion_by_surface left
// empty; input_error for a list of the wrong length).
const std::vector<const char*>& impact_statistics_names();
std::vector<double> impact_statistics_values(const impact_statistics& s);
impact_statistics impact_statistics_from_values(const std::vector<double>& values);

}  // namespace vimpact
