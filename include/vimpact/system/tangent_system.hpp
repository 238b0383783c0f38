#pragma once
// A model's flow or section map together with its linearisation, as an object to step: the
// state and k deviation vectors (the columns of an N x k matrix W) carried by the tangent
// flow, mapped at each impact by the saltation matrix (tangent/variational.hpp,
// tangent/impact_jump.hpp). In continuous time W(t) = Phi(t, t_s) W_s, Phi the fundamental
// matrix since the deviations were last set (t_s); in discrete time (a model section) the
// deviations at each crossing are projected along the flow onto the section,
// W_k = (I - F grad s^T / (grad s . F)) Phi W_s: with W_s the identity, the Jacobian of the
// section map (k returns) in state coordinates. Lyapunov exponents are then a QR
// decomposition of W every so often and set_deviations(Q): a few lines (docs/python.md).
//
// As in the library's tangent analyses the tangent flow integrates with DOP853, with error
// control over the deviations too (keep their columns of order 1), and the tangent map of a
// contact phase is not implemented: a contact phase ends the system with outcome sticking.
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "vimpact/core/outcome.hpp"
#include "vimpact/core/state_series.hpp"
#include "vimpact/hybrid/flow_options.hpp"
#include "vimpact/hybrid/run_stats.hpp"
#include "vimpact/model/model.hpp"

namespace vimpact {

struct tangent_system_options {
    flow_options flow{};  // as hybrid_system_options::flow (`events` must be empty)
    // >= 0: discrete time, the map of this model section; -1: continuous time.
    int section = -1;
    // The number k of deviation vectors, 1..dim; 0: dim (the full matrix).
    int deviations = 0;
    double max_return_time = 1e4;  // as section_system_options::max_return_time
};

namespace detail {
class tangent_engine;
}

class tangent_system {
public:
    // At (t0, x0) with the deviations the first k columns of the identity. Throws input_error
    // as hybrid_system does, and for a section the model does not have or k out of range.
    tangent_system(model m, const Eigen::VectorXd& x0, double t0 = 0.0, tangent_system_options o = {});
    tangent_system(const tangent_system& other);
    tangent_system& operator=(const tangent_system& other);
    tangent_system(tangent_system&&) noexcept;
    tangent_system& operator=(tangent_system&&) noexcept;
    ~tangent_system();

    [[nodiscard]] const Eigen::VectorXd& state() const;
    [[nodiscard]] double time() const;
    [[nodiscard]] const Eigen::MatrixXd& deviations() const;  // N x k
    [[nodiscard]] outcome status() const;
    [[nodiscard]] run_stats stats() const;
    [[nodiscard]] bool discrete() const { return m_options.section >= 0; }

    // Continuous time: one accepted step; discrete: to the next crossing.
    outcome step();
    outcome step(long n);
    // Continuous time only: to time t exactly (t >= time()).
    outcome advance_to(double t);
    // New deviations (N x k, finite) at the current point; the tangent flow starts again there.
    void set_deviations(const Eigen::MatrixXd& w);
    // Starts again at (t, x) with the identity's first k columns, or with w.
    void reinit(const Eigen::VectorXd& x, double t = 0.0);
    void reinit(const Eigen::VectorXd& x, double t, const Eigen::MatrixXd& w);

    [[nodiscard]] const model& system_model() const { return m_model; }
    [[nodiscard]] const std::vector<double>& parameters() const { return m_model.parameters(); }
    // Parameter i to v (range-checked); the tangent flow starts again at the current point
    // with the current deviations.
    void set_parameter(int i, double v);
    [[nodiscard]] const tangent_system_options& options() const { return m_options; }

private:
    model m_model;
    tangent_system_options m_options;
    std::unique_ptr<detail::tangent_engine> m_impl;
};

}  // namespace vimpact
