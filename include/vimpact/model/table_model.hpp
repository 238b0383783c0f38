#pragma once
// table_model<N>: an engine model (model/engine_model.hpp) that calls a compiled model's
// function table (model/abi.h) with a context made from its parameter values. The
// library instantiates every analysis for it once per dimension N of VIMPACT_MODEL_DIMS
// (fixed-size states, the fast path) and once for N = Eigen::Dynamic (states sized at run time
// from the table's dim: a model of any other dimension), so a model file or plugin runs with
// no interpreter in the loop: each call is one indirect call into native code.
#include <cassert>
#include <cmath>

#include <algorithm>
#include <array>
#include <memory>
#include <type_traits>
#include <vector>

#include "vimpact/core/state.hpp"
#include "vimpact/core/switch_sides.hpp"
#include "vimpact/hybrid/stepper.hpp"
#include "vimpact/integrate/fused_step.hpp"
#include "vimpact/model/abi.h"
#include "vimpact/model/model_limits.hpp"
#include "vimpact/model/spec.hpp"

namespace vimpact {

template <int N>
class table_model {
public:
    static constexpr int dim = N;
    using state = vec<N>;
    using matrix = mat<N>;

    table_model(const vimpact_model_table& table, const void* context) : m_t(&table), m_c(context)
    {
        assert(N == Eigen::Dynamic || table.dim == N);
        assert(table.dim <= max_model_dimension);
    }

    // The state dimension (state_dim in model/engine_model.hpp reads it where N is dynamic).
    [[nodiscard]] int runtime_dim() const { return m_t->dim; }

    [[nodiscard]] const vimpact_model_table& table() const { return *m_t; }
    [[nodiscard]] const void* context() const { return m_c; }
    [[nodiscard]] int surface_count() const { return m_t->surface_count; }
    [[nodiscard]] int section_count() const { return m_t->section_count; }
    [[nodiscard]] crossing section_direction(int k) const { return static_cast<crossing>(m_t->section_directions[k]); }
    [[nodiscard]] bool sticks(int i) const { return m_t->surface_sticks[i] != 0; }
    [[nodiscard]] bool gap_affine(int i) const { return m_t->surface_affine && m_t->surface_affine[i] != 0; }
    [[nodiscard]] bool section_affine(int k) const { return m_t->section_affine && m_t->section_affine[k] != 0; }

    [[nodiscard]] state rhs(const state& x) const
    {
        state f = new_state();
        rhs_into(x, f);
        return f;
    }
    [[nodiscard]] matrix jacobian(const state& x) const
    {
        matrix J = new_matrix();
        jacobian_into(x, J);
        return J;
    }
    [[nodiscard]] state second_derivative(const state& x, const state& u, const state& w) const
    {
        state out = new_state();
        m_t->second_derivative(m_c, x.data(), u.data(), w.data(), out.data());
        return out;
    }
    [[nodiscard]] double divergence(const state& x) const { return m_t->divergence(m_c, x.data()); }

    [[nodiscard]] double gap(int i, const state& x) const { return m_t->gap(m_c, i, x.data()); }
    [[nodiscard]] state gap_gradient(int i, const state& x) const
    {
        state out = new_state();
        gap_gradient_into(i, x, out);
        return out;
    }
    [[nodiscard]] matrix gap_hessian(int i, const state& x) const
    {
        matrix out = new_matrix();
        m_t->gap_hessian(m_c, i, x.data(), out.data());
        return out;
    }
    [[nodiscard]] state reset(int i, const state& x) const
    {
        state out = new_state();
        reset_into(i, x, out);
        return out;
    }
    [[nodiscard]] matrix reset_jacobian(int i, const state& x) const
    {
        matrix out = new_matrix();
        m_t->reset_jacobian(m_c, i, x.data(), out.data());
        return out;
    }
    [[nodiscard]] state reset_second_derivative(int i, const state& x, const state& u, const state& w) const
    {
        state out = new_state();
        m_t->reset_second_derivative(m_c, i, x.data(), u.data(), w.data(), out.data());
        return out;
    }

    // Where states are sized at run time, a gap's or section's derivative along v with its
    // gradient on the stack: event location asks for it on every step, and a returned
    // gradient would be a heap allocation each time.
    [[nodiscard]] double gap_derivative(int i, const state& x, const state& v) const
        requires(N == Eigen::Dynamic)
    {
        return along(m_t->gap_gradient, i, x, v);
    }
    [[nodiscard]] double section_derivative(int k, const state& x, const state& v) const
        requires(N == Eigen::Dynamic)
    {
        return along(m_t->section_gradient, k, x, v);
    }
    [[nodiscard]] double gap_rate(int i, const state& x) const
        requires(N == Eigen::Dynamic)
    {
        alignas(64) std::array<double, max_model_dimension> f;
        m_t->rhs(m_c, x.data(), f.data());
        return along(m_t->gap_gradient, i, x, Eigen::Map<const state, Eigen::Aligned64>(f.data(), x.size()));
    }
    void rhs_into(const state& x, state& out) const
    {
        out.resize(x.size());
        m_t->rhs(m_c, x.data(), out.data());
    }
    void jacobian_into(const state& x, matrix& out) const
    {
        out.resize(x.size(), x.size());
        m_t->jacobian(m_c, x.data(), out.data());
    }
    void gap_gradient_into(int i, const state& x, state& out) const
    {
        out.resize(x.size());
        m_t->gap_gradient(m_c, i, x.data(), out.data());
    }
    void section_gradient_into(int k, const state& x, state& out) const
    {
        out.resize(x.size());
        m_t->section_gradient(m_c, k, x.data(), out.data());
    }
    void reset_into(int i, const state& x, state& out) const
    {
        out.resize(x.size());
        m_t->reset(m_c, i, x.data(), out.data());
    }

