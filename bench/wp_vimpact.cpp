// vimpact's side of the work-precision diagram (bench/work_precision.py): the paper's model
// through the library's simulate(), the call every front end makes, with the options and
// output of the standalone baselines (bench/baseline_common.hpp) and --method dop853|dopri5.
// The protocol: 500 impacts discarded, 200 maxima kept; with --horizon H, every maximum up to
// t = H from t = 0. --hold B: the step-size controller's hold band (integrator_options::hold_band;
// without it, the method's: 0.1 for DOPRI5, 0 for DOP853).
#include <cstring>
#include <optional>
#include <vector>

#include "baseline_common.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/model/model.hpp"

int main(int argc, char** argv)
{
    std::optional<double> hold_band;
    std::vector<char*> args;
    for (int i = 0; i < argc; ++i) {
        if (i > 0 && i + 1 < argc && std::strcmp(argv[i], "--hold") == 0) hold_band = std::atof(argv[++i]);
        else args.push_back(argv[i]);
    }
    const auto a = baseline::parse_with_method(static_cast<int>(args.size()), args.data(), {"dop853", "dopri5"});
    if (!a) return 2;
    const auto& [method, pr] = *a;
    const baseline::problem* p = &pr;
    vimpact::model m = vimpact::model::builtin("wake_impact");
    m = m.with_parameter(m.info().parameter_index("Ur"), p->ur);
    vimpact::protocol_options po;
    po.method = method == "dopri5" ? vimpact::integration_method::dopri5 : vimpact::integration_method::dop853;
    po.flow.integration.rtol = p->tol;
    po.flow.integration.atol = p->tol;
    po.flow.integration.hold_band = hold_band;
    if (p->horizon > 0.0) {
        po.transient_impacts = 0;
        po.record_points = 10'000'000;
        po.flow.t_max = p->horizon;
        po.quiet_time = 1e9;
    }
    const Eigen::VectorXd x0 = m.initial_state();
    const std::string name = std::string(method == "dopri5" ? "vimpact-dopri5" : "vimpact-dop853") +
                             (hold_band ? (*hold_band > 0.0 ? "-hold" : "-nohold") : "");
    return baseline::report(*p, name.c_str(), [&] {
        baseline::run_result r;
        const auto t0 = baseline::clock::now();
        const auto s = vimpact::simulate(m, x0, po);
        r.wall_s = baseline::seconds_since(t0);
        r.steps = s.stats.steps;
        r.rejected = s.stats.rejected;
        r.rhs_calls = s.stats.rhs_calls;
        r.impacts = s.stats.impacts;
        for (std::size_t k = 0; k < s.points.size(); ++k) {
            const auto x = s.points.x(k);
            r.points.push_back({s.points.t(k), {x[0], x[1], x[2], x[3]}});
        }
        return r;
    });
}
