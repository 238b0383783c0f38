#pragma once
// Forward-mode automatic differentiation of the functions a model states once, as templates
// over the scalar type (model/definition.hpp), with Eigen's AutoDiffScalar: a value carrying
// fixed-size derivative vectors, nested for second derivatives. Exact to rounding, no step
// size to choose.
//
//   jacobian(f, x)            Df(x), f: R^N -> R^M (vector) or R (row vector)
//   gradient(g, x)            grad g(x) for a scalar g
//   hessian(g, x)             D2g(x) as an N x N matrix (nested N-directional duals)
//   second_directional(f, x, u, w)   D2f(x)[u, w] (nested one-directional duals)
#include <type_traits>

#include "vimpact/core/state.hpp"  // Eigen/Core first: the AutoDiff module needs it

#include <unsupported/Eigen/AutoDiff>

namespace vimpact::ad {

template <int N>
using dual = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;

// One direction inside one direction: the ee-coefficient of f(x + e1 u + e2 w) is D2f[u, w].
using dual1 = Eigen::AutoDiffScalar<Eigen::Matrix<double, 1, 1>>;
using dual11 = Eigen::AutoDiffScalar<Eigen::Matrix<dual1, 1, 1>>;

// N directions inside N directions: the Hessian of a scalar.
template <int N>
using dual_nn = Eigen::AutoDiffScalar<Eigen::Matrix<dual<N>, N, 1>>;

template <int N>
vec_t<dual<N>, N> seed(const vec<N>& x)
{
    vec_t<dual<N>, N> y;
    for (int i = 0; i < N; ++i) y[i] = dual<N>(x[i], N, i);
    return y;
}

template <int N, class F>
auto jacobian(F&& f, const vec<N>& x)
{
    const auto y = f(seed<N>(x));
    using R = std::decay_t<decltype(y)>;
    if constexpr (std::is_same_v<R, dual<N>>) {
        return Eigen::Matrix<double, 1, N>(y.derivatives().transpose());
    } else {
        constexpr int M = R::RowsAtCompileTime;
        Eigen::Matrix<double, M, N> J;
        for (int i = 0; i < M; ++i) J.row(i) = y[i].derivatives().transpose();
        return J;
    }
}

template <int N, class F>
vec<N> gradient(F&& g, const vec<N>& x)
{
    return g(seed<N>(x)).derivatives();
}

template <int N, class F>
mat<N> hessian(F&& g, const vec<N>& x)
{
    using inner = dual<N>;
    using outer = dual_nn<N>;
    vec_t<outer, N> y;
    for (int i = 0; i < N; ++i) {
        y[i].value() = inner(x[i], N, i);
        y[i].derivatives() = Eigen::Matrix<inner, N, 1>::Constant(inner(0.0, vec<N>::Zero()));
        y[i].derivatives()[i] = inner(1.0, vec<N>::Zero());
    }
    const outer r = g(y);
    mat<N> H;
    for (int i = 0; i < N; ++i) H.row(i) = r.derivatives()[i].derivatives().transpose();
    return H;
}

// Df(x) v for a scalar f: one direction, so twice the cost of f (a gradient costs N + 1).
template <int N, class F>
double directional(F&& f, const vec<N>& x, const vec<N>& v)
{
    using E = Eigen::Matrix<double, 1, 1>;
    vec_t<dual1, N> y;
    for (int i = 0; i < N; ++i) y[i] = dual1(x[i], E::Constant(v[i]));
    return f(y).derivatives()[0];
}

// D2f(x)[u, w]: a vector for a vector-valued f, a double for a scalar one.
template <int N, class F>
auto second_directional(F&& f, const vec<N>& x, const vec<N>& u, const vec<N>& w)
{
    using E = Eigen::Matrix<double, 1, 1>;
    vec_t<dual11, N> y;
    for (int i = 0; i < N; ++i) {
        y[i].value() = dual1(x[i], E::Constant(u[i]));
        y[i].derivatives() = Eigen::Matrix<dual1, 1, 1>::Constant(dual1(w[i], E::Zero()));
    }
    const auto r = f(y);
    using R = std::decay_t<decltype(r)>;
    if constexpr (std::is_same_v<R, dual11>) {
        return r.derivatives()[0].derivatives()[0];
    } else {
        constexpr int M = R::RowsAtCompileTime;
        vec<M> out;
        for (int i = 0; i < M; ++i) out[i] = r[i].derivatives()[0].derivatives()[0];
        return out;
    }
}

}  // namespace vimpact::ad
