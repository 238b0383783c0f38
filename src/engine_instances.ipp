// The analyses on one engine model, as its module compiles them: included by the source files
// of src/instances/, each of which makes the module of one engine model with
// VIMPACT_ENGINE_MODULE, or (MODEL_lanes.cpp) compiles its SIMD lanes with
// VIMPACT_ENGINE_LANES.
#include "engine_instances.hpp"
#include "system/system_engines.ipp"
#include "vimpact/engine/floquet.hpp"
#include "vimpact/engine/grazing.hpp"
#include "vimpact/engine/lyapunov.hpp"
#include "vimpact/engine/orbit_map.hpp"
#include "vimpact/engine/protocol.hpp"
#include "vimpact/integrate/runge_kutta.hpp"

#include <unordered_map>

namespace vimpact::detail {

namespace instance {

// f.template operator()<Method>() for the chosen integrator.
template <class F>
auto with_method(integration_method m, F&& f)
{
    if (m == integration_method::dopri5) return f.template operator()<dopri5>();
    return f.template operator()<dop853>();
}


template <class EM>
simulation run_simulate(const EM& em, const Eigen::VectorXd& x0, const protocol_options& o)
{
    return with_method(o.method, [&]<template <int> class M>() { return engine::run_protocol<M>(em, head_as<EM::dim>(x0, state_dim(em)), o); });
}

template <class EM>
lanes_counts run_simulate_lanes(const protocol_options& o, int width, const protocol_source& next,
                                const protocol_sink& done)
{
    constexpr bool table = !requires { typename EM::definition_type; };
    // The jobs in the lanes, by the number run_in_lanes knows them by.
    std::unordered_map<long, protocol_job> running;
    long taken = 0;
    // A table's lanes definition: its lanes and the lanes of the jobs' contexts (the jobs
    // share the table: simulate_stream gives the lanes one model's jobs).
    const vimpact_model_table* lanes_table = nullptr;
    const auto make = [&](std::span<const lanes> p) {
        if constexpr (table) return table_lanes<EM::dim>(*lanes_table, p);
        else return typename EM::definition_type::lanes_definition(p);
    };
    using L = std::invoke_result_t<decltype(make), std::span<const lanes>>;
    auto run = [&]<template <int, class = double> class M>() {
        return run_in_lanes_of<L, EM::dim, M>(
            width, make,
            [&]() -> std::optional<long> {
                std::optional<protocol_job> j = next();
                if (!j) return std::nullopt;
                if constexpr (table) lanes_table = &j->m.table();
                running.emplace(taken, std::move(*j));
                return taken++;
            },
            [&](long k) {
                const protocol_job& j = running.at(k);
                return std::make_unique<engine::protocol_run<M, EM>>(engine_model_of<EM>(j.m), head_as<EM::dim>(j.x0, EM::dim), o);
            },
            [&](long k) {
                const model& m = running.at(k).m;
                if constexpr (table)
                    return std::span<const double>(static_cast<const double*>(m.context()),
                                                   static_cast<std::size_t>(m.table().context_size));
                else return std::span<const double>(m.parameters());
            },
            [&](long k, simulation&& s) {
                auto node = running.extract(k);
                done(std::move(node.mapped()), std::move(s));
            });
    };
    if (o.method == integration_method::dopri5) return run.template operator()<dopri5>();
    return run.template operator()<dop853>();
}

template <class EM>
grazing_result run_grazing(const EM& em, const Eigen::VectorXd& x0, const grazing_options& o)
{
    return with_method(o.method, [&]<template <int> class M>() { return engine::run_grazing<M>(em, head_as<EM::dim>(x0, state_dim(em)), o); });
}

// The tangent flows always integrate with DOP853: at the tolerances they need (1e-12) a
// fifth-order pair takes several times the steps, and one instantiation of the large tangent
// systems per model keeps the library's build time in bounds. The method chosen by the caller
// integrates the protocol's runs.
template <class EM>
floquet_result run_floquet(const EM& em, const Eigen::VectorXd& x0, const floquet_options& o, const model_info& info)
{
    if constexpr (EM::dim != Eigen::Dynamic && EM::dim < 2) return floquet_result{};
    else {
        if (state_dim(em) < 2) return floquet_result{};
        // The protocol with the caller's method, then the tangent runs.
        const simulation pr = instance::run_simulate(em, x0, o.protocol);
        return engine::floquet_after_protocol<dop853>(em, pr, o, info);
    }
}

template <class EM>
floquet_result run_floquet_from_point(const EM& em, const Eigen::VectorXd& x, int returns, const floquet_options& o)
{
    if constexpr (EM::dim != Eigen::Dynamic && EM::dim < 2) return floquet_result{};
    else {
        if (state_dim(em) < 2) return floquet_result{};
        return engine::floquet_from_point<dop853>(em, head_as<EM::dim>(x, state_dim(em)), returns, o);
    }
}

// DOP853, as every tangent run (see run_floquet); the runs without the tangent use it too, so
// that the residual is the same function of z with and without the tangent.
template <class EM>
orbit_map_value run_orbit_map(const EM& em, const orbit_map_request& r)
{
    if constexpr (EM::dim != Eigen::Dynamic && EM::dim < 2) return orbit_map_value{};
    else {
        if (state_dim(em) < 2) return orbit_map_value{};
        return engine::orbit_map<dop853>(em, r);
    }
}

template <class EM>
lyapunov_result run_lyapunov(const EM& em, const Eigen::VectorXd& x0, const lyapunov_options& o)
{
    const simulation pr = instance::run_simulate(em, x0, engine::lyapunov_transient(o, em.section_count() > 0));
    return with_method(o.method, [&]<template <int> class M>() { return engine::lyapunov_after_transient<M>(em, pr, o); });
}

}  // namespace instance

// The table of EM's module (its lanes, where it has them, from MODEL_lanes.cpp).
template <class EM>
engine_functions<EM> engine_functions_of()
{
    engine_functions<EM> f;
    f.model = typeid(EM).name();
    f.simulate = &instance::run_simulate<EM>;
    if constexpr (lanes_engine<EM>) f.simulate_lanes = &instance::run_simulate_lanes<EM>;
    f.grazing = &instance::run_grazing<EM>;
    f.floquet = &instance::run_floquet<EM>;
    f.floquet_from_point = &instance::run_floquet_from_point<EM>;
    f.orbit_map = &instance::run_orbit_map<EM>;
    f.lyapunov = &instance::run_lyapunov<EM>;
    f.make_flow_system = &instance::make_flow_system<EM>;
    f.make_tangent_engine = &instance::make_tangent_engine<EM>;
    return f;
}

}  // namespace vimpact::detail

// A model's SIMD lanes, in a source file of its own (src/instances/MODEL_lanes.cpp:
// CMakeLists.txt gives it the options of the lanes' moves, which would slow the other
// analyses' tangent runs).
#define VIMPACT_ENGINE_LANES(EM)                                                                                   \
    template vimpact::lanes_counts vimpact::detail::instance::run_simulate_lanes<EM>(                              \
        const vimpact::protocol_options&, int, const vimpact::protocol_source&, const vimpact::protocol_sink&);

// The module of the engine model EM: its table, the one symbol the library looks up. The lanes
// are compiled in MODEL_lanes.cpp, never here (a copy compiled without the lanes' options
// could be the one the linker keeps).
#define VIMPACT_ENGINE_MODULE(EM)                                                                                  \
    extern template vimpact::lanes_counts vimpact::detail::instance::run_simulate_lanes<EM>(                       \
        const vimpact::protocol_options&, int, const vimpact::protocol_source&, const vimpact::protocol_sink&);    \
    extern "C" __attribute__((visibility("default"))) const void* vimpact_engine_v1()                             \
    {                                                                                                              \
        static const vimpact::detail::engine_functions<EM> f = vimpact::detail::engine_functions_of<EM>();        \
        return &f;                                                                                                 \
    }
