// The units command: an engineer's cylinder in SI units to the wake model's dimensionless
// parameters at each flow speed, with the scales that turn the model's outputs back into
// metres, seconds and hertz (include/vimpact/physical/flow_units.hpp has the formulas).
#include <algorithm>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "output.hpp"
#include "parse.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/physical/si_units.hpp"

namespace vimpact::cli {
namespace {

struct units_args {
    std::string si;
    std::string speeds;
    bool json = false;
};

si_input parse_units_si(const std::string& text)
{
    const si_input in = parse_si(text);
    if (!in.cylinder) throw input_error("units needs a cylinder in --si (D, m or mstar, fn or k, zeta, rho)");
    if (in.speed || in.gap) throw input_error("units takes the flow speeds from --speeds; leave U and gap out of --si");
    return in;
}

int run_units(const units_args& a)
{
    const si_input in = parse_units_si(a.si);
    const cylinder_in_flow& c = *in.cylinder;
    const value_grid speeds = parse_range(a.speeds, "--speeds");
    json rows = json::array();
    std::string text;
    // What the alternatives gave (flow_units.hpp): the mass per metre, the still-fluid frequency.
    if (in.mass_ratio) text += "mstar = " + format_double(*in.mass_ratio) + ": m = " + format_double(c.mass) + " kg/m\n";
    if (in.stiffness)
        text += "k = " + format_double(*in.stiffness) + " N/m^2 on m + m_f = " + format_double(c.mass + added_mass(c)) +
                " kg/m: fn = " + format_double(c.natural_frequency) + " Hz\n";
    text += "U [m/s]  Ur  mu  xi  | one model unit: time [s]  velocity [m/s]  frequency [Hz]\n";
    for (const double U : speeds) {
        const wake_dimensionless d = dimensionless(c, U);
        const flow_scales s = scales(c, U);
        json row = json::object();
        for (const auto& [name, value] : units_at(c, U)) row[name] = value;
        rows.push_back(std::move(row));
        text += format_double(U) + "  " + format_double(d.Ur) + "  " + format_double(d.mu) + "  " +
                format_double(d.xi) + "  | " + format_double(s.time) + "  " + format_double(s.velocity) + "  " +
                format_double(s.frequency) + "\n";
    }
    std::vector<std::string> warnings;
    for (const double U : {speeds.front(), speeds.back()})
        for (const auto& w : validity_warnings(c, U))
            if (std::find(warnings.begin(), warnings.end(), w) == warnings.end()) warnings.push_back(w);
    for (const auto& w : warnings) std::cerr << "vimpact: warning: " << w << '\n';
    const wake_dimensionless first = dimensionless(c, speeds.front());
    text += "model parameters: --set mu=" + format_double(first.mu) + " --set xi=" + format_double(first.xi) +
            " --set St=" + format_double(first.St) +
            (in.lift_coefficient ? " --set CL0=" + format_double(*in.lift_coefficient) : std::string()) +
            ", Ur from " + format_double(first.Ur) + " to " +
            format_double(dimensionless(c, speeds.back()).Ur) + "; y in units of D = " + format_double(c.diameter) +
            " m\n";
    json inputs = json::object();
    for (const auto& [name, value] : si_inputs(in)) inputs[name] = value;
    const json summary = {{"command", "units"}, {"si", inputs}, {"dimensionless", rows}, {"warnings", warnings}};
    if (a.json) std::cout << summary.dump() << '\n';
    else std::cout << text;
    return 0;
}

}  // namespace

cli_command add_units_command(CLI::App& app)
{
    auto a = std::make_shared<units_args>();
    auto* s = app.add_subcommand("units",
                                 "A cylinder in a flow in SI units -> the wake model's Ur, mu, xi at each speed, and the "
                                 "scales back to metres, seconds, hertz (Facchinetti et al. 2004)");
    s->add_option("--si", a->si,
                  "D=diameter [m],m=structural mass per length [kg/m] (or mstar=mass ratio m/(rho pi D^2/4)),"
                  "fn=natural frequency in still fluid [Hz] (or k=stiffness per length [N/m^2]),zeta=structural "
                  "damping ratio (free decay in still fluid),rho=fluid density [kg/m^3]; optional CM=added-mass "
                  "coefficient (1), St=Strouhal number (0.2), nu=kinematic viscosity [m^2/s] (1e-6, water) for the "
                  "Reynolds number, CL0=the wake model's lift coefficient (default: the model's)")
        ->required();
    s->add_option("--speeds", a->speeds, "Flow speeds a:b:n [m/s]")->required();
    s->add_flag("--json", a->json, "Print one JSON object to stdout");
    return {s, [a] { return run_units(*a); }};
}

}  // namespace vimpact::cli
