// Every analysis on the built-in model forced_impact_oscillator, compiled natively (see src/dispatch.hpp); its
// SIMD lanes are in forced_impact_oscillator_lanes.cpp.
#include "engine_instances.ipp"

VIMPACT_INSTANTIATE_ENGINE(vimpact::native_model<vimpact::forced_impact_oscillator>)
