#include "vimpact/physical/si_units.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

#include "vimpact/analysis/clearance.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/model/model_phrases.hpp"
#include "vimpact/physical/checked_input.hpp"

namespace vimpact {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr const char* cylinder_text = "D, m or mstar, fn or k, zeta, rho";
constexpr const char* gap_text = "distance to the neighbouring surface, m";

const std::vector<std::string>& cylinder_keys()
{
    static const std::vector<std::string> keys{"D", "m", "mstar", "fn", "k", "zeta", "rho", "CM", "St", "nu", "CL0"};
    return keys;
}
const std::vector<std::string>& scale_keys()
{
    static const std::vector<std::string> keys{"length", "time", "mass"};
    return keys;
}
bool among(const std::vector<std::string>& keys, const std::string& k)
{
    return std::find(keys.begin(), keys.end(), k) != keys.end();
}

int named_parameter(const model& m, const char* name, const char* why)
{
    const int i = m.info().parameter_index(name);
    if (i < 0)
        throw input_error(std::string(why) + " sets the wake model's parameter " + name + ", which model " + m.name() +
                          " does not have (" + parameters_it_has(m.info()) + ")");
    return i;
}

// The first gap parameter and the first surface it moves.
std::pair<int, int> gap_parameter_and_surface(const model& m)
{
    const int p = first_gap_parameter(m);
    return {p, p < 0 ? -1 : surface_moved_by(m, p)};
}

// Exactly one of two keys that give the same quantity (m or mstar, fn or k): the one given.
const char* one_of(const std::map<std::string, double>& v, const char* a, const char* a_is, const char* b,
                   const char* b_is)
{
    const std::string what = std::string(a) + " (" + a_is + ") or " + b + " (" + b_is + ")";
    if (v.count(a) && v.count(b))
        throw input_error(std::string(a) + " (" + a_is + ") and " + b + " (" + b_is +
                          ") give the same quantity: give one, not both");
    if (!v.count(a) && !v.count(b)) throw input_error("missing " + what + " (keys: " + si_keys() + ")");
    return v.count(a) ? a : b;
}

// The energy and power units (the impact statistics in J and W) of scales whose length, time
// and mass are each in range.
physical_scales checked_scales(const physical_scales& k, std::initializer_list<input_value> from)
{
    derived_value(k.mass, "the mass scale", from);
    derived_value(k.velocity(), "the velocity scale", from);
    derived_value(k.energy(), "the energy scale", from);
    derived_value(k.power(), "the power scale", from);
    return k;
}

}  // namespace

double length_scale(const si_input& in)
{
    if (in.cylinder) return in.cylinder->diameter;
    if (in.scales) return in.scales->length;
    return nan;
}

double physical_scales::frequency() const { return 1.0 / (2.0 * std::numbers::pi * time); }

double physical_scales::of(physical_dimension d) const
{
    switch (d) {
    case physical_dimension::length: return length;
    case physical_dimension::velocity: return velocity();
    case physical_dimension::none: break;
    }
    return nan;
}

std::string si_keys()
{
    return "D, m or mstar, fn or k, zeta, rho for a cylinder in a flow (CM, St, nu, CL0 optional), or length, time "
           "for any model (mass optional); U (flow speed, m/s, with a cylinder) and gap (m)";
}

