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

// A fixed-size vector or matrix as a dynamic one, element by element (Eigen's packet copy into
// a dynamic destination trips false -Warray-bounds errors in GCC 12 with AVX-512 for sizes
// below one register).
template <class Derived>
Eigen::Matrix<double, Eigen::Dynamic, Derived::ColsAtCompileTime == 1 ? 1 : Eigen::Dynamic> to_dynamic(
    const Eigen::MatrixBase<Derived>& a)
{
    Eigen::Matrix<double, Eigen::Dynamic, Derived::ColsAtCompileTime == 1 ? 1 : Eigen::Dynamic> out(a.rows(), a.cols());
    for (Eigen::Index j = 0; j < a.cols(); ++j)
        for (Eigen::Index i = 0; i < a.rows(); ++i) out(i, j) = a(i, j);
    return out;
}

}  // namespace vimpact
