#pragma once
// The SIMD lanes' Runge-Kutta step compiled together with a model that lives in another binary
// (a model file, model/abi.h's lanes entries), as integrate/fused_step.hpp does for one job:
// the library's own stage code (the templates of integrate/runge_kutta.hpp on core/lanes.hpp's
// type, which hybrid/flow_lanes.hpp runs for the built-in models) with the field inlined. Each
// lane goes through the operations of its job alone in the same order, so it gets the same
// bits, provided no multiply-add is fused by the compiler on either side (model files are
// compiled with -ffp-contract=off, as the library's analyses are).
//
// The values cross the binary boundary as the library's own lanes objects (the ABI's "lanes
// values"): the library passes pointers to them as doubles, and they are read back as lanes.
#include <cstddef>

#include "vimpact/core/lanes.hpp"
#include "vimpact/integrate/fused_step.hpp"

namespace vimpact {

template <int N, template <int, class> class Method, class Field>
void fused_lanes_attempt(const Field& field, const double* x, const double* f, const double* h, double rtol,
                         double atol, double* x_new, double* f_new, double* stages, double* err2)
{
    using lvec = vec_t<lanes, N>;
    using method = Method<N, lanes>;
    static_assert(sizeof(lvec) == N * sizeof(lanes), "lanes vectors must be contiguous lanes values");
    // A method is its stages and nothing else: the caller's stages are its method, tried in place.
    static_assert(sizeof(method) == method::stage_count * sizeof(lvec), "a method must be its stages alone");
    auto& m = *reinterpret_cast<method*>(stages);
    *reinterpret_cast<lanes*>(err2) =
        m.attempt(field, *reinterpret_cast<const lvec*>(x), *reinterpret_cast<const lvec*>(f),
                  *reinterpret_cast<const lanes*>(h), rtol, atol, *reinterpret_cast<lvec*>(x_new),
                  *reinterpret_cast<lvec*>(f_new));
}

// The lanes_step entry of a model table for a lanes field `Field` (a functor of the lanes'
// contexts): method 0 DOP853, 1 DOPRI5, as fused_step_entry.
template <int N, class Field>
void fused_lanes_step_entry(const double* contexts, int method, const double* x, const double* f, const double* h,
                            double rtol, double atol, double* x_new, double* f_new, double* stages, double* err2)
{
    const Field field{contexts};
    if (method == static_cast<int>(fused_method::dopri5))
        fused_lanes_attempt<N, dopri5>(field, x, f, h, rtol, atol, x_new, f_new, stages, err2);
    else
        fused_lanes_attempt<N, dop853>(field, x, f, h, rtol, atol, x_new, f_new, stages, err2);
}

}  // namespace vimpact
