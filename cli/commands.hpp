#pragma once
// The single-run commands: simulate, period, grazing.
#include "command.hpp"

namespace vimpact::cli {

cli_command add_simulate_command(CLI::App& app);
cli_command add_period_command(CLI::App& app);
cli_command add_grazing_command(CLI::App& app);

}  // namespace vimpact::cli
