#pragma once
// Which Runge-Kutta stepper a hybrid flow integrates with: the method itself for every model
// compiled into the caller, and, for a model behind a function table, a wrapper that uses the
// table's fused step for the free field when it has one (integrate/fused_step.hpp,
// model/table_model.hpp).
#include "vimpact/core/state.hpp"

namespace vimpact {

// The free vector field of a model, as the flow passes it to the integrator: a type of its
// own, so that a stepper can recognise it (the contact fields are lambdas).
template <class Model>
struct free_field {
    const Model* model;
    vec<Model::dim> operator()(const vec<Model::dim>& x) const { return model->rhs(x); }
    // The same into `out`, where the model writes there without a temporary (states sized at
    // run time: the Runge-Kutta stages of the tangent runs, integrate/runge_kutta.hpp).
    void into(const vec<Model::dim>& x, vec<Model::dim>& out) const
    {
        if constexpr (requires { model->rhs_into(x, out); }) model->rhs_into(x, out);
        else out = model->rhs(x);
    }
};

template <class Model, template <int> class Method>
struct flow_stepper {
    using type = Method<Model::dim>;
};

}  // namespace vimpact
