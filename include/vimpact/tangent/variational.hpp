#pragma once
// The tangent dynamics as an engine model of its own, so that the hybrid flow, its step
// control and its event location are reused unchanged: the state is X = (x, Y, q) with
//
//   x' = F(x),   Y' = DF(x) Y  (Y: N x N, column-major),   q' = div F(x) = trace DF(x)
//
// integrated together (same steps, one dense output for all). The gaps and sections read x
// only, so the impacts are those of the reference orbit; at an impact on surface i the reset
// maps x by R_i and the columns of Y by the chosen jump (saltation matrix, or the
// second-order mapping applied to each column as a finite deviation); q is continuous. q
// accumulates the integral of the divergence, the independent check of det Y (Liouville) and
// of the sum of the Lyapunov exponents.
//
// Error control covers all of X, not only x: the adaptive step must resolve the tangent as
// well as the state, or the monodromy is less accurate than the orbit (a trivial multiplier
// to 1e-9 needs the STM more than the orbit). The columns of Y are kept of order 1 so that
// rtol controls them relatively.
//
// Contact phases: the tangent map into and out of a contact phase (a finite-time accumulation
// of impacts) is not implemented. During contact Y and q are frozen; the analyses detect every
// contact phase (run_stats::sticking_phases) and report the outcome `sticking` instead of
// numbers.
#include <cmath>
#include <limits>
#include <type_traits>

#include <Eigen/Core>

#include "vimpact/core/state.hpp"
#include "vimpact/integrate/adaptive_integrator.hpp"
#include "vimpact/model/engine_model.hpp"
#include "vimpact/tangent/impact_jump.hpp"

namespace vimpact {

// The size of the integrated vector: the smallest d >= n with d = 4 (mod 8). Eigen unrolls the
// Runge-Kutta stage combinations completely for such sizes but not for the others (a
// synthetic DOP853 run with GCC 12 and AVX-512: 1.76 us per step with 21 components, 0.95 us
// with 28, 0.64 us with 20; one period of the paper's tangent flow: 400 -> 320 us). The
// padding stays zero; since the error norm is an RMS over all components, the tolerances are
// scaled by sqrt(raw / padded) (integration_options) so that the step control is exactly that
// of the unpadded system.
constexpr int padded_size(int n)
{
    int d = n;
    while (d % 8 != 4) ++d;
    return d;
}

// `Divergence`: also integrate q = integral of div F (the Liouville and sum-rule checks).
// A base model whose states are sized at run time (dim == Eigen::Dynamic) gives a tangent
// state sized at run time too, unpadded: n + n^2 (+ 1) components for a base of n.
template <engine_model Model, bool Divergence = true>
class variational_model {
public:
    using base_model = Model;
    static constexpr int base_dim = Model::dim;
    static constexpr bool has_divergence_integral = Divergence;
    static constexpr bool sized_at_run_time = base_dim == Eigen::Dynamic;
    // The unpadded size for a base of n, and the index of q in it.
    static constexpr int raw_size(int n) { return n + n * n + (Divergence ? 1 : 0); }
    static constexpr int divergence_index_of(int n) { return n + n * n; }
    static constexpr int dim = sized_at_run_time ? Eigen::Dynamic : padded_size(raw_size(base_dim));
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
    }

    [[nodiscard]] const Model& base() const { return m_model; }
    [[nodiscard]] int runtime_dim() const { return raw_size(state_dim(m_model)); }
    // The base dimension n of a tangent state X.
    static int base_size(const state& X)
    {
        if constexpr (!sized_at_run_time) return base_dim;
        else {
            const double m = static_cast<double>(X.size() - (Divergence ? 1 : 0));
            return static_cast<int>(std::lround((std::sqrt(4.0 * m + 1.0) - 1.0) / 2.0));
        }
    }
    [[nodiscard]] impact_tangent jump() const { return m_jump; }
    [[nodiscard]] double deviation_scale() const { return m_scale; }

