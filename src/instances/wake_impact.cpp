// The module of the built-in model wake_impact (libvimpact_engine_wake_impact.so): every analysis and the
// steppable systems on its native definition (see src/engine_instances.hpp); its SIMD lanes are
// in wake_impact_lanes.cpp.
#include "engine_instances.ipp"

VIMPACT_ENGINE_MODULE(vimpact::native_model<vimpact::wake_impact>)
