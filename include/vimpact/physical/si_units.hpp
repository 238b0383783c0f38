#pragma once
// Running a model in SI units: an engineer's inputs (a cylinder in a flow for the paper's
// model, or the SI value of the model's units for any model; a flow speed and a gap to the
// neighbour in metres) to the model's dimensionless parameters, and its results back to
// metres, seconds, hertz, joules and watts. docs/engineering.md has every formula.
//
// The keys (KEY=VALUE, as `--si` and vimpact.PhysicalUnits take them):
//   D, m | mstar, fn | k, zeta, rho     a cylinder in a flow (flow_units.hpp): sets the wake
//   [, CM, St, nu, CL0]                 model's mu, xi, St (and CL0 when given); the mass per
//                                       metre m or the mass ratio mstar = m / (rho pi D^2 / 4),
//                                       the natural frequency fn in still fluid or the
//                                       stiffness per metre k [N/m^2] (exactly one of each);
//                                       one model unit of length is D, of time 1 / Omega_f at
//                                       the flow speed, of mass (per metre of tube)
//                                       m + m_f = mu rho D^2
//   length, time [, mass]               any model: one model unit of length [m], time [s] and
//                                       mass [kg] (mass 1 when not given: energies per kg)
//   U                                   the flow speed [m/s] (with a cylinder): sets Ur
//   gap                                 [m] the distance from the rest state (the model's initial
//                                       state) to the surface moved by the model's first gap
//                                       parameter (sigma: sigma = -gap / D): sets that parameter
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "vimpact/analysis/impact_statistics.hpp"
#include "vimpact/core/value_grid.hpp"
#include "vimpact/model/model.hpp"
#include "vimpact/physical/flow_units.hpp"
#include "vimpact/physical/state_dimensions.hpp"

namespace vimpact {

struct clearance_result;  // analysis/clearance.hpp

// One unit of a model's quantities in SI.
struct physical_scales {
    double length = 1.0;  // m
    double time = 1.0;    // s
    double mass = 1.0;    // kg (kg/m for a cylinder: per metre of its length)

    [[nodiscard]] double velocity() const { return length / time; }
    [[nodiscard]] double energy() const { return mass * velocity() * velocity(); }
    [[nodiscard]] double power() const { return energy() / time; }
    // Hz of an angular frequency w of the model (a response's frequency): w / (2 pi time).
    [[nodiscard]] double frequency() const;
    // One model unit of a state variable of dimension d in SI (m, m/s); NaN for none.
    [[nodiscard]] double of(physical_dimension d) const;
};

struct si_input {
    std::optional<cylinder_in_flow> cylinder;  // m and fn computed when mstar and k are given
    std::optional<double> mass_ratio;          // mstar, as given
    std::optional<double> stiffness;           // k [N/m^2], as given
    std::optional<double> lift_coefficient;    // CL0, as given (else the model's own)
    std::optional<physical_scales> scales;     // given directly (any model)
    std::optional<double> speed;               // U [m/s]
    std::optional<double> gap;                 // [m]
};

// "D, m or mstar, fn or k, zeta, rho (a cylinder; CM, St, nu, CL0 optional) or length, time
// (mass optional); U, gap", for messages.
std::string si_keys();

// From KEY=VALUE pairs in the order given. Throws input_error naming the key: an unknown or
// repeated key, a missing one, a value out of range (a gap below zero, a zero diameter...),
// or values that together give a quantity no double holds (derived_value). The messages
// name no front end (`--si`, PhysicalUnits): each caller adds its own.
si_input si_from_pairs(const std::vector<std::pair<std::string, double>>& pairs);

// The inputs by key, defaults filled in (CM, St, nu; mass) and m and fn computed where mstar
// and k were given, as run.json echoes them.
std::vector<named_value> si_inputs(const si_input& in);

// The parameter an SI quantity sets on `m` (U -> Ur, gap -> the first gap parameter), -1 for a
// name that is not one; throws input_error when `m` has no such parameter.
int si_parameter(const si_input& in, const model& m, std::string_view quantity);
// The value of that parameter for the SI value (U in m/s, gap in m), at m's other parameters.
double si_parameter_value(const si_input& in, const model& m, std::string_view quantity, double value);
// A grid of SI values of the quantity as the grid of that parameter's values, mapped value by
// value with si_parameter_value (a range stays a range: value_grid).
value_grid si_parameter_grid(const si_input& in, const model& m, std::string_view quantity, const value_grid& given);
// Back: the SI value of the quantity (U [m/s], gap [m]) where that parameter is `value`.
double si_quantity_value(const si_input& in, const model& m, std::string_view quantity, double value);

// The model with the parameters the SI input sets (mu, xi, St of a cylinder, CL0 when given; Ur
// from U; the gap parameter from gap). Throws input_error naming what `m` lacks.
model apply_si(const model& m, const si_input& in);
// Those parameters, (index, value) in the model's order.
std::vector<std::pair<int, double>> si_parameters(const model& m, const si_input& in);

// One model unit in SI at m's parameters (a cylinder: at the flow speed of m's Ur).
physical_scales scales_at(const si_input& in, const model& m);
// Back from the model: the flow speed [m/s] of m's Ur (NaN without a cylinder) and the gap
// [m] between the rest state and the surface the first gap parameter moves (rest_gap, NaN
// when m has none).
double flow_speed_of(const si_input& in, const model& m);
double gap_of(const si_input& in, const model& m);
// The gap [m] between the rest state and surface `surface` of m.
double gap_to(const si_input& in, const model& m, int surface);
// One model unit of length in metres.
double length_scale(const si_input& in);

// The statistics in SI: rate [Hz], velocities [m/s], energy per impact [J, J/m for a
// cylinder], power [W, W/m], excursion [m]; counts, fractions and duration [s] alike.
impact_statistics in_si(const impact_statistics& s, const physical_scales& k);

// Gaps in metres as model units (gap / length), each checked >= 0: the message names the gap.
std::vector<double> gaps_in_model_units(const si_input& in, const std::vector<double>& metres);
// A clearance result in SI: gaps, clearances and aperiodic ranges in metres, and each chart
// run's statistics in SI at its point's flow value (m with `parameter` at the point's value).
clearance_result in_si(const clearance_result& r, const si_input& in, const model& m, int parameter);

// The numbers of a run in SI by name (U, Re, mass_ratio and the lift coefficient CL0 the run
// uses for a cylinder, gap, and the scales length, time, mass, velocity, energy, power), as
// run.json's `si` section gives them.
std::vector<named_value> si_values(const si_input& in, const model& m);

// Where the wake model leaves the range it was calibrated for: the Reynolds number U D / nu
// outside [300, 1.5e5] and the mass ratio m* = m / (rho pi D^2 / 4) outside [0.54, 20]
// (docs/engineering.md, "Limits of validity"); empty when inside, or without a cylinder.
std::vector<std::string> validity_warnings(const si_input& in, const model& m);

}  // namespace vimpact
