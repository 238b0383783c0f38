// The cost of every job of a periodicity map (the CPU time of the thread that ran it, which
// a busy machine does not inflate), computed through the library's map2d (the call
// `vimpact map` makes): the cost distribution the projection of the MPI
// schedule resamples (bench/schedule_sim.cpp, bench/run_mpi_bench.sh). Near the grazing line
// jobs cost several times the others; the file keeps each job's cell and label.
//   job_costs NX NY TRANSIENT RECORD OUT.csv [THREADS]   (the paper's Figure 4 axes:
//                                     14 <= Ur <= 26, -0.16 <= sigma <= -0.02; 1 thread)
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <mutex>
#include <vector>

#include "vimpact/analysis/map.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/model/model.hpp"

int main(int argc, char** argv)
{
    if (argc != 6 && argc != 7) {
        std::cerr << "usage: job_costs NX NY TRANSIENT RECORD OUT.csv [THREADS]\n";
        return 2;
    }
    const long nx = std::atol(argv[1]), ny = std::atol(argv[2]);
    const vimpact::model m = vimpact::model::builtin("wake_impact");
    vimpact::map_options o;
    o.x = {m.info().parameter_index("Ur"), vimpact::grid_values(14.0, 26.0, nx)};
    o.y = {m.info().parameter_index("sigma"), vimpact::grid_values(-0.16, -0.02, ny)};
    o.protocol.transient_impacts = std::atol(argv[3]);
    o.protocol.record_points = std::atol(argv[4]);
    o.period_tolerance = 1e-5;
    std::vector<double> seconds(static_cast<std::size_t>(nx * ny), -1.0);
    vimpact::job_options j;
    j.threads = argc == 7 ? std::atoi(argv[6]) : 1;
    j.batch = 1;  // each job timed alone (in SIMD lanes a batch's time is shared out evenly)
    j.timed = [&](long job, double s) { seconds[static_cast<std::size_t>(job)] = s; };
    std::vector<std::string> labels(seconds.size());
    std::vector<long> steps(seconds.size(), 0);
    (void)vimpact::map2d(m, o, j, [&](long job, const vimpact::map_cell& c) {
        labels[static_cast<std::size_t>(job)] = c.label.label;
        steps[static_cast<std::size_t>(job)] = c.steps;
    });
    std::ofstream out(argv[5]);
    out << "job,ix,iy,Ur,sigma,label,seconds,steps\n";
    char buf[64];
    for (long k = 0; k < nx * ny; ++k) {
        std::snprintf(buf, sizeof buf, "%.9f", seconds[static_cast<std::size_t>(k)]);
        out << k << ',' << k % nx << ',' << k / nx << ',' << o.x.values[static_cast<std::size_t>(k % nx)] << ','
            << o.y.values[static_cast<std::size_t>(k / nx)] << ',' << labels[static_cast<std::size_t>(k)] << ',' << buf
            << ',' << steps[static_cast<std::size_t>(k)] << '\n';
    }
    return out ? 0 : 1;
}
