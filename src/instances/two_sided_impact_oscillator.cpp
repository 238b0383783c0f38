// Every analysis and the steppable systems (include/vimpact/system/) on the built-in model
// two_sided_impact_oscillator, compiled natively (see src/dispatch.hpp); its SIMD lanes are in
// two_sided_impact_oscillator_lanes.cpp.
#include "engine_instances.ipp"
#include "system/system_engines.ipp"

VIMPACT_INSTANTIATE_ENGINE(vimpact::native_model<vimpact::two_sided_impact_oscillator>)
VIMPACT_INSTANTIATE_SYSTEMS(vimpact::native_model<vimpact::two_sided_impact_oscillator>)
