#pragma once
// Options shared by the subcommands, and their resolution into a validated configuration:
// preset, then the config file, then --set, then --ic; each step names what it rejects.
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/model/wake_impact.hpp"

namespace vimpact::cli {

struct common_args {
    std::string preset = "paper";
    std::vector<std::string> sets;
    std::string ic;
    std::string config;
    double rtol = 1e-10;
    double atol = 1e-10;
    long transient = 500;
    long record = 200;
    std::string method = "dop853";
    std::string section = "maxima";
    std::string out;
    bool json = false;
    bool no_plot = false;
    CLI::Option* preset_option = nullptr;
    CLI::Option* rtol_option = nullptr;
    CLI::Option* atol_option = nullptr;
    CLI::Option* transient_option = nullptr;
    CLI::Option* record_option = nullptr;
    CLI::Option* method_option = nullptr;
    CLI::Option* section_option = nullptr;
};

struct run_config {
    std::string preset;
    wake_impact_parameters params;
    vec<4> ic{0.0, 0.0, 0.0, 0.1};
    double rtol = 1e-10;
    double atol = 1e-10;
    long transient = 500;
    long record = 200;
    std::string method = "dop853";
    section_choice section = section_choice::maxima;
    std::optional<std::string> out;
    bool json = false;
    bool plot = true;

    [[nodiscard]] wake_impact model() const { return wake_impact(params); }
    [[nodiscard]] protocol_options protocol() const;
    [[nodiscard]] nlohmann::json to_json() const;
};

void add_common_options(CLI::App& app, common_args& args);

// Throws input_error for anything invalid, naming the input and its valid range.
run_config resolve(const common_args& args);

double parse_number(const std::string& text, const std::string& what);

}  // namespace vimpact::cli
