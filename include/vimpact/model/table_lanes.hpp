#pragma once
// table_lanes<N>: the SIMD lanes of a compiled model (model/abi.h's lanes entries, which a model
// file's binary has) as a lanes definition for hybrid/flow_lanes.hpp's run_in_lanes_of. Its
// trial steps, gaps and sections run in the model's binary, one indirect call for all the lanes;
// its contexts are the lanes' contexts (each job's context doubles, a lanes value each). A
// model with switches reads each lane's sides from its context: the driver gives each lane the
// pinned context of its flow's model (hybrid/flow_lanes.hpp), updated after every crossing.
#include <array>
#include <span>
#include <type_traits>
#include <vector>

#include "vimpact/core/lanes.hpp"
#include "vimpact/core/state.hpp"
#include "vimpact/integrate/fused_step.hpp"
#include "vimpact/integrate/runge_kutta.hpp"
#include "vimpact/model/abi.h"

namespace vimpact {

template <int N>
class table_lanes {
public:
    using lvec = vec_t<lanes, N>;
    static_assert(N >= 1, "lanes need a fixed dimension");
    static_assert(sizeof(lvec) == N * sizeof(lanes), "lanes vectors must be contiguous lanes values");

    // Whether the jobs of table t run in lanes here: it has them, for this dimension and width,
    // with the fused steps a job alone takes (the same stage code; a step's interpolant after
    // lanes is the table's dense).
    static bool available(const vimpact_model_table& t)
    {
        return t.dim == N && (t.switch_count == 0 || t.lanes_switching) && t.lanes_width == lane_width &&
               t.context_size > 0 && t.step && t.dense && t.lanes_step &&
               t.lanes_gap && t.lanes_gap_gradient && t.lanes_section && t.lanes_section_gradient && t.lanes_points;
    }

    table_lanes(const vimpact_model_table& t, std::span<const lanes> contexts)
        : m_t(&t), m_c(contexts.begin(), contexts.end())
    {
        const auto n = static_cast<std::size_t>(t.surface_count + t.section_count + t.switch_count);
        for (auto& p : m_points) {
            p.values.resize(n);
            p.gradients.resize(n);
        }
    }

    // Every gap, section and switch (side * h_k) at x with its gradient, in one call
    // (hybrid/flow_lanes.hpp's lanes_point_at), kept in slot 0 or 1 until the next call for
    // that slot.
    struct point_values {
        const lanes* values;
        const lvec* gradients;
        int surfaces, sections;
        [[nodiscard]] lanes gap(int i) const { return values[i]; }
        [[nodiscard]] const lvec& gap_gradient(int i) const { return gradients[i]; }
        [[nodiscard]] lanes section(int k) const { return values[surfaces + k]; }
        [[nodiscard]] const lvec& section_gradient(int k) const { return gradients[surfaces + k]; }
        [[nodiscard]] lanes switching(int k) const { return values[surfaces + sections + k]; }
        [[nodiscard]] const lvec& switching_gradient(int k) const { return gradients[surfaces + sections + k]; }
    };
    [[nodiscard]] point_values point(const lvec& x, int slot) const
    {
        auto& p = m_points[static_cast<std::size_t>(slot)];
        m_t->lanes_points(contexts(), in(x), reinterpret_cast<double*>(p.values.data()),
                          reinterpret_cast<double*>(p.gradients.data()));
        return {p.values.data(), p.gradients.data(), m_t->surface_count, m_t->section_count};
    }

    // One trial step of every lane (hybrid/flow_lanes.hpp), the stages left in m's.
    template <class M>
    lanes attempt(M& m, const lvec& x, const lvec& f, const lanes& h, double rtol, double atol, lvec& x_new,
                  lvec& f_new) const
    {
        constexpr auto method = std::is_same_v<M, dopri5<N, lanes>> ? fused_method::dopri5 : fused_method::dop853;
        static_assert(std::is_same_v<M, dopri5<N, lanes>> || std::is_same_v<M, dop853<N, lanes>>);
        lanes err2;
        // The method is its stages alone (integrate/fused_lanes.hpp): the step fills them in place.
        static_assert(sizeof(M) == M::stage_count * sizeof(lvec));
        m_t->lanes_step(contexts(), static_cast<int>(method), in(x), in(f), in(h), rtol, atol, out(x_new), out(f_new),
                        reinterpret_cast<double*>(&m), out(err2));
        return err2;
    }

    [[nodiscard]] lanes gap(int i, const lvec& x) const
    {
        lanes g;
        m_t->lanes_gap(contexts(), i, in(x), out(g));
        return g;
    }
    [[nodiscard]] lvec gap_gradient(int i, const lvec& x) const
    {
        lvec g;
        m_t->lanes_gap_gradient(contexts(), i, in(x), out(g));
        return g;
    }
    [[nodiscard]] lanes section(int k, const lvec& x) const
    {
        lanes s;
        m_t->lanes_section(contexts(), k, in(x), out(s));
        return s;
    }
    [[nodiscard]] lvec section_gradient(int k, const lvec& x) const
    {
        lvec s;
        m_t->lanes_section_gradient(contexts(), k, in(x), out(s));
        return s;
    }
    // side * h_k in every lane, the sides its context holds.
    [[nodiscard]] lanes switching(int k, const lvec& x) const
    {
        lanes s;
        m_t->lanes_switching(contexts(), k, in(x), out(s));
        return s;
    }
    [[nodiscard]] int switch_count() const { return m_t->switch_count; }
    // Lane `lane`'s context becomes c (context_size doubles): its flow's, pinned anew after a
    // crossing (hybrid/flow_lanes.hpp), without making the definition again.
    void set_lane_context(int lane, const double* c)
    {
        alignas(64) double v[lane_width];
        for (std::size_t k = 0; k < m_c.size(); ++k) {
            m_c[k].store(v);
            v[lane] = c[k];
            m_c[k] = lanes::load(v);
        }
    }
    [[nodiscard]] bool switching_affine(int k) const { return m_t->switch_affine && m_t->switch_affine[k] != 0; }
    [[nodiscard]] bool gap_affine(int i) const { return m_t->surface_affine && m_t->surface_affine[i] != 0; }
    [[nodiscard]] bool section_affine(int k) const { return m_t->section_affine && m_t->section_affine[k] != 0; }

private:
    // The lanes values cross to the model's binary as doubles (abi.h), which reads them back
    // as the same lanes objects (integrate/fused_lanes.hpp).
    [[nodiscard]] const double* contexts() const { return reinterpret_cast<const double*>(m_c.data()); }
    static const double* in(const lanes& v) { return reinterpret_cast<const double*>(&v); }
    static const double* in(const lvec& v) { return reinterpret_cast<const double*>(v.data()); }
    static double* out(lanes& v) { return reinterpret_cast<double*>(&v); }
    static double* out(lvec& v) { return reinterpret_cast<double*>(v.data()); }

    struct point_buffer {
        std::vector<lanes> values;
        std::vector<lvec> gradients;
    };
    const vimpact_model_table* m_t;
    std::vector<lanes> m_c;
    mutable std::array<point_buffer, 2> m_points;  // point()'s slots
};

}  // namespace vimpact
