#pragma once
// The step-size control's options a user sets by name (core/option.hpp): the tolerances, the
// hold band and the longest step. Apart from integrator_options.hpp, which the engine includes
// everywhere, so that a change of a help text rebuilds the front ends only.
#include "vimpact/core/option.hpp"
#include "vimpact/core/record.hpp"
#include "vimpact/integrate/integrator_options.hpp"

namespace vimpact {

// rtol below 1e-15 asks more than double precision gives; atol below 1e-300 is subnormal.
template <class V, record_of<integrator_options> I>
void declare(V& v, I& in)
{
    v(option{"rtol", "relative tolerance of the adaptive integrator; double precision cannot do better than 1e-15",
             value_range{1e-15, 1.0, true, false}},
      in.rtol);
    v(option{"atol", "absolute tolerance of the adaptive integrator", value_range{1e-300, 1.0, true, false}}, in.atol);
    v(option{"hold_band", "an accepted step whose error norm lies in [hold_band, 1] keeps its step size (faster steps, "
                          "more rejections; docs/performance.md); 0: the controller acts on every step; none: the "
                          "method's, 0.1 with dopri5 and 0 with dop853",
             value_range{0.0, 1.0, true, false}},
      in.hold_band);
    v(option{"max_step", "longest integration step; inf: none, the error control and the resolution of the model's "
                         "gaps and sections set it (docs/model.md)",
             or_infinite(above(0.0))},
      in.h_max);
}

}  // namespace vimpact