    static state pack(const base_state& x, const tangent& Y, double q = 0.0)
    {
        const int n = static_cast<int>(x.size());
        state X = zero_state(n);
        head(X, n) = x;
        tangent_of(X.data() + n, n) = Y;
        if constexpr (Divergence) X[divergence_index_of(n)] = q;
        return X;
    }
    // The tolerances that make the padded RMS error norm equal the unpadded one.
    static integrator_options integration_options(integrator_options o)
    {
        if constexpr (!sized_at_run_time) {
            const double s = std::sqrt(static_cast<double>(raw_size(base_dim)) / static_cast<double>(dim));
            o.rtol *= s;
            o.atol *= s;
        }
        return o;
    }

    static base_state point(const state& X) { return head(X, base_size(X)); }
    static tangent matrix(const state& X)
    {
        const int n = base_size(X);
        return tangent_of(X.data() + n, n);
    }
    // The same, read in place.
    static auto matrix_view(const state& X)
    {
        const int n = base_size(X);
        return tangent_of(X.data() + n, n);
    }
    static double divergence_integral(const state& X)
    {
        if constexpr (Divergence) return X[divergence_index_of(base_size(X))];
        else return std::numeric_limits<double>::quiet_NaN();
    }

    [[nodiscard]] int surface_count() const { return m_model.surface_count(); }
    [[nodiscard]] int section_count() const { return m_model.section_count(); }
    [[nodiscard]] crossing section_direction(int k) const { return m_model.section_direction(k); }
    [[nodiscard]] bool sticks(int i) const { return m_model.sticks(i); }

    [[nodiscard]] state rhs(const state& X) const
    {
        const int n = base_size(X);
        const base_state x = point(X);
        const tangent J = m_model.jacobian(x);
        state f = zero_state(n);
        head(f, n) = m_model.rhs(x);
        tangent_of(f.data() + n, n).noalias() = J * tangent_of(X.data() + n, n);
        if constexpr (Divergence) f[divergence_index_of(n)] = m_model.divergence(x);
        return f;
    }

    // The same into `f` where states are sized at run time, with the base state, its field and
    // Jacobian in this model's own vectors (a flow integrates its own copy of the model): the
    // same numbers as rhs(), and no allocation per stage. Every component of f is written.
    void rhs_into(const state& X, state& f) const
        requires(sized_at_run_time)
    {
        const int n = base_size(X);
        m_x = head(X, n);
        jacobian_into(m_model, m_x, m_jacobian);
        vimpact::rhs_into(m_model, m_x, m_field);
        f.resize(X.size());
        head(f, n) = m_field;
        tangent_of(f.data() + n, n).noalias() = m_jacobian * tangent_of(X.data() + n, n);
        if constexpr (Divergence) f[divergence_index_of(n)] = m_model.divergence(m_x);
    }

    // The flow needs the tangent model's derivatives only for events of the reference state:
    // their gradients are those of the base model, padded with zeros. No N^2 x N^2 matrix is
    // ever formed.
    [[nodiscard]] state gap_rate_gradient(int i, const state& X) const
    {
        return embed(vimpact::gap_rate_gradient(m_model, i, point(X)));
    }
    [[nodiscard]] double gap_derivative(int i, const state& X, const state& V) const
    {
        return vimpact::gap_derivative(m_model, i, base_of(X, m_x), base_of(V, m_field));
    }
    // The rate of gap i along the flow: the base field's part of the tangent field, without
    // the tangent field itself (an n x n product) that the generic form would compute.
    [[nodiscard]] double gap_rate(int i, const state& X) const { return vimpact::gap_rate(m_model, i, base_of(X, m_x)); }
    [[nodiscard]] double section_derivative(int k, const state& X, const state& V) const
    {
        return vimpact::section_derivative(m_model, k, base_of(X, m_x), base_of(V, m_field));
    }
    [[nodiscard]] state state_rate_gradient(int j, const state& X) const
    {
        return j < base_size(X) ? embed(vimpact::state_rate_gradient(m_model, j, point(X))) : zero_like(X);
    }
    [[nodiscard]] mat<dim> jacobian(const state& X) const;  // not defined: see above
    [[nodiscard]] state second_derivative(const state& X, const state&, const state&) const { return zero_like(X); }
    [[nodiscard]] double divergence(const state& X) const { return m_model.divergence(base_of(X, m_x)); }

