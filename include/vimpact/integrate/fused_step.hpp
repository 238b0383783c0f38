#pragma once
// A Runge-Kutta step compiled together with one vector field, for a model that lives in
// another binary (a model file or plugin, model/abi.h): the library would otherwise call the
// field once per stage through a pointer, and the stage chain could not be scheduled across
// the calls (about twice the time per step for a 4-dimensional model). The model's binary
// compiles these two functions with its field inlined and exports them in its table; the
// library keeps the stages between a step and its interpolant, in memory laid out as the
// method (method_at).
//
// The arithmetic is the library's (the same templates of integrate/runge_kutta.hpp); only
// where it is compiled differs.
#include <cstddef>

#include "vimpact/integrate/runge_kutta.hpp"

namespace vimpact {

enum class fused_method : int { dop853 = 0, dopri5 = 1 };

// The caller's stage memory is the method (a method is its stages alone): the step is tried in
// place, and the stages stay there for the interpolant, without a copy either way.
template <int N, template <int> class Method>
Method<N>& method_at(double* stages)
{
    static_assert(sizeof(vec<N>) == N * sizeof(double), "stages must be contiguous doubles");
    static_assert(sizeof(Method<N>) == Method<N>::stage_count * sizeof(vec<N>), "a method must be its stages alone");
    return *reinterpret_cast<Method<N>*>(stages);
}

template <int N, template <int> class Method, class F>
double fused_attempt(F&& rhs, const double* x, const double* f, double h, double rtol, double atol, double* x_new,
                     double* f_new, double* stages)
{
    vec<N> xn, fn;
    const double err2 = method_at<N, Method>(stages).attempt(rhs, Eigen::Map<const vec<N>>(x),
                                                             Eigen::Map<const vec<N>>(f), h, rtol, atol, xn, fn);
    Eigen::Map<vec<N>> x_out(x_new), f_out(f_new);
    x_out = xn;
    f_out = fn;
    return err2;
}

template <int N, template <int> class Method, class F>
void fused_dense(F&& rhs, double t0, double h, const double* x0, const double* x1, double* stages,
                 double* coefficients)
{
    typename Method<N>::dense_type d;
    method_at<N, Method>(stages).build_dense(rhs, t0, h, Eigen::Map<const vec<N>>(x0), Eigen::Map<const vec<N>>(x1), d);
    for (std::size_t j = 0; j < d.c.size(); ++j) {
        Eigen::Map<vec<N>> out(coefficients + j * N);
        out = d.c[j];
    }
}

// The two entry points of a model table for a field `F` (a functor of a const double* context
// returning the field): method 0 DOP853, 1 DOPRI5.
template <int N, class Field>
double fused_step_entry(const void* c, int method, const double* x, const double* f, double h, double rtol, double atol,
                        double* x_new, double* f_new, double* stages)
{
    const Field field{c};
    if (method == static_cast<int>(fused_method::dopri5))
        return fused_attempt<N, dopri5>(field, x, f, h, rtol, atol, x_new, f_new, stages);
    return fused_attempt<N, dop853>(field, x, f, h, rtol, atol, x_new, f_new, stages);
}

template <int N, class Field>
void fused_dense_entry(const void* c, int method, double t0, double h, const double* x0, const double* x1,
                       double* stages, double* coefficients)
{
    const Field field{c};
    if (method == static_cast<int>(fused_method::dopri5))
        fused_dense<N, dopri5>(field, t0, h, x0, x1, stages, coefficients);
    else
        fused_dense<N, dop853>(field, t0, h, x0, x1, stages, coefficients);
}

}  // namespace vimpact
