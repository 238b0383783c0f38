#pragma once
// Fixed-size state vectors: nothing in the integration loop allocates. vec_t<T, N> is the
// same over another scalar type (the automatic-differentiation scalars of model/autodiff.hpp).
#include <Eigen/Core>

namespace vimpact {

template <int N>
using vec = Eigen::Matrix<double, N, 1>;

template <int N>
using mat = Eigen::Matrix<double, N, N>;

template <class T, int N>
using vec_t = Eigen::Matrix<T, N, 1>;

}  // namespace vimpact
