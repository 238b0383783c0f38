#pragma once
// The analyses on one engine model: declared here, defined in engine_instances.ipp, and
// instantiated for every engine model in src/instances/ (one source file per model, and one
// more for a built-in model's SIMD lanes).
#include <Eigen/Core>

#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/lyapunov.hpp"
#include "vimpact/analysis/orbit_map.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/model/builtin/forced_impact_oscillator.hpp"
#include "vimpact/model/builtin/two_sided_impact_oscillator.hpp"
#include "vimpact/model/builtin/wake_impact.hpp"
#include "vimpact/model/native_model.hpp"
#include "vimpact/model/table_model.hpp"
#include "vimpact/hybrid/flow_lanes.hpp"

#include <type_traits>
#include <vector>

namespace vimpact::detail {

template <class EM>
simulation run_simulate(const EM& em, const Eigen::VectorXd& x0, const protocol_options& o);

// An engine model whose protocol runs can share SIMD lanes (hybrid/flow_lanes.hpp).
template <class EM>
struct lanes_engine_t : std::false_type {};
template <class D>
struct lanes_engine_t<native_model<D>> : std::bool_constant<lanes_capable<D>> {};
template <class EM>
inline constexpr bool lanes_engine = lanes_engine_t<EM>::value;

// The protocol for the jobs `next` gives (models of the engine model EM, differing in their
// parameters), up to `width` at once in SIMD lanes (simulate_stream).
template <class EM>
lanes_counts run_simulate_lanes(const protocol_options& o, int width, const protocol_source& next,
                                const protocol_sink& done);

template <class EM>
grazing_result run_grazing(const EM& em, const Eigen::VectorXd& x0, const grazing_options& o);

template <class EM>
floquet_result run_floquet(const EM& em, const Eigen::VectorXd& x0, const floquet_options& o, const model_info& info);

template <class EM>
floquet_result run_floquet_from_point(const EM& em, const Eigen::VectorXd& x, int returns, const floquet_options& o);

template <class EM>
orbit_map_value run_orbit_map(const EM& em, const orbit_map_request& r);

template <class EM>
lyapunov_result run_lyapunov(const EM& em, const Eigen::VectorXd& x0, const lyapunov_options& o);

}  // namespace vimpact::detail
