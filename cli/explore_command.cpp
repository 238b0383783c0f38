// The explore command: the model in the browser (python/vimpact/explore.py serves the page and
// computes through the Python module, which runs the same library). The program only hands
// its options over: the process becomes the server, so Ctrl-C reaches it directly and stops it.
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/io/build_info.hpp"

namespace vimpact::cli {
namespace {

struct explore_args {
    std::string model = "wake_impact";
    std::string preset;
    std::vector<std::string> sets;
    int port = 8765;
    int threads = 0;
    bool no_browser = false;
};

// The package from the directory given (argv[1]), never from the working directory or the
// environment, which -I leaves out of sys.path.
constexpr const char* explore_program =
    "import sys\n"
    "d = sys.argv.pop(1)\n"
    "if d: sys.path.insert(0, d)\n"
    "from vimpact.explore import main\n"
    "sys.exit(main(sys.argv[1:]))\n";

int run_explore(const explore_args& a)
{
    const std::string interp(python_interpreter()), pydir(python_module_dir());
    std::vector<std::string> args{interp, "-I", "-c", explore_program, pydir, "--model", a.model,
                                  "--port", std::to_string(a.port), "--threads", std::to_string(a.threads)};
    if (!a.preset.empty()) args.insert(args.end(), {"--preset", a.preset});
    for (const auto& s : a.sets) args.insert(args.end(), {"--set", s});
    if (a.no_browser) args.emplace_back("--no-browser");
    std::vector<char*> argv;
    for (auto& s : args) argv.push_back(s.data());
    argv.push_back(nullptr);
    ::execv(interp.c_str(), argv.data());
    throw input_error("explore needs " + interp + " with the vimpact package (" + std::strerror(errno) + ")");
}

}  // namespace

cli_command add_explore_command(CLI::App& app)
{
    auto a = std::make_shared<explore_args>();
    auto* s = app.add_subcommand("explore",
                                 "The model in the browser: a bifurcation diagram, periodicity map or basins computed "
                                 "as you zoom, any parameter changed, a clicked point's orbit, label and Floquet "
                                 "multipliers, and the command line of every view (served on 127.0.0.1 only)");
    s->add_option("--model", a->model,
                  "The model: a built-in name (default wake_impact), a model file NAME.toml or a shared library; the "
                  "page can change its parameters, never load another model or read a file");
    s->add_option("--preset", a->preset, "A parameter preset of the model");
    s->add_option("--set", a->sets, "Set a parameter of the model, KEY=VALUE (repeatable)")->allow_extra_args(false);
    s->add_option("--port", a->port, "Port on 127.0.0.1 (0: a free one; the address is printed)")
        ->check(CLI::Range(0, 65535));
    s->add_option("--threads", a->threads, "Worker threads of the computations (0: every core)")
        ->check(CLI::NonNegativeNumber);
    s->add_flag("--no-browser", a->no_browser, "Do not open a browser; print the address only");
    return {s, [a] { return run_explore(*a); }};
}

}  // namespace vimpact::cli
