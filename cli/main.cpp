// vimpact: the command line. A thin layer: parse, validate, call the library, report.
// Exit codes: 0 success (numerical trouble is reported as an outcome), 1 internal or I/O
// failure, 2 bad input.
#include <iostream>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/io/build_info.hpp"

int main(int argc, char** argv)
{
    using namespace vimpact::cli;
    CLI::App app{"vimpact: nonlinear dynamics of a wake-induced vibro-impacting oscillator"};
    app.set_version_flag("--version", std::string(vimpact::version()) + " (" +
                                          std::string(vimpact::git_hash()) + ")");
    app.require_subcommand(1);

    simulate_args sim;
    auto* s = app.add_subcommand("simulate", "Run the protocol: discard a transient of impacts, record section points and the time series");
    add_common_options(*s, sim.common);
    s->add_option("--dt", sim.sample_dt, "Time-series sampling interval with --out (default 0.05)");

    period_args per;
    auto* p = app.add_subcommand("period", "Classify the attractor: P0, P1, P2, ..., aperiodic");
    add_common_options(*p, per.common);
    p->add_option("--tol", per.tol, "Period tolerance on the section state (default 1e-8)");

    grazing_args gr;
    auto* g = app.add_subcommand("grazing", "Grazing value: minimum of y on the barrier-free attracting orbit");
    add_common_options(*g, gr.common);
    g->add_option("--tol", gr.tol, "Agreement of successive minima (default 1e-11)");
    g->add_option("--transient-time", gr.transient_time, "Time discarded before minima count (default 1000)");

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
        if (s->parsed()) return run_simulate(sim);
        if (p->parsed()) return run_period(per);
        if (g->parsed()) return run_grazing(gr);
    } catch (const vimpact::input_error& e) {
        std::cerr << "vimpact: error: " << e.what() << '\n';
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "vimpact: internal error: " << e.what() << '\n';
        return 1;
    }
    return 2;
}
