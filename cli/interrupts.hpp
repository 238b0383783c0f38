#pragma once
// Ctrl-C and SIGTERM for every command: the first one sets a flag that the runs poll (their
// flow stops with the outcome `interrupted`, the job loop keeps its journal) and that stops
// an output directory from being committed, so an interrupted command exits 130 and leaves
// nothing half-written; a second one ends the program at once (for work that does not poll,
// such as a long correlation sum).
#include <atomic>

#include "vimpact/core/cancelled.hpp"

namespace vimpact::cli {

// Installs the handlers for its lifetime (main holds one) and clears the flag.
class interrupt_guard {
public:
    interrupt_guard();
    ~interrupt_guard();
    interrupt_guard(const interrupt_guard&) = delete;
    interrupt_guard& operator=(const interrupt_guard&) = delete;
};

// Set by the first SIGINT or SIGTERM; a lock-free atomic, so the handler may set it.
const std::atomic<bool>& interrupt_flag();

// Thrown where the work stops for an interruption; main reports it, as the library's own
// `cancelled` (a model file's compilation stopped by the flag), and exits 130.
struct interrupted : vimpact::cancelled {};

// Throws `interrupted` once the flag is set.
void throw_if_interrupted();

}  // namespace vimpact::cli
