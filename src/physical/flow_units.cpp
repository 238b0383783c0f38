#include "vimpact/physical/flow_units.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"

namespace vimpact {

namespace {

void require_positive(double v, const char* name, const char* what)
{
    if (!(v > 0.0) || !std::isfinite(v))
        throw input_error(std::string(name) + " (" + what + ") must be a finite number > 0 (got " + format_double(v) +
                          ")");
}

}  // namespace

void validate(const cylinder_in_flow& c)
{
    require_positive(c.diameter, "D", "diameter, m");
    require_positive(c.natural_frequency, "fn", "natural frequency in still fluid, Hz");
    require_positive(c.fluid_density, "rho", "fluid density, kg/m^3");
    require_positive(c.strouhal, "St", "Strouhal number");
    if (!(c.mass >= 0.0) || !std::isfinite(c.mass))
        throw input_error("m (structural mass per unit length, kg/m) must be a finite number >= 0 (got " +
                          format_double(c.mass) + ")");
    if (!(c.damping_ratio >= 0.0) || !std::isfinite(c.damping_ratio))
        throw input_error("zeta (structural damping ratio) must be a finite number >= 0 (got " +
                          format_double(c.damping_ratio) + ")");
    require_positive(c.kinematic_viscosity, "nu", "kinematic viscosity, m^2/s");
    if (!(c.added_mass_coefficient >= 0.0) || !std::isfinite(c.added_mass_coefficient))
        throw input_error("CM (added-mass coefficient) must be a finite number >= 0 (got " +
                          format_double(c.added_mass_coefficient) + ")");
}

wake_dimensionless dimensionless(const cylinder_in_flow& c, double U)
{
    validate(c);
    require_positive(U, "U", "flow speed, m/s");
    const double D = c.diameter;
    const double added = c.added_mass_coefficient * c.fluid_density * std::numbers::pi * D * D / 4.0;
    return {.Ur = U / (c.natural_frequency * D),
            .mu = (c.mass + added) / (c.fluid_density * D * D),
            .xi = c.damping_ratio,
            .St = c.strouhal};
}

flow_scales scales(const cylinder_in_flow& c, double U)
{
    validate(c);
    require_positive(U, "U", "flow speed, m/s");
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
    require_positive(Ur, "Ur", "reduced velocity");
    return Ur * c.natural_frequency * c.diameter;
}

}  // namespace vimpact
