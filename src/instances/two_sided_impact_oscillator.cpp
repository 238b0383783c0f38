// The module of the built-in model two_sided_impact_oscillator (libvimpact_engine_two_sided_impact_oscillator.so): every analysis and the
// steppable systems on its native definition (see src/engine_instances.hpp); its SIMD lanes are
// in two_sided_impact_oscillator_lanes.cpp.
#include "engine_instances.ipp"

VIMPACT_ENGINE_MODULE(vimpact::native_model<vimpact::two_sided_impact_oscillator>)
