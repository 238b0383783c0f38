// Every analysis on the built-in model wake_impact, compiled natively (see src/dispatch.hpp).
#include "engine_instances.ipp"

VIMPACT_INSTANTIATE_ENGINE(vimpact::native_model<vimpact::wake_impact>)
VIMPACT_INSTANTIATE_LANES(vimpact::native_model<vimpact::wake_impact>)
