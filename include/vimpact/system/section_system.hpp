#pragma once
// The section map of a model as an object to step, in discrete time: step() goes to the next
// crossing of a model section in its direction (the Poincare map), or to the next impact
// (the impact map: the state after it), through whatever impacts and contact phases lie
// between. Its state and time are the crossing's. The continuous flow underneath is
// hybrid_system's (system/hybrid_system.hpp); the engine stays behind the object.
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/outcome.hpp"
#include "vimpact/core/state_series.hpp"
#include "vimpact/hybrid/flow_options.hpp"
#include "vimpact/hybrid/run_stats.hpp"
#include "vimpact/model/model.hpp"

namespace vimpact {

struct section_system_options {
    // A model section (crossed in its direction) or impacts (on one surface or every one);
    // none: the model's first section, or its impacts when it declares none.
    std::optional<section_choice> section{};
    flow_options flow{};  // as hybrid_system_options::flow (`events` must be empty)
    integration_method method = integration_method::dop853;
    // A step that finds no crossing within this flight time ends with time_limit.
    double max_return_time = 1e4;
};

namespace detail {
class flow_system;
}

class section_system {
public:
    // From (t0, x0): the first step() gives the first crossing after it (a start on the
    // section itself is not its own crossing). Throws input_error as hybrid_system does, and
    // for a section or surface the model does not have.
    section_system(model m, const Eigen::VectorXd& x0, double t0 = 0.0, section_system_options o = {});
    section_system(const section_system& other);
    section_system& operator=(const section_system& other);
    section_system(section_system&&) noexcept;
    section_system& operator=(section_system&&) noexcept;
    ~section_system();

    [[nodiscard]] const Eigen::VectorXd& state() const;
    [[nodiscard]] double time() const;
    [[nodiscard]] outcome status() const;
    [[nodiscard]] run_stats stats() const;
    // The impacts since the previous point, up to this one (for the impact map: this one).
    [[nodiscard]] const impact_series& impacts() const;
    // The crossings of switching surfaces in the same span (`surface`: the switch).
    [[nodiscard]] const impact_series& switchings() const;
    [[nodiscard]] const section_choice& section() const { return m_section; }

    // To the next crossing: ok, or why there is none (then the state is the last crossing's).
    outcome step();
    // n steps (n >= 0), fewer when the system stops on the way.
    outcome step(long n);
    void reinit(const Eigen::VectorXd& x, double t = 0.0);

    [[nodiscard]] const model& system_model() const { return m_model; }
    [[nodiscard]] const std::vector<double>& parameters() const { return m_model.parameters(); }
    // Parameter i to v (range-checked); the map goes on from the current point.
    void set_parameter(int i, double v);
    [[nodiscard]] const section_system_options& options() const { return m_options; }

private:
    model m_model;
    section_system_options m_options;
    section_choice m_section;
    std::unique_ptr<detail::flow_system> m_impl;
};

}  // namespace vimpact
