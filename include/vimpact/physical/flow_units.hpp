#pragma once
// From an engineer's cylinder in a flow (SI units) to the dimensionless parameters of the
// wake-oscillator model (Facchinetti, de Langre & Biolley 2004, J. Fluids Struct. 19:123-140,
// the model `wake_impact` builds on), and back.
//
// The model measures length in diameters and time in the vortex-shedding time scale:
//   y = Y / D,   t = Omega_f T,   Omega_f = 2 pi St U / D  (shedding angular frequency)
// so a displacement y is y D metres, a time t is t / Omega_f seconds, a velocity ydot is
// ydot D Omega_f m/s, and a dimensionless angular frequency w is w Omega_f / (2 pi) Hz.
// Parameters (Facchinetti et al. 2004, Section 2):
//   Ur = U / (f_n D)                          reduced velocity, f_n in still fluid
//   mu = (m_s + m_f) / (rho D^2)              mass ratio, m_f = C_M rho pi D^2 / 4 (added mass)
//   xi = zeta                                 structural damping ratio, defined there on the
//                                             total mass m_s + m_f and the still-fluid
//                                             frequency: r_s = 2 (m_s + m_f) (2 pi f_n) xi,
//                                             i.e. what a free-decay test in still fluid gives
// St (0.2) and C_M (1) are the values Facchinetti et al. use for the subcritical range
// 300 < Re < 1.5e5. The Reynolds number Re = U D / nu needs the fluid's kinematic viscosity
// nu (default 1.0e-6 m^2/s, water at 20 C); the mass ratio is m* = m_s / (rho pi D^2 / 4).
// What an engineer may know instead of m_s and f_n: the mass ratio m* (m_s = m* rho pi D^2 / 4)
// and the stiffness per unit length k [N/m^2]; f_n is then the natural frequency in still
// fluid on the total mass, f_n = sqrt(k / (m_s + m_f)) / (2 pi), the f_n the formulas above use.
#include <string>
#include <vector>

namespace vimpact {

struct cylinder_in_flow {
    double diameter = 0.0;           // D [m]
    double mass = 0.0;               // m_s, structural mass per unit length [kg/m]
    double natural_frequency = 0.0;  // f_n, in still fluid [Hz]
    double damping_ratio = 0.0;      // zeta, structural, from a free decay in still fluid
    double fluid_density = 0.0;      // rho [kg/m^3]
    double added_mass_coefficient = 1.0;  // C_M
    double strouhal = 0.2;                // St
    double kinematic_viscosity = 1.0e-6;  // nu [m^2/s], for the Reynolds number only
};

// Throws input_error naming the field and its valid range.
void validate(const cylinder_in_flow& c);

struct wake_dimensionless {
    double Ur = 0.0, mu = 0.0, xi = 0.0, St = 0.0;
};

// The model's parameters at flow speed U [m/s].
wake_dimensionless dimensionless(const cylinder_in_flow& c, double flow_speed);

// m_f = C_M rho pi D^2 / 4 [kg/m], the fluid that moves with the cylinder.
double added_mass(const cylinder_in_flow& c);
// m_s from the mass ratio m* (c's D and rho), and f_n from the stiffness per unit length k
// [N/m^2] (c's D, rho, C_M and m_s). Each throws input_error naming the input it refuses.
double mass_from_ratio(const cylinder_in_flow& c, double mass_ratio);
double natural_frequency_from_stiffness(const cylinder_in_flow& c, double stiffness);

// The SI value of one unit of the model's quantities at flow speed U.
struct flow_scales {
    double length = 0.0;     // D [m]
    double time = 0.0;       // 1 / Omega_f [s]
    double velocity = 0.0;   // D Omega_f [m/s]
    double frequency = 0.0;  // Omega_f / (2 pi) [Hz], for a dimensionless angular frequency
};

flow_scales scales(const cylinder_in_flow& c, double flow_speed);

// One flow speed's numbers by name (U, Ur, mu, xi, St, time_scale, length_scale,
// velocity_scale, frequency_scale, Re, mass_ratio), as `vimpact units --json` and vimpact.cylinder_units give
// them: the names are defined here once.
struct named_value {
    const char* name;
    double value;
};
std::vector<named_value> units_at(const cylinder_in_flow& c, double flow_speed);

// The flow speed [m/s] at which the cylinder has reduced velocity Ur.
double flow_speed(const cylinder_in_flow& c, double Ur);

// Re = U D / nu and m* = m_s / (rho pi D^2 / 4).
double reynolds_number(const cylinder_in_flow& c, double flow_speed);
double mass_ratio(const cylinder_in_flow& c);

// The range the wake model's constants were calibrated for (docs/engineering.md, "Limits of
// validity"), and one line per limit the cylinder at flow speed U leaves (empty: inside).
inline constexpr double calibrated_reynolds_min = 300.0, calibrated_reynolds_max = 1.5e5;
inline constexpr double calibrated_mass_ratio_min = 0.54, calibrated_mass_ratio_max = 20.0;
std::vector<std::string> validity_warnings(const cylinder_in_flow& c, double flow_speed);

}  // namespace vimpact
