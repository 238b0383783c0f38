#include "vimpact/model/wake_impact.hpp"

#include <cmath>

namespace vimpact {

wake_impact_parameters wake_impact_preset(std::string_view name)
{
    wake_impact_parameters p;
    if (name == "paper") return p;
    if (name == "facchinetti") {
        p.CL0 = 0.3;
        return p;
    }
    throw input_error("unknown preset '" + std::string(name) + "' (valid: " +
                      wake_impact_preset_names() + ")");
}

std::string wake_impact_preset_names() { return "paper, facchinetti"; }

wake_impact::wake_impact(const wake_impact_parameters& p) : m_p(p)
{
    validate_parameters(m_p, wake_impact_parameter_table());
    m_delta = 1.0 / (m_p.St * m_p.Ur);
    m_delta2 = m_delta * m_delta;
    m_alpha = 2.0 * m_p.xi * m_delta + m_p.gamma / m_p.mu;
    m_M = m_p.CL0 / (16.0 * std::numbers::pi * std::numbers::pi * m_p.St * m_p.St * m_p.mu);
}

wake_impact wake_impact::with(std::string_view name, double value) const
{
    wake_impact_parameters p = m_p;
    set_parameter(p, wake_impact_parameter_table(), name, value);
    return wake_impact(p);
}

}  // namespace vimpact
