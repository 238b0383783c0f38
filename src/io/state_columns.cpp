#include "vimpact/io/state_columns.hpp"

#include <cmath>

namespace vimpact {

std::vector<std::string> state_columns(const model_info& info)
{
    std::vector<std::string> out;
    for (const auto& v : info.state) out.push_back(v.name);
    return out;
}

std::vector<bool> reset_changes(const model& m)
{
    const int n = m.dim();
    std::vector<bool> changed(static_cast<std::size_t>(n), false);
    const auto& t = m.table();
    Eigen::VectorXd grad(n), post(n);
    for (int i = 0; i < m.surface_count(); ++i)
        for (int k = 0; k < 4; ++k) {
            // The initial state and states spread around it, in every direction, so that no
            // velocity-like variable is zero by chance.
            Eigen::VectorXd x = m.initial_state();
            for (int j = 0; j < n; ++j) x[j] += 0.1 * k * (j % 2 == 0 ? 1.0 : -1.0) + 0.013 * (j + 1);
            // Onto the surface by Newton steps along the gap's gradient.
            bool on = false;
            for (int it = 0; it < 50; ++it) {
                const double g = t.gap(m.context(), i, x.data());
                if (!std::isfinite(g)) break;
                t.gap_gradient(m.context(), i, x.data(), grad.data());
                const double gg = grad.squaredNorm();
                if (!(gg > 0.0) || !std::isfinite(gg)) break;
                if (std::abs(g) <= 1e-13 * std::sqrt(gg) * (1.0 + x.cwiseAbs().maxCoeff())) {
                    on = true;
                    break;
                }
                x -= (g / gg) * grad;
            }
            if (!on) continue;
            t.reset(m.context(), i, x.data(), post.data());
            for (int j = 0; j < n; ++j)
                if (std::abs(post[j] - x[j]) > 1e-9 * (1.0 + std::abs(x[j]))) changed[static_cast<std::size_t>(j)] = true;
        }
    return changed;
}

std::vector<impact_column> impact_columns(const model& m)
{
    const auto changed = reset_changes(m);
    std::vector<impact_column> out;
    for (int j = 0; j < m.dim(); ++j) {
        const std::string& name = m.info().state[static_cast<std::size_t>(j)].name;
        if (changed[static_cast<std::size_t>(j)]) {
            out.push_back({name + "_before", j, false});
            out.push_back({name + "_after", j, true});
        } else {
            out.push_back({name, j, false});
        }
    }
    return out;
}

}  // namespace vimpact
