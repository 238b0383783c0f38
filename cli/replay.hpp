#pragma once
// Replayable runs: every --out directory gets a config.toml that `vimpact COMMAND --config
// DIR/config.toml` runs again to the same files. The file holds the resolved run (model,
// preset, every parameter, ic, tolerances, protocol) at the top level and the command's own
// options in a table named after the command ([sweep], [map], ...), as they were given.
//
// The command's table is applied before parsing, as if its options had been typed after the
// ones on the command line (an option given on the command line wins), so that CLI11 checks
// them exactly as typed ones, required options included.
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace vimpact::cli {

struct run_config;

// The arguments after the program name, with the options of the config file's table for the
// command appended (those not given on the command line). Throws input_error for a table key
// that is not an option of the command, or a value of a type an option cannot take.
std::vector<std::string> arguments_with_config(const CLI::App& app, int argc, char** argv);

// The options given to a command that shape its results, {name: value} with names without the
// leading dashes; the run's settings (model, parameters, protocol) and the options that only
// say where or how to run (--out, --json, --config, --threads, --shard, --resume) are left out.
nlohmann::json recorded_options(const CLI::App& command);

// Writes config.toml for the run into `path`.
void write_replay_config(const std::filesystem::path& path, const run_config& c);

}  // namespace vimpact::cli
