// Every analysis on the built-in model forced_impact_oscillator, compiled natively (see src/dispatch.hpp).
#include "engine_instances.ipp"

VIMPACT_INSTANTIATE_ENGINE(vimpact::native_model<vimpact::forced_impact_oscillator>)
VIMPACT_INSTANTIATE_LANES(vimpact::native_model<vimpact::forced_impact_oscillator>)