    [[nodiscard]] double gap(int i, const state& X) const { return m_model.gap(i, base_of(X, m_x)); }
    [[nodiscard]] bool gap_affine(int i) const { return gap_is_affine(m_model, i); }
    [[nodiscard]] bool section_affine(int k) const { return section_is_affine(m_model, k); }
    [[nodiscard]] state gap_gradient(int i, const state& X) const { return embed(m_model.gap_gradient(i, point(X))); }
    // The same into `out` (the flow's hop resolution on every step that may hold an impact).
    void gap_gradient_into(int i, const state& X, state& out) const
    {
        const int n = base_size(X);
        vimpact::gap_gradient_into(m_model, i, base_of(X, m_x), m_field);
        out.setZero(X.size());
        head(out, n) = m_field;
    }
    [[nodiscard]] mat<dim> gap_hessian(int i, const state& X) const;  // not defined: see above

    [[nodiscard]] state reset(int i, const state& X) const
    {
        const int n = base_size(X);
        const base_state x = point(X);
        state out = zero_state(n);
        head(out, n) = m_model.reset(i, x);
        const tangent Y = matrix(X);
        tangent Yp(Y.rows(), Y.cols());
        if (m_jump == impact_tangent::second_order) {
            const auto d = prepare_impact(m_model, i, x);
            for (int j = 0; j < n; ++j)
                Yp.col(j) = second_order_map(m_model, d, base_state(m_scale * Y.col(j))).y_plus / m_scale;
        } else {
            Yp = impact_jump_matrix(m_model, i, x, m_jump) * Y;
        }
        tangent_of(out.data() + n, n) = Yp;
        if constexpr (Divergence) out[divergence_index_of(n)] = X[divergence_index_of(n)];
        return out;
    }
    [[nodiscard]] mat<dim> reset_jacobian(int, const state&) const;  // not defined: see above
    [[nodiscard]] state reset_second_derivative(int, const state& X, const state&, const state&) const
    {
        return zero_like(X);
    }

    // Switching surfaces: the base's, read on its point. Crossing one maps the columns of Y by
    // its saltation matrix S = R' + (F+ - R' F-) n^T / (n^T F-): n = grad h_k, F- and F+ the
    // base fields of the sides before and after, R the switch's reset where it applies (the
    // identity otherwise), so that S = I + (F+ - F-) n^T / (n^T F-) for a field that only
    // changes. The second-order mapping of impacts has no counterpart here: S is applied for
    // it too; reset_jacobian applies R' alone, identity nothing.
    [[nodiscard]] int switch_count() const
        requires switching_model<Model>
    {
        return m_model.switch_count();
    }
    [[nodiscard]] crossing switch_direction(int k) const
        requires switching_model<Model>
    {
        return m_model.switch_direction(k);
    }
    [[nodiscard]] bool switching_affine(int k) const
        requires switching_model<Model>
    {
        return m_model.switching_affine(k);
    }
    [[nodiscard]] double switching(int k, const state& X) const
        requires switching_model<Model>
    {
        return m_model.switching(k, point(X));
    }
    [[nodiscard]] state switching_gradient(int k, const state& X) const
        requires switching_model<Model>
    {
        return embed(m_model.switching_gradient(k, point(X)));
    }
    [[nodiscard]] double switching_derivative(int k, const state& X, const state& V) const
        requires switching_model<Model>
    {
        return m_model.switching_derivative(k, point(X), point(V));
    }
    [[nodiscard]] switch_sides sides_at(const state& X) const
        requires switching_model<Model>
    {
        return m_model.sides_at(point(X));
    }
    void pin_sides(const switch_sides& s)
        requires switching_model<Model>
    {
        m_model.pin_sides(s);
    }
    [[nodiscard]] mat<dim> switch_reset_jacobian(int, const state&) const
        requires switching_model<Model>;  // not defined: the flow crosses with cross()
    bool cross(int k, const state& X, state& out)
        requires switching_model<Model>
    {
        const int n = base_size(X);
        const base_state x = point(X);
        const base_state normal = m_model.switching_gradient(k, x);
        const base_state f_before = m_model.rhs(x);
        base_state x_after = x;
        const bool applied = m_model.cross(k, x, x_after);
        const tangent Rp = applied ? tangent(m_model.switch_reset_jacobian(k, x)) : tangent(tangent::Identity(n, n));
        const tangent Y = matrix(X);
        tangent Yp = Y;
        if (m_jump == impact_tangent::reset_jacobian) {
            Yp = Rp * Y;
        } else if (m_jump != impact_tangent::identity) {
            Yp = saltation<base_dim>(Rp, f_before, m_model.rhs(x_after), normal) * Y;
        }
        out = pack(x_after, Yp, divergence_integral(X));
        return applied;
    }

