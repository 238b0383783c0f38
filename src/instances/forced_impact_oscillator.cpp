// The module of the built-in model forced_impact_oscillator (libvimpact_engine_forced_impact_oscillator.so): every analysis and the
// steppable systems on its native definition (see src/engine_instances.hpp); its SIMD lanes are
// in forced_impact_oscillator_lanes.cpp.
#include "engine_instances.ipp"

VIMPACT_ENGINE_MODULE(vimpact::native_model<vimpact::forced_impact_oscillator>)
