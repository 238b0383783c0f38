#pragma once
// Helpers shared by the unit tests.
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "vimpact/hybrid/flow.hpp"
#include "vimpact/model/model.hpp"

namespace vimpact::test {

// Largest |a_ij - b_ij| by a plain loop (Eigen's AVX-512 reductions of small fixed-size
// matrices trip false -Wmaybe-uninitialized errors in GCC 12).
template <class A, class B>
double max_abs_diff(const A& a, const B& b)
{
    double m = 0.0;
    for (Eigen::Index i = 0; i < a.rows(); ++i)
        for (Eigen::Index j = 0; j < a.cols(); ++j) m = std::max(m, std::abs(a(i, j) - b(i, j)));
    return m;
}

template <int N>
Eigen::Matrix<double, N, 1> random_vec(std::mt19937& gen, double scale = 1.0)
{
    std::uniform_real_distribution<double> u(-scale, scale);
    Eigen::Matrix<double, N, 1> x;
    for (int i = 0; i < N; ++i) x[i] = u(gen);
    return x;
}

// The default parameter values of a C++ definition D (native_model<D> takes them in order).
template <class D>
std::vector<double> defaults()
{
    std::vector<double> p;
    for (const auto& q : D::parameters) p.push_back(q.default_value);
    return p;
}

// Flow options with one tolerance for rtol and atol, and a time limit.
inline flow_options flow_tolerances(double tol, double t_max)
{
    flow_options o;
    o.integration.rtol = tol;
    o.integration.atol = tol;
    o.t_max = t_max;
    return o;
}

// The model with parameters changed by name (a test's shorthand; front ends look names up
// once and pass indices).
inline model with(model m, std::string_view name, double value)
{
    const int i = m.info().parameter_index(name);
    if (i < 0) throw std::invalid_argument("no parameter " + std::string(name));
    return m.with_parameter(i, value);
}

// The paper's model at Ur and sigma (paper preset).
inline model paper(double Ur, double sigma = -0.150298) { return with(with(model{}, "Ur", Ur), "sigma", sigma); }

inline Eigen::VectorXd paper_ic() { return Eigen::Vector4d(0.0, 0.0, 0.0, 0.1); }

}  // namespace vimpact::test
