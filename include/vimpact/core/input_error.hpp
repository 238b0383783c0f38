#pragma once
// Tier-1 errors: misuse or bad input, detected at an entry point. The message names the
// offending input and its valid range; the CLI maps this type to exit code 2.
#include <stdexcept>
#include <string>

namespace vimpact {

class input_error : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

}  // namespace vimpact
