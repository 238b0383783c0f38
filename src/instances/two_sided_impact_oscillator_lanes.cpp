// The job commands' SIMD lanes on the built-in model two_sided_impact_oscillator, part of its module, in a translation
// unit of its own: it is compiled with the options that make the compiler move a lane value
// whole (CMakeLists.txt, VIMPACT_LANE_MOVE_OPTIONS), which would slow the other analyses'
// tangent runs.
#include "engine_instances.ipp"

VIMPACT_ENGINE_LANES(vimpact::native_model<vimpact::two_sided_impact_oscillator>)
