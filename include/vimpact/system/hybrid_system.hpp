#pragma once
// The hybrid flow of a model as an object to step: its state and time, one integrator step
// at a time (through impacts and contact phases) or to a given time exactly, reinit to any
// state, parameters to change. A researcher's own analysis is a loop over step() or
// advance_to(). Underneath is the library's hybrid flow (hybrid/flow.hpp), stepped by
// engine/stepping.hpp, which the Lyapunov spectrum's tangent intervals step too. The engine
// stays behind the object: this header does not include the integrator.
//
// The continuous-time system of the family: section_system.hpp (the section or impact map)
// and tangent_system.hpp (with deviation vectors) are its discrete and linearised kin.
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/outcome.hpp"
#include "vimpact/core/state_series.hpp"
#include "vimpact/hybrid/flow_options.hpp"
#include "vimpact/hybrid/run_stats.hpp"
#include "vimpact/model/model.hpp"

namespace vimpact {

struct hybrid_system_options {
    // Integration, limits (t_max, max_steps, max_impacts, cancel) and the chattering rule;
    // the surfaces always act, and the flow watches no events (`events` must be empty).
    flow_options flow{};
    integration_method method = integration_method::dop853;
};

namespace detail {
class flow_system;
}

class hybrid_system {
public:
    // At (t0, x0). Throws input_error for a state of the wrong size, not finite or beyond a
    // surface, a time not finite, or options out of range.
    hybrid_system(model m, const Eigen::VectorXd& x0, double t0 = 0.0, hybrid_system_options o = {});
    hybrid_system(const hybrid_system& other);
    hybrid_system& operator=(const hybrid_system& other);
    hybrid_system(hybrid_system&&) noexcept;
    hybrid_system& operator=(hybrid_system&&) noexcept;
    ~hybrid_system();

    [[nodiscard]] const Eigen::VectorXd& state() const;
    [[nodiscard]] double time() const;
    // ok while the system can go on; else why it stopped (non_finite, chattering,
    // step_limit, time_limit, ...): then step() and advance_to() change nothing until reinit.
    [[nodiscard]] outcome status() const;
    // Counters since the last (re)start: steps, impacts, contact phases, ...
    [[nodiscard]] run_stats stats() const;
    // The impacts of the last step() or advance_to() call, with the states before and after.
    [[nodiscard]] const impact_series& impacts() const;
    // The crossings of switching surfaces of that call (`surface`: the switch).
    [[nodiscard]] const impact_series& switchings() const;
    // In a contact phase (at rest on a surface that declares one).
    [[nodiscard]] bool in_contact() const;

    // One accepted integrator step, through any impact in it.
    outcome step();
    // To time() + dt exactly (dt >= 0).
    outcome step(double dt);
    // To time t exactly (t >= time()): in free flight the last step is cut to end at t.
    outcome advance_to(double t);
    // Starts again at (t, x), as a new system would (the same steps, to the bit).
    void reinit(const Eigen::VectorXd& x, double t = 0.0);

    [[nodiscard]] const model& system_model() const { return m_model; }
    [[nodiscard]] const std::vector<double>& parameters() const { return m_model.parameters(); }
    // Parameter i to v (range-checked): the integration starts again at the current state.
    void set_parameter(int i, double v);
    [[nodiscard]] const hybrid_system_options& options() const { return m_options; }

private:
    model m_model;
    hybrid_system_options m_options;
    std::unique_ptr<detail::flow_system> m_impl;
};

}  // namespace vimpact
