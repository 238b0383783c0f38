// The step-size controller's constants, compared by work and accuracy (machine-independent:
// counts of right-hand-side calls, not times). For each candidate (safety, PI beta, largest
// growth factor, hold band) and each method, the protocol of the paper's model at several Ur (periodic
// and chaotic cells) at rtol = atol = 1e-8 and 1e-10: total trial steps, rejected steps, rhs
// calls, and the largest state error of the section points of the periodic cells against a
// run at 1e-13 with the default controller (the chaotic cells have no reference: their errors
// grow to the attractor's size whatever the controller). docs/performance.md quotes the table.
//
// Usage: build/controller_bench
#include <cmath>
#include <cstdio>
#include <vector>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/model/model.hpp"

int main()
{
    using namespace vimpact;
    const model base = model::builtin("wake_impact");
    const int ur = base.info().parameter_index("Ur");
    const std::vector<double> periodic{12.0, 14.0, 16.0, 18.0, 20.0}, chaotic{22.5, 24.0};
    struct candidate {
        const char* name;
        double safety, beta, factor_max, factor_min, hold_band = 0.0;
    };
    const integrator_options d;
    const std::vector<candidate> cands{
        {"PI, no band (DOP853's default)", d.safety, d.pi_beta, d.factor_max, d.factor_min},
        {"proportional (beta 0)", 0.9, 0.0, 10.0, 0.2},
        {"Hairer DOP853 (0.9, beta 0, [1/3, 6])", 0.9, 0.0, 6.0, 1.0 / 3.0},
        {"beta 0.04, growth <= 5", 0.9, 0.04, 5.0, 0.2},
        {"beta 0.08", 0.9, 0.08, 10.0, 0.2},
        {"PI 0.7/k, 0.4/k (beta = 0.4/k)", 0.9, -1.0, 10.0, 0.2},
        {"safety 0.8", 0.8, 0.04, 10.0, 0.2},
        {"safety 0.95", 0.95, 0.04, 10.0, 0.2},
        {"hold band 0.05", 0.9, 0.04, 10.0, 0.2, 0.05},
        {"hold band 0.1 (DOPRI5's default)", 0.9, 0.04, 10.0, 0.2, 0.1},
        {"hold band 0.2", 0.9, 0.04, 10.0, 0.2, 0.2},
        {"hold band 0.3", 0.9, 0.04, 10.0, 0.2, 0.3},
        {"hold band 0.5", 0.9, 0.04, 10.0, 0.2, 0.5},
    };
    std::printf("| method | rtol | controller | trial steps | rejected | rhs calls | max state error (periodic cells) |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    for (const auto method : all_integration_methods) {
        const int k = method == integration_method::dop853 ? 8 : 5;
        for (const double tol : {1e-8, 1e-10}) {
            std::vector<simulation> refs;
            for (const double u : periodic) {
                protocol_options po;
                po.method = integration_method::dop853;
                po.flow.integration.rtol = po.flow.integration.atol = 1e-13;
                refs.push_back(simulate(base.with_parameter(ur, u), base.initial_state(), po));
            }
            for (const auto& c : cands) {
                protocol_options po;
                po.method = method;
                po.flow.integration.rtol = po.flow.integration.atol = tol;
                po.flow.integration.safety = c.safety;
                po.flow.integration.pi_beta = c.beta < 0.0 ? 0.4 / k : c.beta;
                po.flow.integration.factor_max = c.factor_max;
                po.flow.integration.factor_min = c.factor_min;
                po.flow.integration.hold_band = c.hold_band;
                long steps = 0, rejected = 0, rhs = 0;
                double err = 0.0;
                for (std::size_t i = 0; i < periodic.size() + chaotic.size(); ++i) {
                    const double u = i < periodic.size() ? periodic[i] : chaotic[i - periodic.size()];
                    const auto s = simulate(base.with_parameter(ur, u), base.initial_state(), po);
                    steps += s.stats.steps + s.stats.rejected;
                    rejected += s.stats.rejected;
                    rhs += s.stats.rhs_calls;
                    if (i < periodic.size() && s.points.size() == refs[i].points.size())
                        for (std::size_t p = 0; p < s.points.size(); ++p)
                            err = std::max(err, (s.points.x(p) - refs[i].points.x(p)).cwiseAbs().maxCoeff());
                    else if (i < periodic.size())
                        err = INFINITY;
                }
                std::printf("| %s | %.0e | %s | %ld | %ld | %ld | %.1e |\n", std::string(to_string(method)).c_str(), tol,
                            c.name, steps, rejected, rhs, err);
                std::fflush(stdout);
            }
        }
    }
    return 0;
}
