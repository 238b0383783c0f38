#include "vimpact/analysis/orbit_map.hpp"

#include <cmath>
#include <string>

#include "dispatch.hpp"
#include "vimpact/core/input_error.hpp"

namespace vimpact {

std::vector<long> orbit_map_value::impacts_by_surface(int surfaces) const
{
    std::vector<long> n(static_cast<std::size_t>(std::max(surfaces, 0)), 0);
    for (const auto& i : impacts)
        if (i.surface >= 0 && i.surface < surfaces) ++n[static_cast<std::size_t>(i.surface)];
    return n;
}

std::vector<int> orbit_map_value::impact_sequence() const
{
    std::vector<int> s;
    s.reserve(impacts.size());
    for (const auto& i : impacts) s.push_back(i.surface);
    return s;
}

Eigen::VectorXd chart_of(const Eigen::VectorXd& x, int c)
{
    Eigen::VectorXd z(x.size() - 1);
    for (Eigen::Index i = 0, k = 0; i < x.size(); ++i)
        if (i != c) z[k++] = x[i];
    return z;
}

int default_chart_coordinate(const model& m, int section, const Eigen::VectorXd& x)
{
    if (section < 0 || section >= m.section_count())
        throw input_error("section " + std::to_string(section) + " is out of range (the model has " +
                          std::to_string(m.section_count()) + ")");
    check_state_size(m, x.size(), "the state");
    return detail::with_engine(m, [&](const auto& em) {
        using EM = std::decay_t<decltype(em)>;
        constexpr int N = EM::dim;
        const vec<N> g = em.section_gradient(section, head_as<N>(x, x.size()));
        int c = 0;
        for (int j = 1; j < g.size(); ++j)
            if (std::abs(g[j]) > std::abs(g[c])) c = j;
        return c;
    });
}

orbit_map_value orbit_map(const model& m, const orbit_map_request& r)
{
    if (m.dim() < 2) throw input_error("a section map needs at least 2 state variables");
    if (r.section < 0 || r.section >= m.section_count())
        throw input_error("section " + std::to_string(r.section) + " is out of range (the model has " +
                          std::to_string(m.section_count()) + ")");
    if (r.returns < 1) throw input_error("section returns must be >= 1 (got " + std::to_string(r.returns) + ")");
    if (r.z.size() != m.dim() - 1)
        throw input_error("chart coordinates need " + std::to_string(m.dim() - 1) + " numbers, got " +
                          std::to_string(r.z.size()));
    check_state_size(m, r.guess.size(), "the guess");
    if (r.chart_coordinate >= m.dim()) throw input_error("chart coordinate out of range");
    return detail::with_engine(m, [&](const auto& em) { return detail::run_orbit_map(em, r); });
}

}  // namespace vimpact
