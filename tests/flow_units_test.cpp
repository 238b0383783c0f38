// SI <-> the wake model's dimensionless parameters, against facts that do not come from the
// conversion code: the model's own default mass ratio (Facchinetti et al.'s m* = 0.52 with
// C_M = 1), the structural frequency the model's equations imply, dimensional analysis.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "vimpact/core/input_error.hpp"
#include "vimpact/model/model.hpp"
#include "vimpact/physical/flow_units.hpp"

using namespace vimpact;

namespace {

cylinder_in_flow tube()  // a 20 mm tube in water
{
    return {.diameter = 0.02, .mass = 0.6, .natural_frequency = 12.0, .damping_ratio = 0.002, .fluid_density = 1000.0};
}

}  // namespace

TEST(FlowUnits, FacchinettisMassRatioGivesTheModelsDefaultMu)
{
    // Facchinetti et al. (2004) quote m* = m_s / (rho pi D^2 / 4) = 0.52 and C_M = 1; the
    // model's default mu (1.19381, six digits) is their mass ratio.
    const model m = model::builtin("wake_impact");
    const double mu_default = m.parameters()[static_cast<std::size_t>(m.info().parameter_index("mu"))];
    cylinder_in_flow c = tube();
    c.mass = 0.52 * c.fluid_density * std::numbers::pi * c.diameter * c.diameter / 4.0;
    EXPECT_NEAR(dimensionless(c, 1.0).mu, mu_default, 5e-6);
}

TEST(FlowUnits, TheModelsStructuralFrequencyIsTheNaturalFrequency)
{
    // In the model the structure oscillates at angular frequency delta = 1 / (St Ur) per unit
    // of model time; one model time unit's angular frequency is 2 pi frequency_scale Hz. The
    // product must give back f_n, whatever the speed: Ur and the time scale fit together.
    const cylinder_in_flow c = tube();
    for (const double U : {0.5, 3.0, 6.0}) {
        const auto d = dimensionless(c, U);
        const auto s = scales(c, U);
        const double delta = 1.0 / (d.St * d.Ur);
        EXPECT_NEAR(delta * s.frequency, c.natural_frequency, 1e-12 * c.natural_frequency) << U;
        // The wake oscillator's own frequency (1 in model units) is Strouhal's shedding law.
        EXPECT_NEAR(s.frequency, c.strouhal * U / c.diameter, 1e-12 * s.frequency);
        EXPECT_NEAR(s.velocity * s.time, s.length, 1e-15);
    }
}

TEST(FlowUnits, DimensionlessNumbersDoNotChangeWithScale)
{
    // Geometric similarity: D -> k D, m -> k^2 m (mass per length), U -> k U keep Ur and mu.
    const cylinder_in_flow c = tube();
    cylinder_in_flow big = c;
    const double k = 7.5;
    big.diameter *= k;
    big.mass *= k * k;
    const auto a = dimensionless(c, 2.0), b = dimensionless(big, 2.0 * k);
    EXPECT_NEAR(b.Ur, a.Ur, 1e-12 * a.Ur);
    EXPECT_NEAR(b.mu, a.mu, 1e-12 * a.mu);
    EXPECT_NEAR(scales(big, 2.0 * k).time, scales(c, 2.0).time, 1e-15);
}

TEST(FlowUnits, AMasslessTubeHasOnlyItsAddedMass)
{
    cylinder_in_flow c = tube();
    c.mass = 0.0;
    c.added_mass_coefficient = 2.0;
    EXPECT_NEAR(dimensionless(c, 1.0).mu, 2.0 * std::numbers::pi / 4.0, 1e-15);
}

TEST(FlowUnits, FlowSpeedInvertsTheReducedVelocity)
{
    const cylinder_in_flow c = tube();
    EXPECT_NEAR(dimensionless(c, flow_speed(c, 16.0)).Ur, 16.0, 1e-13);
}

TEST(FlowUnits, BadInputNamesTheQuantity)
{
    cylinder_in_flow c = tube();
    c.diameter = 0.0;
    try {
        (void)dimensionless(c, 1.0);
        FAIL();
    } catch (const input_error& e) {
        EXPECT_NE(std::string(e.what()).find("D (diameter, m) must be"), std::string::npos) << e.what();
    }
    c = tube();
    c.damping_ratio = -0.1;
    EXPECT_THROW((void)dimensionless(c, 1.0), input_error);
    EXPECT_THROW((void)dimensionless(tube(), -1.0), input_error);
    EXPECT_THROW((void)dimensionless(tube(), std::nan("")), input_error);
}

TEST(FlowUnits, TheMassRatioGivesTheModelsMuAsItsDescriptionSays)
{
    // The model describes mu as "(m* + C_m) pi/4": with Facchinetti et al.'s m* = 0.52 and
    // C_M = 1 that is 1.52 pi / 4 = 1.19381 (the model's default), whatever D and rho are.
    for (const double D : {0.02, 0.5}) {
        cylinder_in_flow c = tube();
        c.diameter = D;
        c.fluid_density = 1025.0;
        c.mass = mass_from_ratio(c, 0.52);
        EXPECT_NEAR(dimensionless(c, 1.0).mu, 1.52 * std::numbers::pi / 4.0, 1e-14) << D;
        EXPECT_NEAR(mass_ratio(c), 0.52, 1e-15) << D;
    }
    // By hand for the tube: m* = 2 is 2 * 1000 * pi * 0.0004 / 4 = 0.2 pi kg/m.
    EXPECT_NEAR(mass_from_ratio(tube(), 2.0), 0.2 * std::numbers::pi, 1e-15);
}

TEST(FlowUnits, TheStiffnessGivesTheFrequencyOnTheTotalMass)
{
    // The tube with m* = 3 (m = 0.3 pi kg/m) and water's added mass 0.1 pi kg/m: 0.4 pi kg/m
    // in all. k = 160 pi^3 N/m^2 = 0.4 pi (2 pi 10)^2: 10 Hz.
    cylinder_in_flow c = tube();
    c.mass = 0.3 * std::numbers::pi;
    EXPECT_NEAR(added_mass(c), 0.1 * std::numbers::pi, 1e-15);
    EXPECT_NEAR(natural_frequency_from_stiffness(c, 160.0 * std::pow(std::numbers::pi, 3)), 10.0, 1e-13);
    // Added mass lowers the frequency: in air (rho = 1.2) nearly the structure's own, sqrt(k/m).
    c.fluid_density = 1.2;
    EXPECT_NEAR(natural_frequency_from_stiffness(c, 160.0 * std::pow(std::numbers::pi, 3)),
                10.0 * std::sqrt(0.4 / (0.3 + 0.1 * 1.2 / 1000.0)), 1e-12);
    EXPECT_THROW((void)natural_frequency_from_stiffness(tube(), 0.0), input_error);
    EXPECT_THROW((void)mass_from_ratio(tube(), -1.0), input_error);
}

