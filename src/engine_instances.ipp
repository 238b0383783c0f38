// The definitions of engine_instances.hpp: included by the source files of src/instances/,
// each of which instantiates them for one engine model with VIMPACT_INSTANTIATE_ENGINE, or
// (MODEL_lanes.cpp) its SIMD lanes with VIMPACT_INSTANTIATE_LANES.
#include "engine_instances.hpp"
#include "vimpact/engine/floquet.hpp"
#include "vimpact/engine/grazing.hpp"
#include "vimpact/engine/lyapunov.hpp"
#include "vimpact/engine/orbit_map.hpp"
#include "vimpact/engine/protocol.hpp"
#include "vimpact/integrate/runge_kutta.hpp"

#include <unordered_map>

namespace vimpact::detail {

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
    using D = typename EM::definition_type;
    // The jobs in the lanes, by the number run_in_lanes knows them by.
    std::unordered_map<long, protocol_job> running;
    long taken = 0;
    auto run = [&]<template <int, class = double> class M>() {
        return run_in_lanes<D, M>(
            width,
            [&]() -> std::optional<long> {
                std::optional<protocol_job> j = next();
                if (!j) return std::nullopt;
                running.emplace(taken, std::move(*j));
                return taken++;
            },
            [&](long k) {
                const protocol_job& j = running.at(k);
                return std::make_unique<engine::protocol_run<M, EM>>(EM(j.m.parameters()), head_as<EM::dim>(j.x0, EM::dim), o);
            },
            [&](long k) { return std::span<const double>(running.at(k).m.parameters()); },
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
        const simulation pr = run_simulate(em, x0, o.protocol);
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
    const simulation pr = run_simulate(em, x0, engine::lyapunov_transient(o, em.section_count() > 0));
    return with_method(o.method, [&]<template <int> class M>() { return engine::lyapunov_after_transient<M>(em, pr, o); });
}

}  // namespace vimpact::detail

// For an engine model that runs in SIMD lanes (lanes_engine<EM>), besides the above, in a
// source file of its own (src/instances/MODEL_lanes.cpp: CMakeLists.txt gives it the options
// of the lanes' moves, which would slow the other analyses' tangent runs).
#define VIMPACT_INSTANTIATE_LANES(EM)                                                                            \
    template vimpact::lanes_counts vimpact::detail::run_simulate_lanes<EM>(                                      \
        const vimpact::protocol_options&, int, const vimpact::protocol_source&, const vimpact::protocol_sink&);

#define VIMPACT_INSTANTIATE_ENGINE(EM)                                                                           \
    template vimpact::simulation vimpact::detail::run_simulate<EM>(const EM&, const Eigen::VectorXd&,            \
                                                                    const vimpact::protocol_options&);           \
    template vimpact::grazing_result vimpact::detail::run_grazing<EM>(const EM&, const Eigen::VectorXd&,         \
                                                                       const vimpact::grazing_options&);         \
    template vimpact::floquet_result vimpact::detail::run_floquet<EM>(                                           \
        const EM&, const Eigen::VectorXd&, const vimpact::floquet_options&, const vimpact::model_info&);         \
    template vimpact::floquet_result vimpact::detail::run_floquet_from_point<EM>(                                \
        const EM&, const Eigen::VectorXd&, int, const vimpact::floquet_options&);                                 \
    template vimpact::orbit_map_value vimpact::detail::run_orbit_map<EM>(const EM&,                               \
                                                                          const vimpact::orbit_map_request&);    \
    template vimpact::lyapunov_result vimpact::detail::run_lyapunov<EM>(const EM&, const Eigen::VectorXd&,       \
                                                                         const vimpact::lyapunov_options&);
