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
            {"frequency_scale", s.frequency}};
}

double flow_speed(const cylinder_in_flow& c, double Ur)
{
    validate(c);
    require_positive(Ur, "Ur", "reduced velocity");
    return Ur * c.natural_frequency * c.diameter;
}

}  // namespace vimpact
