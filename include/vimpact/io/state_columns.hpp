#pragma once
// The columns in which front ends write a model's states and impacts (CSV files, tables), so
// that every front end names them the same way for any model.
//
// States: one column per state variable, named after it.
// Impacts: the state just before the reset, one column per state variable, except that a
// variable some surface's reset changes is written twice, NAME_before and NAME_after; for the
// paper's model that is y, ydot_before, ydot_after, x, xdot (the reset keeps y = sigma and
// reverses ydot).
#include <string>
#include <vector>

#include "vimpact/model/model.hpp"

namespace vimpact {

struct impact_column {
    std::string name;
    int variable = 0;    // the state variable
    bool after = false;  // the value after the reset (else before)
};

std::vector<std::string> state_columns(const model_info& info);

std::vector<impact_column> impact_columns(const model& m);

// Whether the reset of some surface changes each state variable, probed at a few states
// moved onto each surface (a variable the reset sets to the value it has on the surface,
// like the paper's y -> sigma, is unchanged).
std::vector<bool> reset_changes(const model& m);

}  // namespace vimpact
