#pragma once
// Every command of the program; each file defines its add_<name>_command, main lists them.
#include "command.hpp"

namespace vimpact::cli {

cli_command add_simulate_command(CLI::App& app);   // run_commands.cpp
cli_command add_period_command(CLI::App& app);
cli_command add_grazing_command(CLI::App& app);
cli_command add_sweep_command(CLI::App& app);      // sweep_commands.cpp
cli_command add_map_command(CLI::App& app);
cli_command add_basins_command(CLI::App& app);
cli_command add_response_command(CLI::App& app);
cli_command add_floquet_command(CLI::App& app);    // stability_commands.cpp
cli_command add_continue_command(CLI::App& app);   // continue_command.cpp
cli_command add_lyapunov_command(CLI::App& app);
cli_command add_dimension_command(CLI::App& app);  // dimension_command.cpp
cli_command add_models_command(CLI::App& app);     // models_command.cpp
cli_command add_units_command(CLI::App& app);      // units_command.cpp
cli_command add_clearance_command(CLI::App& app);  // clearance_command.cpp
cli_command add_explore_command(CLI::App& app);    // explore_command.cpp

}  // namespace vimpact::cli