si_input si_from_pairs(const std::vector<std::pair<std::string, double>>& pairs)
{
    std::map<std::string, double> v;
    for (const auto& [k, x] : pairs) {
        if (!among(cylinder_keys(), k) && !among(scale_keys(), k) && k != "U" && k != "gap")
            throw input_error("unknown key '" + k + "' (keys: " + si_keys() + ")");
        if (!v.emplace(k, x).second) throw input_error(k + " is given twice");
    }
    const bool cyl = std::any_of(cylinder_keys().begin(), cylinder_keys().end(), [&](const auto& k) { return v.count(k); });
    const bool sc = std::any_of(scale_keys().begin(), scale_keys().end(), [&](const auto& k) { return v.count(k); });
    if (cyl && sc)
        throw input_error(std::string("give either a cylinder (") + cylinder_text +
                          ") or the model's units (length, time), not both");
    if (!cyl && !sc)
        throw input_error(std::string("missing a cylinder (") + cylinder_text + ") or the model's units (length, time)");
    si_input in;
    if (cyl) {
        for (const char* key : {"D", "zeta", "rho"})
            if (!v.count(key)) throw input_error(std::string("missing ") + key + " (keys: " + si_keys() + ")");
        const char* mass = one_of(v, "m", "structural mass per unit length, kg/m", "mstar",
                                  "mass ratio m / (rho pi D^2 / 4)");
        const char* frequency = one_of(v, "fn", "natural frequency in still fluid, Hz", "k",
                                       "stiffness per unit length, N/m^2");
        cylinder_in_flow c;
        c.diameter = v.at("D");
        c.damping_ratio = v.at("zeta");
        c.fluid_density = v.at("rho");
        if (v.count("CM")) c.added_mass_coefficient = v.at("CM");
        if (v.count("St")) c.strouhal = v.at("St");
        if (v.count("nu")) c.kinematic_viscosity = v.at("nu");
        // The alternatives to m and fn (flow_units.hpp): fn from k needs the mass, so m first.
        if (mass == std::string("mstar")) in.mass_ratio = v.at("mstar");
        c.mass = in.mass_ratio ? mass_from_ratio(c, *in.mass_ratio) : v.at("m");
        if (frequency == std::string("k")) in.stiffness = v.at("k");
        c.natural_frequency = in.stiffness ? natural_frequency_from_stiffness(c, *in.stiffness) : v.at("fn");
        validate(c);
        in.cylinder = c;
        if (v.count("CL0"))
            in.lift_coefficient = non_negative_input(v.at("CL0"), "CL0", "lift coefficient of the fixed cylinder");
    } else {
        for (const char* key : {"length", "time"})
            if (!v.count(key)) throw input_error(std::string("missing ") + key + " (keys: " + si_keys() + ")");
        physical_scales s{.length = v.at("length"), .time = v.at("time"), .mass = v.count("mass") ? v.at("mass") : 1.0};
        for (const auto& [name, x] : {std::pair{"length", s.length}, {"time", s.time}, {"mass", s.mass}})
            positive_input(x, name, "one model unit in SI");
        in.scales = checked_scales(s, {{"length", s.length}, {"time", s.time}, {"mass", s.mass}});
    }
    if (v.count("U")) {
        if (!in.cylinder) throw input_error(std::string("U (flow speed) needs a cylinder (") + cylinder_text + ")");
        in.speed = positive_input(v.at("U"), "U", "flow speed, m/s");
        (void)dimensionless(*in.cylinder, *in.speed);  // Ur and the scales at U are numbers
    }
    if (v.count("gap")) in.gap = non_negative_input(v.at("gap"), "gap", gap_text);
    return in;
}

std::vector<named_value> si_inputs(const si_input& in)
{
    std::vector<named_value> out;
    if (in.cylinder) {
        const cylinder_in_flow& c = *in.cylinder;
        out.push_back({"D", c.diameter});
        out.push_back({"m", c.mass});
        if (in.mass_ratio) out.push_back({"mstar", *in.mass_ratio});
        out.push_back({"fn", c.natural_frequency});
        if (in.stiffness) out.push_back({"k", *in.stiffness});
        out.insert(out.end(), {{"zeta", c.damping_ratio},
                               {"rho", c.fluid_density},
                               {"CM", c.added_mass_coefficient},
                               {"St", c.strouhal},
                               {"nu", c.kinematic_viscosity}});
        if (in.lift_coefficient) out.push_back({"CL0", *in.lift_coefficient});
    }
    if (in.scales) out = {{"length", in.scales->length}, {"time", in.scales->time}, {"mass", in.scales->mass}};
    if (in.speed) out.push_back({"U", *in.speed});
    if (in.gap) out.push_back({"gap", *in.gap});
    return out;
}

