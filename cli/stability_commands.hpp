#pragma once
// The stability commands: floquet (multipliers of the periodic orbit) and lyapunov (the
// spectrum of exponents), docs/stability.md.
#include "command.hpp"

namespace vimpact::cli {

cli_command add_floquet_command(CLI::App& app);
cli_command add_lyapunov_command(CLI::App& app);

}  // namespace vimpact::cli
