#include "vimpact/physical/state_dimensions.hpp"

#include <cmath>

namespace vimpact {

namespace {

// The initial state and states spread around it with a different offset in every variable, so
// that no variable is zero or equal to another by chance.
std::vector<Eigen::VectorXd> spread_states(const model& m)
{
    std::vector<Eigen::VectorXd> out;
    for (int k = 0; k < 4; ++k) {
        Eigen::VectorXd x = m.initial_state();
        for (int j = 0; j < x.size(); ++j) x[j] += 0.07 * k * (j % 2 == 0 ? 1.0 : -1.0) + 0.011 * (j + 1) * (k + 1);
        out.push_back(std::move(x));
    }
    return out;
}

bool close(double a, double b) { return std::abs(a - b) <= 1e-12 * (1.0 + std::abs(b)); }

}  // namespace

std::vector<physical_dimension> state_dimensions(const model& m)
{
    const int n = m.dim();
    const auto& t = m.table();
    const auto states = spread_states(m);
    std::vector<physical_dimension> out(static_cast<std::size_t>(n), physical_dimension::none);
    Eigen::VectorXd grad(n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < m.surface_count(); ++i) {
            bool unit = true;
            for (const auto& x : states) {
                t.gap_gradient(m.context(), i, x.data(), grad.data());
                unit = unit && close(std::abs(grad[j]), 1.0);
            }
            if (unit) out[static_cast<std::size_t>(j)] = physical_dimension::length;
        }
    // The velocity of a displacement x_j: the variable v with dx_j/dt = v everywhere.
    std::vector<Eigen::VectorXd> fields;
    for (const auto& x : states) {
        Eigen::VectorXd f(n);
        t.rhs(m.context(), x.data(), f.data());
        fields.push_back(std::move(f));
    }
    for (int j = 0; j < n; ++j) {
        if (out[static_cast<std::size_t>(j)] != physical_dimension::length) continue;
        for (int v = 0; v < n; ++v) {
            if (v == j || out[static_cast<std::size_t>(v)] != physical_dimension::none) continue;
            bool derivative = true;
            for (std::size_t s = 0; s < states.size(); ++s) derivative = derivative && close(fields[s][j], states[s][v]);
            if (derivative) out[static_cast<std::size_t>(v)] = physical_dimension::velocity;
        }
    }
    return out;
}

std::string_view si_unit(physical_dimension d)
{
    switch (d) {
    case physical_dimension::length: return "m";
    case physical_dimension::velocity: return "m/s";
    case physical_dimension::none: break;
    }
    return "";
}

}  // namespace vimpact