int si_parameter(const si_input& in, const model& m, std::string_view quantity)
{
    if (quantity == "U") {
        if (!in.cylinder)
            throw input_error(std::string("U (flow speed) needs a cylinder among the SI inputs (") + cylinder_text + ")");
        return named_parameter(m, "Ur", "the flow speed U");
    }
    if (quantity == "gap") {
        const int p = gap_parameter_and_surface(m).first;
        if (p < 0)
            throw input_error("gap: model " + m.name() +
                              " has no parameter that moves a surface without entering the vector field");
        return p;
    }
    return -1;
}

double si_parameter_value(const si_input& in, const model& m, std::string_view quantity, double value)
{
    if (quantity == "U") {
        positive_input(value, "U", "flow speed, m/s");
        (void)si_parameter(in, m, quantity);
        return dimensionless(*in.cylinder, value).Ur;
    }
    if (quantity == "gap") {
        non_negative_input(value, "gap", gap_text);
        const auto [p, surface] = gap_parameter_and_surface(m);
        if (p < 0) (void)si_parameter(in, m, quantity);  // the message
        const double P = parameter_for_gap(m, surface, p, m.initial_state(), value / length_scale(in));
        if (!std::isfinite(P))
            throw input_error("gap = " + format_double(value) + " m has no value of " +
                              m.info().parameters[static_cast<std::size_t>(p)].name + " in its range");
        return P;
    }
    throw input_error("'" + std::string(quantity) + "' is not an SI quantity (U, gap)");
}

value_grid si_parameter_grid(const si_input& in, const model& m, std::string_view quantity, const value_grid& given)
{
    if (si_parameter(in, m, quantity) < 0)
        throw input_error("'" + std::string(quantity) + "' is not an SI quantity (U, gap)");
    // The map is part of what the run is: the quantity and the inputs it is converted with.
    std::string what = std::string(quantity) + " in SI with";
    for (const auto& [key, v] : si_inputs(in)) what += std::string(" ") + key + "=" + format_double(v);
    return given.mapped([in, m, q = std::string(quantity)](double v) { return si_parameter_value(in, m, q, v); },
                        std::move(what));
}

double si_quantity_value(const si_input& in, const model& m, std::string_view quantity, double value)
{
    const int p = si_parameter(in, m, quantity);
    if (p < 0) throw input_error("'" + std::string(quantity) + "' is not an SI quantity (U, gap)");
    const model at = m.with_parameter(p, value);
    return quantity == "U" ? flow_speed_of(in, at) : gap_of(in, at);
}

std::vector<std::pair<int, double>> si_parameters(const model& m, const si_input& in)
{
    std::vector<std::pair<int, double>> out;
    if (in.cylinder) {
        const cylinder_in_flow& c = *in.cylinder;
        // mu, xi and St do not depend on the speed: any speed gives them.
        const wake_dimensionless d = dimensionless(c, in.speed.value_or(1.0));
        out.emplace_back(named_parameter(m, "mu", "the cylinder (D, m, rho, CM)"), d.mu);
        out.emplace_back(named_parameter(m, "xi", "the damping ratio zeta"), d.xi);
        out.emplace_back(named_parameter(m, "St", "the Strouhal number St"), d.St);
        if (in.lift_coefficient)
            out.emplace_back(named_parameter(m, "CL0", "the lift coefficient CL0"), *in.lift_coefficient);
        if (in.speed) out.emplace_back(si_parameter(in, m, "U"), d.Ur);
    }
    if (in.gap) out.emplace_back(si_parameter(in, m, "gap"), si_parameter_value(in, m, "gap", *in.gap));
    std::sort(out.begin(), out.end());
    return out;
}

model apply_si(const model& m, const si_input& in)
{
    std::vector<double> values = m.parameters();
    for (const auto& [i, v] : si_parameters(m, in)) values[static_cast<std::size_t>(i)] = v;
    return m.with_parameters(values);
}

