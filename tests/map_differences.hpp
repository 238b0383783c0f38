#pragma once
// Central differences of a section map in the chart of its section: the independent check of
// the map's Jacobian from the tangent flow (tangent/section_map.hpp).
#include <gtest/gtest.h>

#include "vimpact/tangent/section_map.hpp"

namespace vimpact::test {

// d(P^returns)/dz at x in the chart (one coordinate dropped), by central differences of step
// h: truncation h^2 times the map's curvature, noise the integration's error over h.
template <engine_model Model>
mat<Model::dim - 1> map_differences(const Model& m, const section_chart<Model>& chart, const vec<Model::dim>& x,
                                    int returns, double h, const section_map_options& o = {})
{
    constexpr int K = Model::dim - 1;
    mat<K> fd;
    for (int j = 0; j < K; ++j) {
        vec<K> z = chart.to_chart(x);
        z[j] += h;
        const auto plus = section_map<dop853>(m, chart.from_chart(z, x), returns, o);
        z[j] -= 2.0 * h;
        const auto minus = section_map<dop853>(m, chart.from_chart(z, x), returns, o);
        EXPECT_TRUE(plus.valid() && minus.valid());
        fd.col(j) = (chart.to_chart(plus.x_end) - chart.to_chart(minus.x_end)) / (2.0 * h);
    }
    return fd;
}

}  // namespace vimpact::test
