#include "vimpact/physical/flow_units.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/physical/checked_input.hpp"

namespace vimpact {

namespace {

// The inputs the cylinder's cross-section and fluid give, checked before anything uses them.
void validate_section(const cylinder_in_flow& c)
{
    positive_input(c.diameter, "D", "diameter, m");
    positive_input(c.fluid_density, "rho", "fluid density, kg/m^3");
    non_negative_input(c.added_mass_coefficient, "CM", "added-mass coefficient");
}

}  // namespace

void validate(const cylinder_in_flow& c)
{
    positive_input(c.diameter, "D", "diameter, m");
    positive_input(c.natural_frequency, "fn", "natural frequency in still fluid, Hz");
    positive_input(c.fluid_density, "rho", "fluid density, kg/m^3");
    positive_input(c.strouhal, "St", "Strouhal number");
    non_negative_input(c.mass, "m", "structural mass per unit length, kg/m");
    non_negative_input(c.damping_ratio, "zeta", "structural damping ratio");
    positive_input(c.kinematic_viscosity, "nu", "kinematic viscosity, m^2/s");
    non_negative_input(c.added_mass_coefficient, "CM", "added-mass coefficient");
    // Each in range, the inputs may still give no number together: every quantity made of
    // them without the flow speed (the mass scale, mu, the mass ratio, fn D of Ur) is checked.
    const double D = c.diameter, rho = c.fluid_density, m = c.mass, CM = c.added_mass_coefficient;
    const double section = derived_value(rho * D * D, "rho D^2", {{"rho", rho}, {"D", D}});
    const double added = derived_value(CM * rho * std::numbers::pi * D * D / 4.0, "the added mass CM rho pi D^2 / 4",
                                       {{"CM", CM}, {"rho", rho}, {"D", D}}, true);
    derived_value((m + added) / section, "mu = (m + CM rho pi D^2 / 4) / (rho D^2)",
                  {{"m", m}, {"CM", CM}, {"rho", rho}, {"D", D}}, true);
    derived_value(m / (section * std::numbers::pi / 4.0), "the mass ratio m / (rho pi D^2 / 4)",
                  {{"m", m}, {"rho", rho}, {"D", D}}, true);
    derived_value(c.natural_frequency * D, "fn D", {{"fn", c.natural_frequency}, {"D", D}});
}

namespace {

// The quantities made of the flow speed U with the cylinder's inputs: Ur, Omega_f and its
// time and velocity scales, the Reynolds number.
void validate_at(const cylinder_in_flow& c, double U)
{
    const double D = c.diameter, St = c.strouhal, fn = c.natural_frequency;
    derived_value(U / (fn * D), "Ur = U / (fn D)", {{"U", U}, {"fn", fn}, {"D", D}});
    const double omega = derived_value(2.0 * std::numbers::pi * St * U / D, "Omega_f = 2 pi St U / D",
                                       {{"St", St}, {"U", U}, {"D", D}});
    derived_value(1.0 / omega, "the time scale 1 / Omega_f", {{"St", St}, {"U", U}, {"D", D}});
    derived_value(D * omega, "the velocity scale D Omega_f", {{"St", St}, {"U", U}});
    derived_value(U * D / c.kinematic_viscosity, "Re = U D / nu", {{"U", U}, {"D", D}, {"nu", c.kinematic_viscosity}});
}

}  // namespace

double added_mass(const cylinder_in_flow& c)
{
    validate_section(c);
    return c.added_mass_coefficient * c.fluid_density * std::numbers::pi * c.diameter * c.diameter / 4.0;
}

double mass_from_ratio(const cylinder_in_flow& c, double mass_ratio)
{
    validate_section(c);
    non_negative_input(mass_ratio, "mstar", "mass ratio m / (rho pi D^2 / 4)");
    return derived_value(mass_ratio * c.fluid_density * std::numbers::pi * c.diameter * c.diameter / 4.0,
                         "m = mstar rho pi D^2 / 4", {{"mstar", mass_ratio}, {"rho", c.fluid_density}, {"D", c.diameter}},
                         true);
}

double natural_frequency_from_stiffness(const cylinder_in_flow& c, double stiffness)
{
    non_negative_input(c.mass, "m", "structural mass per unit length, kg/m");
    positive_input(stiffness, "k", "stiffness per unit length, N/m^2");
    const double total = c.mass + added_mass(c);
    if (!(total > 0.0))
        throw input_error("k (stiffness per unit length, N/m^2) needs a mass to oscillate: m + CM rho pi D^2 / 4 is 0");
    return derived_value(std::sqrt(stiffness / total) / (2.0 * std::numbers::pi),
                         "fn = sqrt(k / (m + CM rho pi D^2 / 4)) / (2 pi)",
                         {{"k", stiffness}, {"m", c.mass}, {"CM", c.added_mass_coefficient}, {"rho", c.fluid_density},
                          {"D", c.diameter}});
}

wake_dimensionless dimensionless(const cylinder_in_flow& c, double U)
{
    validate(c);
    positive_input(U, "U", "flow speed, m/s");
    validate_at(c, U);
    const double D = c.diameter;
    return {.Ur = U / (c.natural_frequency * D),
            .mu = (c.mass + added_mass(c)) / (c.fluid_density * D * D),
            .xi = c.damping_ratio,
            .St = c.strouhal};
}

flow_scales scales(const cylinder_in_flow& c, double U)
{
    validate(c);
    positive_input(U, "U", "flow speed, m/s");
    validate_at(c, U);
    const double omega_f = 2.0 * std::numbers::pi * c.strouhal * U / c.diameter;
    return {.length = c.diameter,
            .time = 1.0 / omega_f,
            .velocity = c.diameter * omega_f,
            .frequency = omega_f / (2.0 * std::numbers::pi)};
}

std::vector<named_value> units_at(const cylinder_in_flow& c, double U)
{
    const wake_dimensionless d = dimensionless(c, U);
    const flow_scales s = scales(c, U);
    return {{"U", U},
            {"Ur", d.Ur},
            {"mu", d.mu},
            {"xi", d.xi},
            {"St", d.St},
            {"time_scale", s.time},
            {"length_scale", s.length},
            {"velocity_scale", s.velocity},
            {"frequency_scale", s.frequency},
            {"Re", reynolds_number(c, U)},
            {"mass_ratio", mass_ratio(c)}};
}

double reynolds_number(const cylinder_in_flow& c, double U)
{
    validate(c);
    positive_input(U, "U", "flow speed, m/s");
    validate_at(c, U);
    return U * c.diameter / c.kinematic_viscosity;
}

double mass_ratio(const cylinder_in_flow& c)
{
    validate(c);
    return c.mass / (c.fluid_density * std::numbers::pi * c.diameter * c.diameter / 4.0);
}

std::vector<std::string> validity_warnings(const cylinder_in_flow& c, double U)
{
    std::vector<std::string> out;
    const double Re = reynolds_number(c, U);
    if (Re < calibrated_reynolds_min || Re > calibrated_reynolds_max)
        out.push_back("Re = U D / nu = " + format_double(Re) + " at U = " + format_double(U) +
                      " m/s is outside 300 < Re < 1.5e5, where the wake model's St = 0.2 and CL0 hold");
    const double ms = mass_ratio(c);
    if (ms < calibrated_mass_ratio_min || ms > calibrated_mass_ratio_max)
        out.push_back("the mass ratio m* = m / (rho pi D^2 / 4) = " + format_double(ms) +
                      " is outside 0.54 <= m* <= 20, the range taken as the wake model's calibration "
                      "(docs/engineering.md)");
    return out;
}

double flow_speed(const cylinder_in_flow& c, double Ur)
{
    validate(c);
    positive_input(Ur, "Ur", "reduced velocity");
    return derived_value(Ur * c.natural_frequency * c.diameter, "U = Ur fn D",
                         {{"Ur", Ur}, {"fn", c.natural_frequency}, {"D", c.diameter}});
}

}  // namespace vimpact