    [[nodiscard]] double section(int k, const state& x) const { return m_t->section(m_c, k, x.data()); }
    [[nodiscard]] state section_gradient(int k, const state& x) const
    {
        state out = new_state();
        section_gradient_into(k, x, out);
        return out;
    }

    [[nodiscard]] state sticking_rhs(int i, const state& x) const
    {
        state out = new_state();
        m_t->sticking_rhs(m_c, i, x.data(), out.data());
        return out;
    }
    [[nodiscard]] double release(int i, const state& x) const { return m_t->release(m_c, i, x.data()); }
    [[nodiscard]] state release_gradient(int i, const state& x) const
    {
        state out = new_state();
        m_t->release_gradient(m_c, i, x.data(), out.data());
        return out;
    }
    [[nodiscard]] state rest(int i, const state& x) const
    {
        state out = new_state();
        m_t->rest(m_c, i, x.data(), out.data());
        return out;
    }

    // Every gap's and section's (value, rate) at x in one call, when the table has it
    // (hybrid/flow.hpp samples each step end with it); false otherwise.
    bool samples(const state& x, const state& f, double* gaps, double* sections) const
    {
        if (!m_t->samples) return false;
        m_t->samples(m_c, x.data(), f.data(), gaps, sections);
        return true;
    }

    // Switching surfaces (model/abi.h, ABI version 6; engine_model.hpp's switching_model). The
    // first pin_sides gives this copy a context of its own (the table's copy_context), which
    // copies of it copy again: the flow that pins holds its sides alone, whatever other flows
    // of the same model do in other threads.
    [[nodiscard]] int switch_count() const { return m_t->switch_count; }
    [[nodiscard]] crossing switch_direction(int k) const { return static_cast<crossing>(m_t->switch_directions[k]); }
    [[nodiscard]] bool switching_affine(int k) const { return m_t->switch_affine && m_t->switch_affine[k] != 0; }
    [[nodiscard]] double switching(int k, const state& x) const { return m_t->switching(m_c, k, x.data()); }
    [[nodiscard]] state switching_gradient(int k, const state& x) const
    {
        state out = new_state();
        m_t->switching_gradient(m_c, k, x.data(), out.data());
        return out;
    }
    [[nodiscard]] double switching_derivative(int k, const state& x, const state& v) const
    {
        return along(m_t->switching_gradient, k, x, v);
    }
    [[nodiscard]] switch_sides sides_at(const state& x) const
    {
        if (m_t->switch_count == 0) return {};
        return switch_sides::from_bits(m_t->sides_at(m_c, x.data()));
    }
    void pin_sides(const switch_sides& s)
    {
        if (m_t->switch_count == 0) return;
        own_context();
        m_t->pin_sides(m_own.get(), s.negative_bits());
    }
    bool cross(int k, const state& x, state& out)
    {
        own_context();
        out.resize(x.size());
        return m_t->cross(m_own.get(), k, x.data(), out.data()) != 0;
    }
    [[nodiscard]] matrix switch_reset_jacobian(int k, const state& x) const
    {
        matrix out = new_matrix();
        m_t->switch_reset_jacobian(m_c, k, x.data(), out.data());
        return out;
    }

    table_model(const table_model& o) : m_t(o.m_t), m_c(o.m_c) { copy_own(o); }
    table_model& operator=(const table_model& o)
    {
        if (this != &o) {
            m_t = o.m_t;
            m_c = o.m_c;
            m_own.reset();
            copy_own(o);
        }
        return *this;
    }
    table_model(table_model&&) noexcept = default;
    table_model& operator=(table_model&&) noexcept = default;
    ~table_model() = default;

    // b - a, with every phase variable's difference taken into (-period/2, period/2].
    [[nodiscard]] state state_difference(const state& b, const state& a) const
    {
        state d = b - a;
        for (int j = 0; j < d.size(); ++j) {
            const double p = m_t->state_periods[j];
            if (p > 0.0) d[j] -= p * std::round(d[j] / p);
        }
        return d;
    }

private:
    // gradient . v, the gradient written by the table on the stack: the same dot product on the
    // same aligned layout as a returned gradient's, so the same bits.
    using gradient_function = void (*)(const void*, int, const double*, double*);
    template <class V>
    double along(gradient_function gradient, int i, const state& x, const V& v) const
    {
        alignas(64) std::array<double, max_model_dimension> g;
        gradient(m_c, i, x.data(), g.data());
        return Eigen::Map<const state, Eigen::Aligned64>(g.data(), x.size()).dot(v);
    }

