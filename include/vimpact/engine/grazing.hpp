#pragma once
// The grazing run (analysis/grazing.hpp) on an engine model.
#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

#include "vimpact/analysis/grazing.hpp"
#include "vimpact/hybrid/flow.hpp"

namespace vimpact::engine {

template <int N>
struct grazing_observer : flow_observer {
    const grazing_options& opt;
    grazing_result& res;
    struct block_state {
        double min = std::numeric_limits<double>::infinity();
        double t = 0.0;
        vec<N> x;  // zero until a minimum is seen (run_grazing)
        double previous = std::numeric_limits<double>::quiet_NaN();
        int count = 0;
    };
    std::vector<block_state> blocks;
    // response variable: extrema of the current block and the times of its minima
    double r_max = -std::numeric_limits<double>::infinity();
    double r_min = std::numeric_limits<double>::infinity();
    double r_first_t = 0.0;
    int r_minima = 0;

    // Blocks of the surfaces' gaps, then of the switches' distances side * h_k.
    grazing_observer(const grazing_options& o, grazing_result& r)
        : opt(o), res(r), blocks(r.surfaces.size() + r.switches.size())
    {
    }
    surface_grazing& target(int i)
    {
        const auto S = res.surfaces.size(), k = static_cast<std::size_t>(i);
        return k < S ? res.surfaces[k] : res.switches[k - S];
    }
    [[nodiscard]] bool all_converged() const
    {
        const auto done = [](const surface_grazing& q) { return q.converged; };
        return std::all_of(res.surfaces.begin(), res.surfaces.end(), done) &&
               std::all_of(res.switches.begin(), res.switches.end(), done);
    }

    // Events: the response variable's extrema first (so that at a common time its minimum is
    // counted before a gap's minimum may end the run), then each gap's minima.
    flow_control on_section(int event, crossing dir, double t, const vec<N>& x)
    {
        if (t < opt.transient_time) return flow_control::proceed;
        if (opt.response_variable < 0) return on_minimum(event, t, x);
        if (event > 0) return on_minimum(event - 1, t, x);
        const double v = x[opt.response_variable];
        r_max = std::max(r_max, v);
        r_min = std::min(r_min, v);
        if (dir == crossing::up) {
            if (r_minima == 0) r_first_t = t;
            if (++r_minima == opt.block) close_response_block(t);
        }
        return flow_control::proceed;
    }

    flow_control on_minimum(int i, double t, const vec<N>& x)
    {
        auto& s = target(i);
        auto& b = blocks[static_cast<std::size_t>(i)];
        ++s.minima;
        const double g = gap_value(i, x);
        if (g < b.min) {
            b.min = g;
            b.t = t;
            b.x = x;
        }
        if (++b.count < opt.block) return flow_control::proceed;
        s.change = std::abs(b.min - b.previous);
        s.margin = b.min;
        s.t = b.t;
        s.x = to_dynamic(b.x);
        b.previous = b.min;
        b.min = std::numeric_limits<double>::infinity();
        b.count = 0;
        if (s.change <= opt.tolerance) s.converged = true;
        return all_converged() ? flow_control::stop : flow_control::proceed;
    }

    void close_response_block(double t)
    {
        res.response_max = r_max;
        res.response_min = r_min;
        res.response_omega = r_minima > 1 ? 2.0 * std::numbers::pi * (r_minima - 1) / (t - r_first_t)
                                          : std::numeric_limits<double>::quiet_NaN();
        r_max = -std::numeric_limits<double>::infinity();
        r_min = std::numeric_limits<double>::infinity();
        r_minima = 0;
    }

    std::function<double(int, const vec<N>&)> gap_value;
};

template <template <int> class Method, engine_model Model>
grazing_result run_grazing(const Model& model, const vec<Model::dim>& x0, const grazing_options& opt)
{
    constexpr int N = Model::dim;
    flow_options fo;
    fo.integration = opt.integration;
    fo.surfaces = false;
    fo.switches = false;
    fo.t_max = opt.t_max;
    fo.cancel = opt.cancel;
    const int S = model.surface_count(), W = switch_count(model);
    if (opt.response_variable >= 0) fo.events.push_back(flow_event::state_extrema(opt.response_variable, crossing::both));
    for (int i = 0; i < S; ++i) fo.events.push_back(flow_event::gap_extrema(i, crossing::up));
    for (int k = 0; k < W; ++k) fo.events.push_back(flow_event::switch_extrema(k, crossing::up));
    grazing_result res;
    res.surfaces.resize(static_cast<std::size_t>(S));
    res.switches.resize(static_cast<std::size_t>(W));
    hybrid_flow<Model, Method> flow(model, fo);
    flow.start(0.0, x0);
    grazing_observer<N> obs(opt, res);
    for (auto& b : obs.blocks) b.x = vec<N>::Zero(x0.size());
    // A switch's distance on the side the flow holds (its model's sides, pinned at the start).
    obs.gap_value = [&flow, S](int i, const vec<N>& x) {
        const auto& m = flow.model();
        if (i < S) return m.gap(i, x);
        if constexpr (switching_model<Model>) return m.sides_at(x).side(i - S) * m.switching(i - S, x);
        return 0.0;
    };
    res.status = flow.run(obs);
    res.stats = flow.stats();
    res.converged = obs.all_converged();
    return res;
}

}  // namespace vimpact::engine
