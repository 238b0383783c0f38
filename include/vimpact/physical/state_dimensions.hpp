#pragma once
// Which of a model's state variables are a displacement or a velocity, so that front ends can
// write them in metres and metres per second (si_units.hpp has the scales). A model states no
// dimensions, so they are read off its functions, probed at a few states around its initial
// state:
//   displacement  some surface's gap changes one for one with the variable (dg/dx = +-1 at
//                 every probe): gaps are distances (the gap parameter is set in metres), so
//                 the variable is one too (the paper's y, the two stops' x);
//   velocity      the time derivative of a displacement (dx/dt = v at every probe: ydot, v).
// Every other variable (a wake variable, a forcing phase) is left in the model's units.
#include <string_view>
#include <vector>

#include "vimpact/model/model.hpp"

namespace vimpact {

enum class physical_dimension { none, length, velocity };

std::vector<physical_dimension> state_dimensions(const model& m);

// "m", "m/s", "" (none).
std::string_view si_unit(physical_dimension d);

}  // namespace vimpact
