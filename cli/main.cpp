// vimpact: the command line. A thin layer over the library: parse, resolve names, call one
// analysis, report. Exit codes: 0 success (numerical trouble is reported as an outcome), 1
// internal or I/O failure, 2 bad input, 130 interrupted (Ctrl-C or SIGTERM: nothing written;
// job commands keep their journal).
#include <algorithm>
#include <charconv>
#include <iostream>
#include <system_error>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "interrupts.hpp"
#include "replay.hpp"
#include "vimpact/core/cancelled.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/core/option.hpp"
#include "vimpact/io/build_info.hpp"
#include "vimpact/jobs/job_ranks.hpp"

namespace {

// One printable line: CLI11's messages may span several, and a message that quotes a user's
// file may hold control bytes that a terminal would act on.
std::string one_line(std::string s)
{
    for (auto& ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        if (c == '\n' || c == '\r' || c == '\t') ch = ' ';
        else if (c < 0x20 || c == 0x7f) ch = '?';
    }
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}

// Values CLI11 accepts but would turn silently into something else: an empty value (`--ic
// ''`) means the option's default, and an integer beyond 64 bits is clamped to 2^63 - 1.
void refuse_silent_values(const CLI::App& command)
{
    for (const CLI::Option* opt : command.get_options()) {
        if (opt->count() == 0 || opt->get_expected_min() == 0) continue;
        for (const auto& value : opt->results()) {
            if (value.empty())
                throw vimpact::input_error(opt->get_name() + " is given an empty value (leave the option out for " +
                                           "its default)");
            if (opt->get_type_name() == "INT") {
                long long v = 0;
                const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
                if (ec == std::errc::result_out_of_range)
                    throw vimpact::input_error(opt->get_name() + " = " + value +
                                               " does not fit in a 64-bit integer");
                (void)end;
            }
        }
    }
}

// Under MPI every rank meets the same bad input: rank 0 alone says so.
int fail(const std::string& message)
{
    if (vimpact::launched_rank() == 0) std::cerr << "vimpact: error: " << one_line(message) << '\n';
    return 2;
}

}  // namespace

int main(int argc, char** argv)
{
    using namespace vimpact::cli;
    CLI::App app{"vimpact: nonlinear dynamics of impacting systems (the paper's wake-induced vibro-impacting "
                 "oscillator by default; `vimpact models` lists the others)"};
    app.set_version_flag("--version", std::string(vimpact::version()) + " (" + std::string(vimpact::git_hash()) + ")");
    app.require_subcommand(1);

    const std::vector<cli_command> commands{
        add_simulate_command(app), add_period_command(app),   add_grazing_command(app),
        add_sweep_command(app),    add_map_command(app),      add_basins_command(app),
        add_response_command(app), add_floquet_command(app),  add_lyapunov_command(app),
        add_continue_command(app),
        add_dimension_command(app), add_models_command(app), add_units_command(app),
        add_clearance_command(app), add_explore_command(app),
    };

    try {
        std::vector<std::string> args = arguments_with_config(app, argc, argv);
        std::reverse(args.begin(), args.end());  // CLI11 takes them last first
        app.parse(args);
    } catch (const vimpact::option_error& e) {  // a declared option read as it is parsed
        return fail(vimpact::command_line_key(e.key()) + e.detail());
    } catch (const vimpact::input_error& e) {
        return fail(e.what());
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::string message = e.what();
        // An unknown command: name it (CLI11 reports only that a command is missing).
        if (argc > 1 && app.get_subcommands().empty() && argv[1][0] != '-') {
            message = "unknown command '";
            message += argv[1];
            message += "' (commands:";
            for (const auto& c : commands) message += " " + c.app->get_name();
            message += ")";
        }
        return fail(message);
    }
    try {
        const interrupt_guard interrupts;
        for (const auto& c : commands)
            if (c.app->parsed()) {
                refuse_silent_values(*c.app);
                return c.run();
            }
    } catch (const vimpact::cancelled&) {  // `interrupted` too
        if (vimpact::launched_rank() == 0) std::cerr << "vimpact: interrupted; nothing written\n";
        return 130;
    } catch (const vimpact::option_error& e) {  // the library's key, as this command line spells it
        return fail(vimpact::command_line_key(e.key()) + e.detail());
    } catch (const vimpact::input_error& e) {
        return fail(e.what());
    } catch (const std::exception& e) {
        std::cerr << "vimpact: internal error: " << one_line(e.what()) << '\n';
        return 1;
    }
    return 2;
}
