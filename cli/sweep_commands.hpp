#pragma once
// The job-loop commands: sweep, map, basins, response.
#include "command.hpp"

namespace vimpact::cli {

cli_command add_sweep_command(CLI::App& app);
cli_command add_map_command(CLI::App& app);
cli_command add_basins_command(CLI::App& app);
cli_command add_response_command(CLI::App& app);

}  // namespace vimpact::cli
