#pragma once
// State vectors: fixed-size, so that nothing in the integration loop allocates, for every
// built-in model and the model-file dimensions the library is compiled for; N = Eigen::Dynamic
// (a model file of any other dimension) sizes them at run time. vec_t<T, N> is the same over
// another scalar type (the automatic-differentiation scalars of model/autodiff.hpp).
#include <Eigen/Core>

namespace vimpact {

template <int N>
using vec = Eigen::Matrix<double, N, 1>;

template <int N>
using mat = Eigen::Matrix<double, N, N>;

template <class T, int N>
using vec_t = Eigen::Matrix<T, N, 1>;

inline constexpr int dynamic_dim = Eigen::Dynamic;

// The compile-time size N - 1 (a section's chart), dynamic when N is.
constexpr int dim_less_one(int N) { return N == Eigen::Dynamic ? Eigen::Dynamic : N - 1; }

// An uninitialised vector of n components: sized at run time where V is dynamic (a fixed-size
// V has n components already).
template <class V>
V sized(Eigen::Index n)
{
    if constexpr (V::SizeAtCompileTime == Eigen::Dynamic) return V(n);
    else return V();
}

// The first n components of x as a vec<N> (n == N where N is fixed).
template <int N>
vec<N> head_as(const Eigen::VectorXd& x, [[maybe_unused]] Eigen::Index n)
{
    if constexpr (N == Eigen::Dynamic) return x.head(n);
    else return x.template head<N>();
}

// a into `out`, element by element (see to_dynamic below), resized only when its size differs: a
// stepped system that publishes its state after every step allocates nothing from one step to
// the next.
template <class Derived, class Out>
void assign_dynamic(const Eigen::MatrixBase<Derived>& a, Out& out)
{
    out.resize(a.rows(), a.cols());
    for (Eigen::Index j = 0; j < a.cols(); ++j)
        for (Eigen::Index i = 0; i < a.rows(); ++i) out(i, j) = a(i, j);
}

// A fixed-size vector or matrix as a dynamic one, element by element (Eigen's packet copy into
// a dynamic destination trips false -Warray-bounds errors in GCC 12 with AVX-512 for sizes
// below one register).
template <class Derived>
Eigen::Matrix<double, Eigen::Dynamic, Derived::ColsAtCompileTime == 1 ? 1 : Eigen::Dynamic> to_dynamic(
    const Eigen::MatrixBase<Derived>& a)
{
    Eigen::Matrix<double, Eigen::Dynamic, Derived::ColsAtCompileTime == 1 ? 1 : Eigen::Dynamic> out(a.rows(), a.cols());
    assign_dynamic(a, out);
    return out;
}

}  // namespace vimpact
