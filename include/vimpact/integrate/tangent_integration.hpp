#pragma once
// The accuracy of the tangent runs (Floquet's shooting and monodromy, a continuation's map,
// the grazing search) from the protocol's: they close orbits to 1e-10 and better, which needs
// a map far more accurate than that, so never looser than 1e-12; the protocol's step cap and
// hold band carry over, so that a --max-step that catches a short excursion catches it here too.
#include <algorithm>

#include "vimpact/integrate/integrator_options.hpp"

namespace vimpact {

inline constexpr double loosest_tangent_tolerance = 1e-12;

inline integrator_options tangent_integration(const integrator_options& protocol)
{
    integrator_options t;
    t.rtol = std::min(protocol.rtol, loosest_tangent_tolerance);
    t.atol = std::min(protocol.atol, loosest_tangent_tolerance);
    t.hold_band = protocol.hold_band;
    t.h_max = protocol.h_max;
    return t;
}

}  // namespace vimpact
