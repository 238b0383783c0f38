#pragma once
// The analyses on one engine model. Each engine model's analyses are compiled into a module of
// their own (src/instances/: libvimpact_engine_MODEL.so beside libvimpact.so), loaded the first
// time a run uses that model (core/load_module.hpp). So a build of the library and the program
// compiles none of them (the program's main job then needs only its model's module), and a run
// loads only the models it runs. The calls below are the library's side: each forwards to the
// model's module through its table of functions (engine_functions); the definitions are in
// engine_instances.ipp, namespace instance, compiled only in the modules.
#include <Eigen/Core>

#include "system/system_engines.hpp"
#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/lyapunov.hpp"
#include "vimpact/analysis/orbit_map.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/model/builtin/forced_impact_oscillator.hpp"
#include "vimpact/model/builtin/two_sided_impact_oscillator.hpp"
#include "vimpact/model/builtin/wake_impact.hpp"
#include "vimpact/model/model.hpp"
#include "vimpact/model/native_model.hpp"
#include "vimpact/model/table_lanes.hpp"
#include "vimpact/model/table_model.hpp"
#include "vimpact/hybrid/flow_lanes.hpp"

#include <memory>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <vector>

namespace vimpact::detail {

// An engine model whose protocol runs can share SIMD lanes (hybrid/flow_lanes.hpp).
template <class EM>
struct lanes_engine_t : std::false_type {};
template <class D>
struct lanes_engine_t<native_model<D>> : std::bool_constant<lanes_capable<D>> {};
// A model file's lanes come with its table (model/table_lanes.hpp), for the fixed dimensions.
template <int N>
struct lanes_engine_t<table_model<N>> : std::bool_constant<N != Eigen::Dynamic> {};
template <class EM>
inline constexpr bool lanes_engine = lanes_engine_t<EM>::value;

// The engine model EM of m: a built-in's from its parameters, a table's from its table and
// context.
template <class EM>
EM engine_model_of(const model& m)
{
    if constexpr (requires { typename EM::definition_type; }) return EM(m.parameters());
    else return EM(m.table(), m.context());
}

// Whether this model's jobs run in lanes: a lanes engine, whose table (if any) has lanes of
// this build's width.
template <class EM>
bool lanes_ready(const EM& em)
{
    if constexpr (!lanes_engine<EM>) return false;
    else if constexpr (requires { em.table(); }) return table_lanes<EM::dim>::available(em.table());
    else return true;
}

// What an engine model's module gives: its analyses, as engine_instances.ipp defines them.
template <class EM>
struct engine_functions {
    // The model the module was compiled for (typeid(EM).name()): a module of another model or
    // of another build under the expected name is refused, not called.
    const char* model = nullptr;
    simulation (*simulate)(const EM&, const Eigen::VectorXd&, const protocol_options&) = nullptr;
    // Null where the model has no SIMD lanes (lanes_engine).
    lanes_counts (*simulate_lanes)(const protocol_options&, int, const protocol_source&, const protocol_sink&) = nullptr;
    grazing_result (*grazing)(const EM&, const Eigen::VectorXd&, const grazing_options&) = nullptr;
    floquet_result (*floquet)(const EM&, const Eigen::VectorXd&, const floquet_options&, const model_info&) = nullptr;
    floquet_result (*floquet_from_point)(const EM&, const Eigen::VectorXd&, int, const floquet_options&) = nullptr;
    orbit_map_value (*orbit_map)(const EM&, const orbit_map_request&) = nullptr;
    lyapunov_result (*lyapunov)(const EM&, const Eigen::VectorXd&, const lyapunov_options&) = nullptr;
    std::unique_ptr<flow_system> (*make_flow_system)(const EM&, const flow_system_spec&, double,
                                                const Eigen::VectorXd&) = nullptr;
    std::unique_ptr<tangent_engine> (*make_tangent_engine)(const EM&, const tangent_system_options&, double,
                                                      const Eigen::VectorXd&, const Eigen::MatrixXd&) = nullptr;
};

// The module of an engine model: libvimpact_engine_NAME.so, NAME the built-in model's name, or
// table_N / table_dynamic for the model files and plugins of dimension N (CMakeLists.txt
// builds them under the same names).
template <class D>
std::string engine_module_file(std::type_identity<native_model<D>>)
{
    return "libvimpact_engine_" + std::string(D::name) + ".so";
}
template <int N>
std::string engine_module_file(std::type_identity<table_model<N>>)
{
    return "libvimpact_engine_table_" + (N == Eigen::Dynamic ? std::string("dynamic") : std::to_string(N)) + ".so";
}

// The module's table, at `symbol` (its vimpact_engine_v1), checked to be EM's.
const void* engine_table(const std::string& file, const char* model);

// EM's functions, its module loaded by the first call (thread-safe: a static's initialisation).
template <class EM>
const engine_functions<EM>& engine_of()
{
    static const engine_functions<EM>& f = *static_cast<const engine_functions<EM>*>(
        engine_table(engine_module_file(std::type_identity<EM>{}), typeid(EM).name()));
    return f;
}

template <class EM>
simulation run_simulate(const EM& em, const Eigen::VectorXd& x0, const protocol_options& o)
{
    return engine_of<EM>().simulate(em, x0, o);
}

// The protocol for the jobs `next` gives (models of the engine model EM, differing in their
// parameters), up to `width` at once in SIMD lanes (simulate_stream). Only for lanes_engine<EM>.
template <class EM>
lanes_counts run_simulate_lanes(const protocol_options& o, int width, const protocol_source& next,
                                const protocol_sink& done)
{
    return engine_of<EM>().simulate_lanes(o, width, next, done);
}

template <class EM>
grazing_result run_grazing(const EM& em, const Eigen::VectorXd& x0, const grazing_options& o)
{
    return engine_of<EM>().grazing(em, x0, o);
}

template <class EM>
floquet_result run_floquet(const EM& em, const Eigen::VectorXd& x0, const floquet_options& o, const model_info& info)
{
    return engine_of<EM>().floquet(em, x0, o, info);
}

template <class EM>
floquet_result run_floquet_from_point(const EM& em, const Eigen::VectorXd& x, int returns, const floquet_options& o)
{
    return engine_of<EM>().floquet_from_point(em, x, returns, o);
}

template <class EM>
orbit_map_value run_orbit_map(const EM& em, const orbit_map_request& r)
{
    return engine_of<EM>().orbit_map(em, r);
}

template <class EM>
lyapunov_result run_lyapunov(const EM& em, const Eigen::VectorXd& x0, const lyapunov_options& o)
{
    return engine_of<EM>().lyapunov(em, x0, o);
}

// Started at (t, x); throws input_error where the flow does (x beyond a surface).
template <class EM>
std::unique_ptr<flow_system> make_flow_system(const EM& em, const flow_system_spec& s, double t,
                                              const Eigen::VectorXd& x)
{
    return engine_of<EM>().make_flow_system(em, s, t, x);
}

// Started at (t, x) with deviations w (N x k, k = o.deviations).
template <class EM>
std::unique_ptr<tangent_engine> make_tangent_engine(const EM& em, const tangent_system_options& o, double t,
                                                    const Eigen::VectorXd& x, const Eigen::MatrixXd& w)
{
    return engine_of<EM>().make_tangent_engine(em, o, t, x, w);
}

}  // namespace vimpact::detail
