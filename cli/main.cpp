// vimpact: the command line. A thin layer: parse, validate, call the library, report.
// Exit codes: 0 success (numerical trouble is reported as an outcome), 1 internal or I/O
// failure, 2 bad input.
#include <iostream>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "dimension_command.hpp"
#include "stability_commands.hpp"
#include "sweep_commands.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/io/build_info.hpp"

int main(int argc, char** argv)
{
    using namespace vimpact::cli;
    CLI::App app{"vimpact: nonlinear dynamics of a wake-induced vibro-impacting oscillator"};
    app.set_version_flag("--version", std::string(vimpact::version()) + " (" +
                                          std::string(vimpact::git_hash()) + ")");
    app.require_subcommand(1);

    // One line per command; each command file declares its add_<name>_command.
    const std::vector<cli_command> commands{
        add_simulate_command(app),
        add_period_command(app),
        add_grazing_command(app),
        add_sweep_command(app),
        add_map_command(app),
        add_basins_command(app),
        add_response_command(app),
        add_dimension_command(app),
        add_floquet_command(app),
        add_lyapunov_command(app),
    };

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "vimpact: error: " << e.what() << '\n';
        return 2;
    }
    try {
        for (const auto& c : commands)
            if (c.app->parsed()) return c.run();
    } catch (const vimpact::input_error& e) {
        std::cerr << "vimpact: error: " << e.what() << '\n';
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "vimpact: internal error: " << e.what() << '\n';
        return 1;
    }
    return 2;
}
