#pragma once
// One subcommand: its CLI11 node and the function that runs it once parsed. Each command lives
// in its own file and exposes `cli_command add_<name>_command(CLI::App&)`; main lists them.
#include <functional>

#include <CLI/CLI.hpp>

namespace vimpact::cli {

struct cli_command {
    CLI::App* app = nullptr;
    std::function<int()> run;
};

}  // namespace vimpact::cli