double flow_speed_of(const si_input& in, const model& m)
{
    if (!in.cylinder) return nan;
    return flow_speed(*in.cylinder, m.parameter(named_parameter(m, "Ur", "the flow speed U")));
}

double gap_of(const si_input& in, const model& m)
{
    const int surface = gap_parameter_and_surface(m).second;
    return surface < 0 ? nan : gap_to(in, m, surface);
}

double gap_to(const si_input& in, const model& m, int surface) { return rest_gap(m, surface) * length_scale(in); }

physical_scales scales_at(const si_input& in, const model& m)
{
    if (in.scales) return *in.scales;  // checked when given
    const cylinder_in_flow& c = *in.cylinder;
    const double U = flow_speed_of(in, m);
    const flow_scales f = scales(c, U);
    const double mu = dimensionless(c, U).mu;
    return checked_scales({.length = f.length, .time = f.time, .mass = mu * c.fluid_density * c.diameter * c.diameter},
                          {{"D", c.diameter}, {"m", c.mass}, {"CM", c.added_mass_coefficient}, {"rho", c.fluid_density},
                           {"St", c.strouhal}, {"U", U}});
}

impact_statistics in_si(const impact_statistics& s, const physical_scales& k)
{
    impact_statistics o = s;
    o.duration = s.duration * k.time;
    o.rate = s.rate / k.time;
    o.velocity_min = s.velocity_min * k.velocity();
    o.velocity_mean = s.velocity_mean * k.velocity();
    o.velocity_rms = s.velocity_rms * k.velocity();
    o.velocity_max = s.velocity_max * k.velocity();
    o.energy_per_impact = s.energy_per_impact * k.energy();
    o.power = s.power * k.power();
    o.excursion = s.excursion * k.length;
    for (auto& g : o.excursion_by_surface) g *= k.length;
    return o;
}

std::vector<double> gaps_in_model_units(const si_input& in, const std::vector<double>& metres)
{
    std::vector<double> out;
    for (const double g : metres) {
        if (!(g >= 0.0) || !std::isfinite(g))
            throw input_error("gap " + format_double(g) +
                              " m is below zero (a gap is the distance from the rest state to the surface)");
        out.push_back(g / length_scale(in));
    }
    return out;
}

clearance_result in_si(const clearance_result& r, const si_input& in, const model& m, int parameter)
{
    clearance_result o = r;
    const double L = length_scale(in);
    for (auto& p : o.points) {
        const physical_scales k = scales_at(in, m.with_parameter(parameter, p.value));
        p.clearance *= L;
        p.aperiodic_min *= L;
        p.aperiodic_max *= L;
        for (auto& c : p.cells) {
            c.gap *= L;
            c.statistics = in_si(c.statistics, k);
        }
    }
    return o;
}

std::vector<named_value> si_values(const si_input& in, const model& m)
{
    std::vector<named_value> out;
    if (in.cylinder) {
        const double U = flow_speed_of(in, m);
        out.push_back({"U", U});
        out.push_back({"Re", reynolds_number(*in.cylinder, U)});
        out.push_back({"mass_ratio", mass_ratio(*in.cylinder)});
        // The lift coefficient the run uses: CL0 from --si, else the model's (its preset's).
        if (const int cl = m.info().parameter_index("CL0"); cl >= 0) out.push_back({"CL0", m.parameter(cl)});
    }
    out.push_back({"gap", gap_of(in, m)});
    const physical_scales k = scales_at(in, m);
    out.push_back({"length_scale", k.length});
    out.push_back({"time_scale", k.time});
    out.push_back({"mass_scale", k.mass});
    out.push_back({"velocity_scale", k.velocity()});
    out.push_back({"energy_scale", k.energy()});
    out.push_back({"power_scale", k.power()});
    return out;
}

std::vector<std::string> validity_warnings(const si_input& in, const model& m)
{
    if (!in.cylinder) return {};
    return validity_warnings(*in.cylinder, flow_speed_of(in, m));
}

}  // namespace vimpact
