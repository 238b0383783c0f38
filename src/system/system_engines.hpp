#pragma once
// The steppable systems' engines behind virtual interfaces, so that the public classes
// (include/vimpact/system/) hold a model-independent pointer: declared here, defined in
// system_engines.ipp and compiled for every engine model in its module beside its analyses
// (src/instances/: the flow and integrator templates both use are then compiled once). The
// public classes make them through detail::with_engine (dispatch.hpp) and make_flow_system,
// make_tangent_engine (engine_instances.hpp).
#include <memory>

#include <Eigen/Core>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/outcome.hpp"
#include "vimpact/core/state_series.hpp"
#include "vimpact/hybrid/flow_options.hpp"
#include "vimpact/hybrid/run_stats.hpp"
#include "vimpact/system/tangent_system.hpp"

namespace vimpact::detail {

// What a hybrid flow to step is set up with: the flow, its method, and what makes a point of
// the discrete-time system (a section watched, or impacts).
struct flow_system_spec {
    flow_options flow;
    integration_method method = integration_method::dop853;
    int section = -1;        // >= 0: the model section whose crossings are the points
    int impact_points = -2;  // >= 0: the impacts on that surface are the points; -1: on every one
};

// hybrid_system and section_system: the state and time of the last step's end (step,
// advance_to) or of the last point (next_point), and the impacts and crossings of switches in
// between.
class flow_system {
public:
    virtual ~flow_system() = default;
    [[nodiscard]] virtual std::unique_ptr<flow_system> clone() const = 0;
    virtual outcome step() = 0;
    virtual outcome advance_to(double t) = 0;
    // To the next point, within max_flight of the last one (else time_limit).
    virtual outcome next_point(double max_flight) = 0;
    [[nodiscard]] virtual run_stats stats() const = 0;
    [[nodiscard]] virtual bool in_contact() const = 0;

    [[nodiscard]] const Eigen::VectorXd& x() const { return m_x; }
    [[nodiscard]] double t() const { return m_t; }
    [[nodiscard]] outcome status() const { return m_status; }
    [[nodiscard]] const impact_series& impacts() const { return m_impacts; }
    [[nodiscard]] const impact_series& switchings() const { return m_switchings; }

protected:
    Eigen::VectorXd m_x;
    double m_t = 0.0;
    outcome m_status = outcome::ok;
    impact_series m_impacts;
    impact_series m_switchings;  // `surface`: the switch
};

// tangent_system: the state, time and deviations after the last step or at the last crossing.
class tangent_engine {
public:
    virtual ~tangent_engine() = default;
    [[nodiscard]] virtual std::unique_ptr<tangent_engine> clone() const = 0;
    virtual outcome step() = 0;
    virtual outcome advance_to(double t) = 0;
    // Starts the tangent flow again at the current point with deviations w.
    virtual void set_deviations(const Eigen::MatrixXd& w) = 0;
    [[nodiscard]] virtual run_stats stats() const = 0;

    [[nodiscard]] const Eigen::VectorXd& x() const { return m_x; }
    [[nodiscard]] double t() const { return m_t; }
    [[nodiscard]] const Eigen::MatrixXd& w() const { return m_w; }
    [[nodiscard]] outcome status() const { return m_status; }

protected:
    Eigen::VectorXd m_x;
    Eigen::MatrixXd m_w;
    double m_t = 0.0;
    outcome m_status = outcome::ok;
};

}  // namespace vimpact::detail
