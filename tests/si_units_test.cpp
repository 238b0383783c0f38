// SI units: conversions against values computed by hand from the formulas of Facchinetti et
// al. (2004) (docs/engineering.md), round trips model <-> SI, the statistics' SI forms against
// hand-made products of the scales, bad inputs named, and the clearance at a flow speed against
// the grazing analysis run directly at the matching Ur (times D).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "test_support.hpp"
#include "vimpact/analysis/clearance.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/physical/si_units.hpp"

namespace {

using namespace vimpact;
using pairs = std::vector<std::pair<std::string, double>>;
constexpr double pi = std::numbers::pi;

// The contract's tube: 20 mm, 0.6 kg/m, 12 Hz, 0.2 %, in water.
pairs tube() { return {{"D", 0.02}, {"m", 0.6}, {"fn", 12.0}, {"zeta", 0.002}, {"rho", 1000.0}}; }

std::string message_of(const pairs& p)
{
    try {
        (void)si_from_pairs(p);
    } catch (const input_error& e) {
        return e.what();
    }
    return "";
}

TEST(SIUnits, TubeInWaterToTheWakeModelByHand)
{
    pairs p = tube();
    p.emplace_back("U", 4.0);
    p.emplace_back("gap", 0.003);
    const si_input in = si_from_pairs(p);
    const model m = apply_si(model{}, in);
    // By hand: Ur = 4 / (12 * 0.02) = 16.666..., mu = (0.6 + pi/4 1000 0.0004) / (1000 0.0004)
    // = 1.5 + pi/4, xi = 0.002, sigma = -0.003 / 0.02 = -0.15.
    const auto& info = m.info();
    EXPECT_NEAR(m.parameter(info.parameter_index("Ur")), 4.0 / 0.24, 1e-14);
    EXPECT_NEAR(m.parameter(info.parameter_index("mu")), 1.5 + pi / 4, 1e-14);
    EXPECT_EQ(m.parameter(info.parameter_index("xi")), 0.002);
    EXPECT_EQ(m.parameter(info.parameter_index("St")), 0.2);
    EXPECT_NEAR(m.parameter(info.parameter_index("sigma")), -0.15, 1e-15);
    // Back: the same speed and gap.
    EXPECT_NEAR(flow_speed_of(in, m), 4.0, 1e-14);
    EXPECT_NEAR(gap_of(in, m), 0.003, 1e-17);
    // The scales at U = 4: Omega_f = 2 pi 0.2 4 / 0.02 = 80 pi rad/s.
    const physical_scales k = scales_at(in, m);
    EXPECT_NEAR(k.time, 1.0 / (80 * pi), 1e-17);
    EXPECT_NEAR(k.velocity(), 0.02 * 80 * pi, 1e-13);
    EXPECT_NEAR(k.mass, 0.6 + pi / 4 * 1000 * 0.0004, 1e-14);  // m + m_f per metre
}

TEST(SIUnits, AnyModelByItsUnitsAndGap)
{
    // The two stops at x = +-d: one model unit 2.5 mm and 10 ms; a gap of 5 mm is d = 2.
    const si_input in = si_from_pairs({{"length", 0.0025}, {"time", 0.01}, {"mass", 3.0}, {"gap", 0.005}});
    const model two = model::builtin("two_sided_impact_oscillator");
    const model m = apply_si(two, in);
    EXPECT_NEAR(m.parameter(two.info().parameter_index("d")), 2.0, 1e-14);
    EXPECT_NEAR(gap_of(in, m), 0.005, 1e-17);
    EXPECT_TRUE(std::isnan(flow_speed_of(in, m)));
    // The forced oscillator's barrier at sigma = -gap / length.
    const model f = apply_si(model::builtin("forced_impact_oscillator"), in);
    EXPECT_NEAR(f.parameter(f.info().parameter_index("sigma")), -2.0, 1e-14);
    const physical_scales k = scales_at(in, m);
    EXPECT_EQ(k.length, 0.0025);
    EXPECT_NEAR(k.energy(), 3.0 * 0.25 * 0.25, 1e-15);
    EXPECT_NEAR(k.power(), 3.0 * 0.25 * 0.25 / 0.01, 1e-13);
}

TEST(SIUnits, StatisticsInSIAreTheModelsTimesTheScales)
{
    impact_statistics s;
    s.impacts = 10;
    s.duration = 50.0;
    s.rate = 0.2;
    s.velocity_min = 0.1;
    s.velocity_mean = 0.2;
    s.velocity_rms = 0.25;
    s.velocity_max = 0.3;
    s.energy_per_impact = 0.01;
    s.power = 0.002;
    s.contact_fraction = 0.25;
    s.excursion = 0.4;
    s.excursion_by_surface = {0.4};
    const physical_scales k{.length = 0.02, .time = 0.004, .mass = 0.9};
    const impact_statistics o = in_si(s, k);
    const double v = 0.02 / 0.004;  // m/s per model unit
    EXPECT_EQ(o.impacts, 10);
    EXPECT_NEAR(o.duration, 0.2, 1e-15);
    EXPECT_NEAR(o.rate, 50.0, 1e-12);
    EXPECT_NEAR(o.velocity_max, 0.3 * v, 1e-15);
    EXPECT_NEAR(o.velocity_rms, 0.25 * v, 1e-15);
    EXPECT_NEAR(o.energy_per_impact, 0.01 * 0.9 * v * v, 1e-15);
    EXPECT_NEAR(o.power, 0.002 * 0.9 * v * v / 0.004, 1e-12);
    EXPECT_EQ(o.contact_fraction, 0.25);
    EXPECT_NEAR(o.excursion, 0.008, 1e-17);
    EXPECT_NEAR(o.excursion_by_surface[0], 0.008, 1e-17);
}

TEST(SIUnits, BadInputsAreNamed)
{
    const auto without = [](const char* key) {
        pairs p;
        for (const auto& kv : tube())
            if (kv.first != key) p.push_back(kv);
        return p;
    };
    const auto with = [](const char* key, double v) {
        pairs p = tube();
        for (auto& kv : p)
            if (kv.first == key) kv.second = v;
        return p;
    };
    EXPECT_NE(message_of(with("rho", -1000)).find("rho (fluid density, kg/m^3) must be"), std::string::npos);
    EXPECT_NE(message_of(with("D", 0.0)).find("D (diameter, m) must be"), std::string::npos);
    pairs gap = tube();
    gap.emplace_back("gap", -0.001);
    EXPECT_NE(message_of(gap).find("gap (distance to the neighbouring surface, m) must be a finite number >= 0"),
              std::string::npos);
    EXPECT_NE(message_of(without("fn")).find("missing fn"), std::string::npos);
    pairs both = tube();
    both.emplace_back("length", 1.0);
    EXPECT_NE(message_of(both).find("not both"), std::string::npos);
    EXPECT_NE(message_of({{"length", 1.0}, {"time", 1.0}, {"U", 3.0}}).find("U (flow speed) needs a cylinder"),
              std::string::npos);
    // The wake model's parameters do not exist in the two-stop model.
    EXPECT_THROW((void)apply_si(model::builtin("two_sided_impact_oscillator"), si_from_pairs(tube())), input_error);
}

TEST(SIUnits, InputsThatTogetherGiveNoNumberAreRefused)
{
    // Each in its range, together out of a double's: D^2 overflows (mu would be inf / inf, a
    // NaN), rho D^2 underflows to 0, the mass from mstar overflows. Named with the inputs and
    // the range, whatever the front end; never a NaN in a result.
    const auto with = [](std::initializer_list<std::pair<std::string, double>> changed) {
        pairs p = tube();
        for (const auto& [k, v] : changed)
            for (auto& kv : p)
                if (kv.first == k) kv.second = v;
        return message_of(p);
    };
    const std::string range = "is outside the range of a double: the inputs must keep its magnitude in "
                              "[2.2250738585072014e-308, 1.7976931348623157e+308]";
    EXPECT_EQ(with({{"D", 1e300}}), "rho D^2 = inf from rho = 1000, D = 1e+300 " + range);
    EXPECT_EQ(with({{"D", 1e-200}}), "rho D^2 = 0 from rho = 1000, D = 1e-200 " + range);
    EXPECT_EQ(with({{"m", 1e308}, {"rho", 1e-300}}),
              "mu = (m + CM rho pi D^2 / 4) / (rho D^2) = inf from m = 1e+308, CM = 1, rho = 1e-300, D = 0.02 " + range +
                  " or 0");
    EXPECT_NE(message_of({{"D", 1.0}, {"mstar", 1e306}, {"fn", 12.0}, {"zeta", 0.0}, {"rho", 1e5}})
                  .find("m = mstar rho pi D^2 / 4 = inf from mstar = 1e+306, rho = 1e+05, D = 1"),
              std::string::npos);
    // The flow speed: Ur and the scales at U must be numbers too.
    pairs fast = tube();
    fast.emplace_back("U", 1e308);
    EXPECT_EQ(message_of(fast), "Ur = U / (fn D) = inf from U = 1e+308, fn = 12, D = 0.02 " + range);
    const cylinder_in_flow c = *si_from_pairs(tube()).cylinder;
    EXPECT_THROW((void)units_at(c, 1e308), input_error);
    EXPECT_THROW((void)reynolds_number(c, 1e308), input_error);
    // Scales given directly: the energy unit mass (length / time)^2 must be a number.
    EXPECT_NE(message_of({{"length", 1e200}, {"time", 1e-200}}).find("the velocity scale = inf"), std::string::npos);
    EXPECT_NE(message_of({{"length", 1e100}, {"time", 1e-100}, {"mass", 1e200}}).find("the energy scale = inf"),
              std::string::npos);
    // Ordinary inputs are untouched.
    EXPECT_EQ(message_of(tube()), "");
}

TEST(SIUnits, CalibrationWarnings)
{
    pairs p = tube();
    p.emplace_back("U", 4.0);
    const si_input in = si_from_pairs(p);
    EXPECT_TRUE(validity_warnings(in, apply_si(model{}, in)).empty());  // Re 8e4, m* 1.91
    pairs fast = tube();
    fast.emplace_back("U", 10.0);  // Re = 10 * 0.02 / 1e-6 = 2e5
    const si_input f = si_from_pairs(fast);
    const auto w = validity_warnings(f, apply_si(model{}, f));
    ASSERT_EQ(w.size(), 1u);
    EXPECT_NE(w[0].find("Re = U D / nu = 200000"), std::string::npos);
    pairs air = tube();
    for (auto& kv : air)
        if (kv.first == "rho") kv.second = 1.2;  // m* = 0.6 / (1.2 pi 0.0001) = 1592
    const si_input a = si_from_pairs(air);
    const auto wa = validity_warnings(a, apply_si(model{}, a).with_parameter(0, 10.0));
    ASSERT_FALSE(wa.empty());
    EXPECT_NE(wa.back().find("mass ratio"), std::string::npos);
}

TEST(SIUnits, ClearanceIsTheGrazingValueAtTheMatchingReducedVelocity)
{
    pairs p = tube();
    const si_input in = si_from_pairs(p);
    const model m = apply_si(model{}, in);
    const double U = 4.5;
    clearance_options o;
    o.parameter = si_parameter(in, m, "U");
    o.values = {si_parameter_value(in, m, "U", U)};
    o.fractions = {0.5, 1.2};
    o.protocol.transient_impacts = 100;
    o.protocol.record_points = 50;
    const clearance_result r = clearance(m, o);
    ASSERT_EQ(r.points.size(), 1u);
    // Directly: the grazing analysis at Ur = U / (fn D) = 18.75, sigma_graze times -D.
    grazing_options go = job_grazing_options(o.protocol.flow.integration);
    go.parameter = m.info().parameter_index("sigma");
    const model at = m.with_parameter(o.parameter, 4.5 / (12 * 0.02));
    const grazing_result g = grazing(at, m.initial_state(), go);
    const double sigma_graze = g.surfaces[0].parameter_value;
    EXPECT_EQ(r.points[0].grazing_value, sigma_graze);
    EXPECT_EQ(r.points[0].clearance, -sigma_graze);
    EXPECT_NEAR(r.points[0].clearance * length_scale(in), -sigma_graze * 0.02, 1e-17);
    EXPECT_TRUE(r.points[0].converged);
    // Half the clearance impacts; 1.2 times it does not (the surface-free orbit clears it).
    ASSERT_EQ(r.points[0].cells.size(), 2u);
    EXPECT_GT(r.points[0].cells[0].statistics.impacts, 0);
    EXPECT_EQ(r.points[0].cells[1].label.label, "P0");
    EXPECT_NEAR(r.points[0].cells[1].gap, 1.2 * -sigma_graze, 1e-15);
}

TEST(SIUnits, MassRatioAndStiffnessInsteadOfMassAndFrequency)
{
    // The model's own mass ratio: Facchinetti et al.'s m* = 0.52 with C_M = 1 is the default
    // mu = (m* + C_M) pi / 4 = 1.19381 (the parameter's description), for any D and rho.
    const si_input a = si_from_pairs({{"D", 0.5}, {"mstar", 0.52}, {"fn", 0.1}, {"zeta", 0.01}, {"rho", 1025.0}});
    const model m = apply_si(model{}, a);
    EXPECT_NEAR(m.parameter(m.info().parameter_index("mu")), 1.19381, 5e-6);
    EXPECT_NEAR(m.parameter(m.info().parameter_index("mu")), 1.52 * pi / 4, 1e-14);
    // m* = 3 on the 20 mm tube in water: m = 0.3 pi kg/m, with the added mass 0.4 pi kg/m; a
    // stiffness k = 160 pi^3 N/m^2 = 0.4 pi (2 pi 10 Hz)^2 makes fn = 10 Hz, so Ur = U / 0.2.
    const si_input b = si_from_pairs(
        {{"D", 0.02}, {"mstar", 3.0}, {"k", 160 * pi * pi * pi}, {"zeta", 0.002}, {"rho", 1000.0}, {"U", 3.0}});
    ASSERT_TRUE(b.cylinder);
    EXPECT_NEAR(b.cylinder->mass, 0.3 * pi, 1e-15);
    EXPECT_NEAR(b.cylinder->natural_frequency, 10.0, 1e-13);
    const model mb = apply_si(model{}, b);
    EXPECT_NEAR(mb.parameter(mb.info().parameter_index("Ur")), 15.0, 1e-12);
    EXPECT_NEAR(mb.parameter(mb.info().parameter_index("mu")), pi, 1e-14);  // (3 + 1) pi / 4
    // Echoed as given, with the m and fn they give.
    std::map<std::string, double> echo;
    for (const auto& [name, v] : si_inputs(b)) echo[name] = v;
    EXPECT_EQ(echo.at("mstar"), 3.0);
    EXPECT_EQ(echo.at("k"), 160 * pi * pi * pi);
    EXPECT_NEAR(echo.at("m"), 0.3 * pi, 1e-15);
    EXPECT_NEAR(echo.at("fn"), 10.0, 1e-13);
    EXPECT_FALSE(echo.count("CL0"));
}

TEST(SIUnits, ExactlyOneOfEachPairOfAlternatives)
{
    const pairs rest{{"D", 0.02}, {"zeta", 0.002}, {"rho", 1000.0}};
    const auto with = [&](pairs more) {
        pairs p = rest;
        p.insert(p.end(), more.begin(), more.end());
        return message_of(p);
    };
    EXPECT_NE(with({{"m", 0.6}, {"mstar", 2.0}, {"fn", 12.0}}).find("m (structural mass per unit length, kg/m) and "
                                                                     "mstar (mass ratio m / (rho pi D^2 / 4))"),
              std::string::npos);
    EXPECT_NE(with({{"fn", 12.0}}).find("missing m (structural mass per unit length, kg/m) or mstar"),
              std::string::npos);
    EXPECT_NE(with({{"m", 0.6}, {"fn", 12.0}, {"k", 5000.0}}).find("fn (natural frequency in still fluid, Hz) and k"),
              std::string::npos);
    EXPECT_NE(with({{"m", 0.6}}).find("missing fn (natural frequency in still fluid, Hz) or k (stiffness per unit "
                                      "length, N/m^2)"),
              std::string::npos);
    EXPECT_NE(with({{"mstar", -1.0}, {"fn", 12.0}}).find("mstar (mass ratio m / (rho pi D^2 / 4)) must be a finite "
                                                         "number >= 0"),
              std::string::npos);
    EXPECT_NE(with({{"m", 0.6}, {"k", 0.0}}).find("k (stiffness per unit length, N/m^2) must be a finite number > 0"),
              std::string::npos);
    EXPECT_EQ(with({{"mstar", 2.0}, {"k", 5000.0}}), "");
}

TEST(SIUnits, LiftCoefficientSetsTheModelsAndIsEchoed)
{
    const model paper = model::builtin("wake_impact");
    const int cl = paper.info().parameter_index("CL0");
    // Without CL0 the model keeps its own: the paper preset's back-fitted 0.05 * 16 pi^2 * 0.2^2
    // (M = 0.05 / mu at St = 0.2), or the facchinetti preset's 0.3.
    const si_input in = si_from_pairs(tube());
    const auto value_of = [](const std::vector<named_value>& v, const std::string& name) {
        for (const auto& [n, x] : v)
            if (name == n) return x;
        return std::nan("");
    };
    EXPECT_NEAR(value_of(si_values(in, apply_si(paper, in)), "CL0"), 0.05 * 16 * pi * pi * 0.04, 1e-15);
    const model facchinetti = paper.with_preset(paper.info().preset_index("facchinetti"));
    EXPECT_EQ(value_of(si_values(in, apply_si(facchinetti, in)), "CL0"), 0.3);
    // Given, it sets the model's parameter, whatever the preset.
    pairs p = tube();
    p.emplace_back("CL0", 0.25);
    const si_input given = si_from_pairs(p);
    EXPECT_EQ(apply_si(facchinetti, given).parameter(cl), 0.25);
    EXPECT_EQ(value_of(si_inputs(given), "CL0"), 0.25);
    p.back().second = -0.1;
    EXPECT_NE(message_of(p).find("CL0 (lift coefficient of the fixed cylinder) must be a finite number >= 0"),
              std::string::npos);
}

TEST(SIUnits, StateDimensionsReadOffTheModels)
{
    using d = physical_dimension;
    // The paper's y (gap y - sigma) and its velocity; the wake variable and its rate have none.
    EXPECT_EQ(state_dimensions(model::builtin("wake_impact")), (std::vector<d>{d::length, d::velocity, d::none, d::none}));
    // The forced oscillator's y, ydot and its forcing phase; the two stops' x, v and phase.
    EXPECT_EQ(state_dimensions(model::builtin("forced_impact_oscillator")), (std::vector<d>{d::length, d::velocity, d::none}));
    EXPECT_EQ(state_dimensions(model::builtin("two_sided_impact_oscillator")),
              (std::vector<d>{d::length, d::velocity, d::none}));
    const physical_scales k{.length = 0.02, .time = 0.004, .mass = 1.0};
    EXPECT_EQ(k.of(d::length), 0.02);
    EXPECT_NEAR(k.of(d::velocity), 5.0, 1e-15);
    EXPECT_TRUE(std::isnan(k.of(d::none)));
}

TEST(SIUnits, FrequencyScaleGivesTheTubesNaturalFrequency)
{
    // The model's structure oscillates at angular frequency delta = 1 / (St Ur) per unit of
    // model time: in hertz it must be the tube's fn = 12 Hz at any flow speed.
    for (const double U : {1.0, 4.0}) {
        pairs p = tube();
        p.emplace_back("U", U);
        const si_input in = si_from_pairs(p);
        const model m = apply_si(model{}, in);
        const double delta = 1.0 / (0.2 * m.parameter(m.info().parameter_index("Ur")));
        EXPECT_NEAR(delta * scales_at(in, m).frequency(), 12.0, 1e-12) << U;
    }
}

TEST(SIUnits, QuantitiesBackFromTheirParameters)
{
    // Ur = 20 is U = 20 fn D = 4.8 m/s; sigma = -0.1 is a gap of 0.1 D = 2 mm.
    const si_input in = si_from_pairs(tube());
    const model m = apply_si(model{}, in);
    EXPECT_NEAR(si_quantity_value(in, m, "U", 20.0), 4.8, 1e-14);
    EXPECT_NEAR(si_quantity_value(in, m, "gap", -0.1), 0.002, 1e-17);
    // The two stops at +-d: the gap to either is d model units.
    const si_input two = si_from_pairs({{"length", 0.0025}, {"time", 0.01}});
    const model t = model::builtin("two_sided_impact_oscillator");
    EXPECT_NEAR(gap_to(two, t.with_parameter(t.info().parameter_index("d"), 2.0), 1), 0.005, 1e-17);
}

}  // namespace
