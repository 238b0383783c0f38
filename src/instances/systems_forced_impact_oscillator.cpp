// The steppable systems (include/vimpact/system/) on the built-in model forced_impact_oscillator, compiled natively
// (see src/dispatch.hpp), apart from its analyses (src/instances/forced_impact_oscillator.cpp).
#include "system/system_engines.ipp"

VIMPACT_INSTANTIATE_SYSTEMS(vimpact::native_model<vimpact::forced_impact_oscillator>)
