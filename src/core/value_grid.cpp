#include "vimpact/core/value_grid.hpp"

#include <cmath>

#include "vimpact/core/input_error.hpp"

namespace vimpact {

value_grid value_grid::range(double a, double b, long n)
{
    if (n < 1 || n > max_points)
        throw input_error("a range needs 1 <= n <= 1e8 points (got " + std::to_string(n) + ")");
    if (!std::isfinite(a) || !std::isfinite(b)) throw input_error("range ends must be finite");
    value_grid g;
    g.m_a = a;
    g.m_b = b;
    g.m_n = n;
    g.m_range = true;
    return g;
}

value_grid value_grid::mapped(std::function<double(double)> map, std::string what) const
{
    value_grid g = unmapped();
    g.m_map = std::make_shared<const value_map>(value_map{std::move(map), std::move(what)});
    return g;
}

value_grid value_grid::unmapped() const
{
    value_grid g = *this;
    g.m_map.reset();
    return g;
}

const std::string& value_grid::map_name() const
{
    static const std::string none;
    return m_map ? m_map->what : none;
}

std::vector<double> value_grid::values() const { return {begin(), end()}; }

}  // namespace vimpact
