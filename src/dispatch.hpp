#pragma once
// From a runtime model to the compiled engine: the one place where the library chooses, for
// each call, which instantiation of an analysis template runs. Built-in models run on their
// native definitions (everything inlined); model files and plugins on table_model<N> for
// their dimension N when VIMPACT_MODEL_DIMS lists it (fixed-size states), on
// table_model<Eigen::Dynamic> otherwise (states sized at run time; one indirect call per model
// function either way).
//
// The analyses' templates are instantiated once per engine model, each model in source
// files of its own (src/instances/: a built-in model's SIMD lanes in a second one,
// MODEL_lanes.cpp, compiled with their own options), so that the build spreads over the cores; the analysis
// sources call the instantiations declared in engine_instances.hpp through with_engine.
#include <optional>
#include <utility>

#include "engine_instances.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/model/model.hpp"

namespace vimpact::detail {

using model_dimensions = std::integer_sequence<int, VIMPACT_MODEL_DIMS>;

template <class F, int... Dims>
auto with_table_dimension(std::integer_sequence<int, Dims...>, int dim, F&& f)
{
    using R = decltype(f.template operator()<Eigen::Dynamic>());
    std::optional<R> r;
    ((dim == Dims ? (r.emplace(f.template operator()<Dims>()), true) : false) || ...);
    if (!r) {
        check_engine_dimension(dim, "model " + std::to_string(dim));
        r.emplace(f.template operator()<Eigen::Dynamic>());
    }
    return std::move(*r);
}

// Calls f(engine_model) with the engine model of `m`; every call must return the same type.
template <class F>
auto with_engine(const model& m, F&& f)
{
    switch (m.native()) {
        case native_kind::wake_impact: return f(engine_model_of<native_model<wake_impact>>(m));
        case native_kind::forced_impact_oscillator: return f(engine_model_of<native_model<forced_impact_oscillator>>(m));
        case native_kind::two_sided_impact_oscillator:
            return f(engine_model_of<native_model<two_sided_impact_oscillator>>(m));
        case native_kind::none: break;
    }
    return with_table_dimension(model_dimensions{}, m.dim(),
                                [&]<int N>() { return f(engine_model_of<table_model<N>>(m)); });
}

}  // namespace vimpact::detail