    [[nodiscard]] double section(int k, const state& X) const { return m_model.section(k, base_of(X, m_x)); }
    [[nodiscard]] state section_gradient(int k, const state& X) const
    {
        return embed(m_model.section_gradient(k, point(X)));
    }

    [[nodiscard]] state sticking_rhs(int i, const state& X) const
    {
        state f = zero_like(X);
        head(f, base_size(X)) = m_model.sticking_rhs(i, point(X));
        return f;
    }
    [[nodiscard]] double release(int i, const state& X) const { return m_model.release(i, point(X)); }
    [[nodiscard]] state release_gradient(int i, const state& X) const
    {
        return embed(m_model.release_gradient(i, point(X)));
    }
    [[nodiscard]] state rest(int i, const state& X) const
    {
        state out = X;
        head(out, base_size(X)) = m_model.rest(i, point(X));
        return out;
    }
    [[nodiscard]] state state_difference(const state& b, const state& a) const
    {
        state d = b - a;
        head(d, base_size(b)) = m_model.state_difference(point(b), point(a));
        return d;
    }

private:
    static state embed(const base_state& g)
    {
        const int n = static_cast<int>(g.size());
        state e = zero_state(n);
        head(e, n) = g;
        return e;
    }
    // A zero tangent state for a base of n, of X's size; x, the first n components of X; the
    // tangent's n x n matrix at p. Fixed sizes at compile time where the base has them.
    static state zero_state(int n)
    {
        if constexpr (sized_at_run_time) return state::Zero(raw_size(n));
        else return state::Zero();
    }
    static state zero_like(const state& X) { return state::Zero(X.size()); }
    template <class V>
    static auto head(V& X, [[maybe_unused]] int n)
    {
        if constexpr (sized_at_run_time) return X.head(n);
        else return X.template head<base_dim>();
    }
    template <class T>
    static auto tangent_of(T* p, [[maybe_unused]] int n)
    {
        using M = std::conditional_t<std::is_const_v<T>, const tangent, tangent>;
        if constexpr (sized_at_run_time) return Eigen::Map<M>(p, n, n);
        else return Eigen::Map<M>(p);
    }

    Model m_model;
    impact_tangent m_jump;
    double m_scale;
    // The base state of X for the functions the flow calls on every step: where states are sized
    // at run time, in `scratch` (m_x, or m_field for a second one), not in a new vector.
    decltype(auto) base_of(const state& X, base_state& scratch) const
    {
        if constexpr (sized_at_run_time) {
            scratch = head(X, base_size(X));
            return static_cast<const base_state&>(scratch);
        } else {
            return point(X);
        }
    }

    // rhs_into's base state, field and Jacobian (states sized at run time only), and base_of's.
    mutable base_state m_x, m_field;
    mutable tangent m_jacobian;
};

}  // namespace vimpact
