#pragma once
// Work that polls the caller's cancel flag (a `const std::atomic<bool>*`, set by a signal
// handler or by Python's Ctrl-C check) and has no outcome value to end with, such as loading
// a model file (its symbolic derivatives, its compiler run), throws `cancelled` once it is
// set, after undoing what it started. The analyses end with the outcome `interrupted`
// instead. The CLI maps it to exit code 130.
#include <stdexcept>

namespace vimpact {

class cancelled : public std::runtime_error {
public:
    cancelled() : std::runtime_error("interrupted") {}
};

}  // namespace vimpact
