#pragma once
// Small helpers shared by the unit tests.
#include <random>

#include "vimpact/core/state.hpp"

namespace vimpact::test {

// A state with components uniform in [lo, hi).
template <int N>
vec<N> random_vec(std::mt19937& gen, double lo, double hi)
{
    std::uniform_real_distribution<double> d(lo, hi);
    vec<N> x;
    for (int i = 0; i < N; ++i) x[i] = d(gen);
    return x;
}

}  // namespace vimpact::test
