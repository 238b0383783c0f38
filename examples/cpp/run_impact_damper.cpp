// A user's model with the library's analyses: the impact damper (impact_damper.hpp) from the
// command line of this program, with no vimpact code changed.
//
//   run_impact_damper [--quick]
//
// prints, at the default parameters (a symmetric motion with one impact on each wall per
// forcing period), the attractor's label and impacts per wall, the clearance below which the
// ball starts hitting, the Floquet multipliers of the periodic motion with the Liouville
// check, its Lyapunov spectrum, and the labels over the clearance d.
#include <cmath>
#include <cstdio>
#include <cstring>

#include <vimpact/analysis/floquet.hpp>
#include <vimpact/analysis/grazing.hpp>
#include <vimpact/analysis/lyapunov.hpp>
#include <vimpact/analysis/period.hpp>
#include <vimpact/analysis/sweep.hpp>
#include <vimpact/model/export.hpp>
#include <vimpact/model/model.hpp>

#include "impact_damper.hpp"

int main(int argc, char** argv)
{
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    const vimpact::model m = vimpact::model::from_definition<impact_damper>();  // default parameters
    const int d = m.info().parameter_index("d");

    vimpact::protocol_options po;
    po.transient_impacts = quick ? 100 : 500;
    po.record_points = quick ? 40 : 200;
    const auto run = vimpact::run_and_classify(m, m.initial_state(), po, 1e-8);
    std::printf("impact damper, d = %g: %s, %ld impact(s) per period (right %ld, left %ld)\n", m.parameter(d),
                run.label.label.c_str(), run.label.impacts_per_period, run.label.impacts_by_surface.at(0),
                run.label.impacts_by_surface.at(1));

    // The clearance below which the ball hits the walls: the grazing value of d.
    vimpact::grazing_options go;
    go.parameter = d;
    const auto g = vimpact::grazing(m, m.initial_state(), go);
    std::printf("grazing clearance d = %.9f (right wall), %.9f (left wall)\n", g.surfaces.at(0).parameter_value,
                g.surfaces.at(1).parameter_value);

    vimpact::floquet_options fo;
    fo.protocol = po;
    const auto f = vimpact::floquet(m, m.initial_state(), fo);
    if (f.has_multipliers()) {
        std::printf("period T = %.10f, multipliers (trivial first, |mu - 1| = %.2g):", f.period, f.trivial_error);
        for (const auto& mu : f.multipliers) std::printf(" %.6g%+.6gi", mu.real(), mu.imag());
        std::printf("\ndet monodromy %.6g, Liouville %.6g\n", f.det_monodromy, f.liouville_det);
    } else {
        std::printf("no multipliers: %s\n", std::string(vimpact::to_string(f.status)).c_str());
    }

    vimpact::lyapunov_options lo;
    lo.transient_impacts = po.transient_impacts;
    lo.impacts = quick ? 100 : 800;
    const auto l = vimpact::lyapunov(m, m.initial_state(), lo);
    std::printf("Lyapunov exponents (%s):", std::string(vimpact::to_string(l.status)).c_str());
    for (Eigen::Index i = 0; i < l.exponents.size(); ++i) std::printf(" %.5g", l.exponents[i]);
    std::printf("  sum %.8g, sum rule %.8g\n", l.exponents.sum(), l.sum_rule);

    vimpact::sweep_options so;
    so.parameter = d;
    so.values = vimpact::grid_values(0.5, 3.5, quick ? 7 : 25);
    so.protocol = po;
    const auto s = vimpact::sweep(m, so);
    std::printf("sweep of d:");
    for (const auto& p : s.points) std::printf(" %g:%s", p.value, p.label.label.c_str());
    std::printf("\n");
    return 0;
}
