// Every analysis and the steppable systems (include/vimpact/system/) on the built-in model
// wake_impact, compiled natively (see src/dispatch.hpp); its SIMD lanes are in
// wake_impact_lanes.cpp.
#include "engine_instances.ipp"
#include "system/system_engines.ipp"

VIMPACT_INSTANTIATE_ENGINE(vimpact::native_model<vimpact::wake_impact>)
VIMPACT_INSTANTIATE_SYSTEMS(vimpact::native_model<vimpact::wake_impact>)
