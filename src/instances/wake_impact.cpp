// Every analysis on the built-in model wake_impact, compiled natively (see src/dispatch.hpp); its
// SIMD lanes are in wake_impact_lanes.cpp.
#include "engine_instances.ipp"

VIMPACT_INSTANTIATE_ENGINE(vimpact::native_model<vimpact::wake_impact>)
