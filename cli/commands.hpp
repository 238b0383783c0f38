#pragma once
// The subcommands: each resolves its options, calls the library, prints and writes.
#include <CLI/CLI.hpp>

#include "common_options.hpp"

namespace vimpact::cli {

struct simulate_args {
    common_args common;
    double sample_dt = 0.05;
};
struct period_args {
    common_args common;
    double tol = 1e-8;
};
struct grazing_args {
    common_args common;
    double tol = 1e-11;
    double transient_time = 1000.0;
};

int run_simulate(const simulate_args& a);
int run_period(const period_args& a);
int run_grazing(const grazing_args& a);

}  // namespace vimpact::cli