    // Outputs the table writes into: sized at run time where N is dynamic.
    [[nodiscard]] state new_state() const { return sized<state>(m_t->dim); }
    [[nodiscard]] matrix new_matrix() const
    {
        if constexpr (N == Eigen::Dynamic) return matrix(m_t->dim, m_t->dim);
        else return matrix();
    }

    void own_context()
    {
        if (m_own) return;
        m_own = std::shared_ptr<void>(m_t->copy_context(m_c), m_t->destroy);
        m_c = m_own.get();
    }
    void copy_own(const table_model& o)
    {
        if (!o.m_own) return;
        m_own = std::shared_ptr<void>(m_t->copy_context(o.m_own.get()), m_t->destroy);
        m_c = m_own.get();
    }

    const vimpact_model_table* m_t;
    const void* m_c;
    std::shared_ptr<void> m_own;  // this copy's own context, once it pins sides of switches
};

// The stepper of a table model's flows: the table's fused step for the free field when the
// table has one, the method's own stage loop otherwise (the contact fields, tables without
// fused steps).
template <int N, template <int> class Method>
class table_stepper : public Method<N> {
public:
    template <class F>
    double attempt(F&& rhs, const vec<N>& x, const vec<N>& f, double h, double rtol, double atol, vec<N>& x_new,
                   vec<N>& f_new)
    {
        if constexpr (std::is_same_v<std::decay_t<F>, free_field<table_model<N>>>) {
            const auto& t = rhs.model->table();
            if (t.step) {
                m_fused = true;
                if constexpr (N == Eigen::Dynamic) {
                    x_new.resize(x.size());
                    f_new.resize(x.size());
                    m_stages.resize(static_cast<std::size_t>(dop853<N>::stage_count * x.size()));
                }
                return t.step(rhs.model->context(), method_id(), x.data(), f.data(), h, rtol, atol, x_new.data(),
                              f_new.data(), stage_memory());
            }
        }
        m_fused = false;
        return Method<N>::attempt(rhs, x, f, h, rtol, atol, x_new, f_new);
    }

    template <class F>
    void build_dense(F&& rhs, double t0, double h, const vec<N>& x0, const vec<N>& x1,
                     typename Method<N>::dense_type& out)
    {
        if constexpr (std::is_same_v<std::decay_t<F>, free_field<table_model<N>>>) {
            if (m_fused) {
                out.t0 = t0;
                out.h = h;
                out.x0 = x0;
                if constexpr (N == Eigen::Dynamic) {
                    // The coefficients are separate vectors here: written to one buffer, then copied.
                    const Eigen::Index n = x0.size();
                    m_coefficients.resize(out.c.size() * static_cast<std::size_t>(n));
                    rhs.model->table().dense(rhs.model->context(), method_id(), t0, h, x0.data(), x1.data(),
                                             stage_memory(), m_coefficients.data());
                    for (std::size_t j = 0; j < out.c.size(); ++j)
                        out.c[j] = Eigen::Map<const vec<N>>(m_coefficients.data() + j * static_cast<std::size_t>(n), n);
                } else {
                    rhs.model->table().dense(rhs.model->context(), method_id(), t0, h, x0.data(), x1.data(),
                                             stage_memory(), out.c[0].data());
                }
                return;
            }
        }
        Method<N>::build_dense(rhs, t0, h, x0, x1, out);
    }

    // The stages of the last step were set from outside, in the method's stages (the step was
    // tried in SIMD lanes, hybrid/flow_lanes.hpp): its interpolant is then built as after a
    // fused step, by the table's dense (the same arithmetic with the field inlined: a table
    // with lanes has fused steps, model/abi.h).
    void stages_set_outside() { m_fused = N != Eigen::Dynamic; }

private:
    static constexpr int method_id()
    {
        return static_cast<int>(std::is_same_v<Method<N>, dopri5<N>> ? fused_method::dopri5 : fused_method::dop853);
    }
    static_assert(N == Eigen::Dynamic || sizeof(vec<N>) == N * sizeof(double),
                  "interpolant coefficients must be contiguous doubles");
    // Where a fused step keeps its stages for its interpolant: the model's binary tries the
    // step in place on them as its own method object (integrate/fused_step.hpp). For a fixed N
    // that is this method itself, whose stages are then also those a step in SIMD lanes
    // leaves (stages_set_outside); for a dynamic N, whose stages are separate vectors here, a
    // buffer laid out as the model's fixed-size method, aligned as Eigen aligns it.
    double* stage_memory()
    {
        if constexpr (N == Eigen::Dynamic) return m_stages.data();
        else return reinterpret_cast<double*>(static_cast<Method<N>*>(this));
    }
    std::vector<double, Eigen::aligned_allocator<double>> m_stages;  // dynamic N only
    std::vector<double> m_coefficients;  // dynamic N: the interpolant on its way to the segment's vectors
    bool m_fused = false;
};

template <int N, template <int> class Method>
struct flow_stepper<table_model<N>, Method> {
    using type = table_stepper<N, Method>;
};

}  // namespace vimpact
