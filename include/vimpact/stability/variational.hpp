#pragma once
// The tangent dynamics as a model of its own, so that the hybrid flow, its step control and
// its event location are reused unchanged: the state is X = (x, Y, q) with
//
//   x' = F(x),   Y' = DF(x) Y  (Y: N x N, column-major),   q' = div F(x) = trace DF(x)
//
// integrated together (same steps, one dense output for all). The guard reads x only, so the
// impacts are those of the reference orbit; at an impact the reset maps x by R and the
// columns of Y by the chosen jump (saltation matrix, or the second-order mapping applied to
// each column as a finite deviation); q is continuous. q accumulates the integral of the
// divergence, the independent check of det Y (Liouville) and of the sum of the Lyapunov
// exponents.
//
// Error control covers all of X, not only x: the adaptive step must resolve the tangent as
// well as the state, or the monodromy is less accurate than the orbit (a trivial multiplier
// to 1e-9 needs the STM more than the orbit). The columns of Y are kept of order 1 so that
// rtol controls them relatively. The price: the tangent is the harder part, and the steps
// are those it needs (one period at Ur = 16: 252 steps with the tangent, 204 without, at
// rtol = 1e-12; bench/stability_bench.cpp). Controlling x alone is not something the
// integrator offers; it would give the state-only steps and an unchecked STM.
//
// Sticking phases: the tangent map into and out of a sticking phase (a finite-time
// accumulation of impacts) is not implemented. During sticking Y and q are frozen; the
// analyses detect every sticking phase (run_stats::sticking_phases) and report the outcome
// `sticking` instead of numbers.
#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "vimpact/core/state.hpp"
#include "vimpact/integrate/adaptive_integrator.hpp"
#include "vimpact/model/concepts.hpp"
#include "vimpact/stability/discontinuity_map.hpp"

namespace vimpact {

template <class M>
concept tangent_model = sticking_model<M> && has_jacobian<M> && saltation_model<M>;

// The size of the integrated vector: the smallest d >= n with d = 4 (mod 8). Eigen unrolls the
// Runge-Kutta stage combinations completely for such sizes but not for the others (a
// synthetic DOP853 run with GCC 12 and AVX-512: 1.76 us per step with 21 components, 0.95 us
// with 28, 0.64 us with 20; one period of the paper's tangent flow: 400 -> 320 us), and
// multiples of 8 trip false -Wmaybe-uninitialized errors in GCC 12's AVX-512 headers. The padding stays zero; since the error norm is an RMS over all components, the
// tolerances are scaled by sqrt(raw / padded) (integration_options) so that the step control
// is exactly that of the unpadded system.
constexpr int padded_size(int n)
{
    int d = n;
    while (d % 8 != 4) ++d;
    return d;
}

// `Divergence`: also integrate q = integral of div F (the Liouville and sum-rule checks).
template <tangent_model Model, bool Divergence = true>
class variational_model {
public:
    using base_model = Model;
    static constexpr int base_dim = Model::dim;
    static constexpr bool has_divergence_integral = Divergence;
    static constexpr int divergence_index = base_dim + base_dim * base_dim;
    static constexpr int raw_dim = divergence_index + (Divergence ? 1 : 0);
    static constexpr int dim = padded_size(raw_dim);
    static constexpr int position = Model::position;
    static constexpr int velocity = Model::velocity;
    using state = vec<dim>;
    using base_state = vec<base_dim>;
    using tangent = mat<base_dim>;

    // `deviation_scale`: the second-order mapping is nonlinear, so it needs the real size of
    // the deviations; the columns of Y are kept of order 1 (so that the tolerances control
    // them relatively) and stand for deviations of size deviation_scale * Y.
    explicit variational_model(const Model& m, impact_tangent jump = impact_tangent::saltation,
                               double deviation_scale = 1.0)
        : m_model(m), m_jump(jump), m_scale(deviation_scale)
    {
        if constexpr (!second_order_model<Model>) {
            if (jump == impact_tangent::second_order) m_jump = impact_tangent::saltation;
        }
    }

