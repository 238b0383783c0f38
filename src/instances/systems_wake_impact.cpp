// The steppable systems (include/vimpact/system/) on the built-in model wake_impact, compiled natively
// (see src/dispatch.hpp), apart from its analyses (src/instances/wake_impact.cpp).
#include "system/system_engines.ipp"

VIMPACT_INSTANTIATE_SYSTEMS(vimpact::native_model<vimpact::wake_impact>)
