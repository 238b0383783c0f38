#pragma once
// The protocol's options a user sets by name (core/option.hpp), declared once for every front
// end: the command line's options and config keys, Python's keywords, and the one check
// (validate(protocol_options)). Apart from analysis/protocol.hpp, which the engine's
// instantiations include, so that a change here rebuilds the front ends only.
//
// The section is not among them: its name is resolved against the model by each front end.
// Nor is sample_dt: simulate's time series, which each front end names and documents itself.
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/option.hpp"
#include "vimpact/core/record.hpp"
#include "vimpact/integrate/integrator_declaration.hpp"

namespace vimpact {

// The upper ends of transient and record are far beyond any use (a billion impacts is days of
// one run; ten million points are 400 MB): they refuse an overflowed or mistyped value instead
// of running it to a time limit or out of memory.
template <class V, record_of<protocol_options> O>
void declare(V& v, O& o)
{
    v(option{"transient", "impacts discarded before recording, 500 in the paper", between(0.0, 1e9)},
      o.transient_impacts);
    v(option{"record", "section points kept, 200 in the paper", between(1.0, 1e7)}, o.record_points);
    v(option{"method", "Runge-Kutta pair: DOP853 (8th order, 7th-order interpolant) or DOPRI5"}, o.method,
      all_integration_methods);
    declare(v, o.flow.integration);
    v(option{"quiet_time", "no impact for this long means the orbit has left the surfaces (label P0); the points "
                           "recorded from then on describe the surface-free steady state",
             or_infinite(above(0.0))},
      o.quiet_time);
    v(option{"t_max", "the run ends with outcome time_limit at this time", or_infinite(above(0.0))}, o.flow.t_max);
}

}  // namespace vimpact