    [[nodiscard]] const Model& base() const { return m_model; }
    [[nodiscard]] impact_tangent jump() const { return m_jump; }
    [[nodiscard]] double deviation_scale() const { return m_scale; }

    static state pack(const base_state& x, const tangent& Y, double q = 0.0)
    {
        state X = state::Zero();
        X.template head<base_dim>() = x;
        Eigen::Map<tangent>(X.data() + base_dim) = Y;
        if constexpr (Divergence) X[divergence_index] = q;
        return X;
    }
    // The tolerances that make the padded RMS error norm equal the unpadded one.
    static integrator_options integration_options(integrator_options o)
    {
        const double s = std::sqrt(static_cast<double>(raw_dim) / static_cast<double>(dim));
        o.rtol *= s;
        o.atol *= s;
        return o;
    }

    static base_state point(const state& X) { return X.template head<base_dim>(); }
    static tangent matrix(const state& X) { return Eigen::Map<const tangent>(X.data() + base_dim); }
    static double divergence_integral(const state& X)
    {
        if constexpr (Divergence) return X[divergence_index];
        else return std::numeric_limits<double>::quiet_NaN();
    }

    [[nodiscard]] state rhs(const state& X) const
    {
        const base_state x = point(X);
        const tangent J = m_model.jacobian(x);
        state f = state::Zero();
        f.template head<base_dim>() = m_model.rhs(x);
        Eigen::Map<tangent>(f.data() + base_dim).noalias() =
            J * Eigen::Map<const tangent>(X.data() + base_dim);
        if constexpr (Divergence) {
            if constexpr (has_divergence<Model>) f[divergence_index] = m_model.divergence(x);
            else f[divergence_index] = J.trace();
        }
        return f;
    }

    [[nodiscard]] double guard(const state& X) const { return m_model.guard(point(X)); }
    [[nodiscard]] state guard_gradient(const state& X) const
    {
        return embed(m_model.guard_gradient(point(X)));
    }

    [[nodiscard]] state reset(const state& X) const
    {
        const base_state x = point(X);
        state out = state::Zero();
        out.template head<base_dim>() = m_model.reset(x);
        const tangent Y = matrix(X);
        tangent Yp;
        if constexpr (second_order_model<Model>) {
            if (m_jump == impact_tangent::second_order) {
                const auto d = prepare_impact(m_model, x);
                for (int j = 0; j < base_dim; ++j)
                    Yp.col(j) = second_order_map(m_model, d, base_state(m_scale * Y.col(j))).y_plus / m_scale;
            } else {
                Yp = impact_jump_matrix(m_model, x, m_jump) * Y;
            }
        } else {
            Yp = impact_jump_matrix(m_model, x, m_jump) * Y;
        }
        Eigen::Map<tangent>(out.data() + base_dim) = Yp;
        if constexpr (Divergence) out[divergence_index] = X[divergence_index];
        return out;
    }

    [[nodiscard]] auto section_coordinates(const state& X) const
    {
        return m_model.section_coordinates(point(X));
    }

    [[nodiscard]] state sticking_rhs(const state& X) const
    {
        state f = state::Zero();
        f.template head<base_dim>() = m_model.sticking_rhs(point(X));
        return f;
    }
    [[nodiscard]] double free_acceleration(const state& X) const
    {
        return m_model.free_acceleration(point(X));
    }
    [[nodiscard]] state free_acceleration_gradient(const state& X) const
    {
        return embed(m_model.free_acceleration_gradient(point(X)));
    }
    [[nodiscard]] double restitution() const { return m_model.restitution(); }
    [[nodiscard]] double barrier() const { return m_model.barrier(); }

private:
    static state embed(const base_state& g)
    {
        state e = state::Zero();
        e.template head<base_dim>() = g;
        return e;
    }

    Model m_model;
    impact_tangent m_jump;
    double m_scale;
};

}  // namespace vimpact
