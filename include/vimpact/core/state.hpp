#pragma once
// Fixed-size state vectors: nothing in the integration loop allocates.
#include <Eigen/Core>

namespace vimpact {

template <int N>
using vec = Eigen::Matrix<double, N, 1>;

template <int N>
using mat = Eigen::Matrix<double, N, N>;

}  // namespace vimpact
