#pragma once
// Grazing value: the barrier position at which the attracting barrier-free orbit just
// touches the barrier, i.e. the minimum of y on that orbit. A barrier just above it is hit,
// just below it is not.
//
// The barrier-free flow is run past a transient; the minima of y (v = 0, v increasing) are
// located on the interpolant, and the minimum over consecutive blocks of minima is compared
// until two blocks agree within `tolerance`.
//
// The same run gives the barrier-free response (lock-in curves): the largest maximum of y in
// the last block, hence the amplitude max |y|, and the mean angular frequency of y from the
// times of the block's minima (2 pi (n - 1) / (t_n - t_1)). In the model's time unit the wake
// oscillator's own angular frequency is 1, so omega is also the ratio to the wake frequency.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "vimpact/hybrid/flow.hpp"

namespace vimpact {

struct grazing_options {
    integrator_options integration{.rtol = 1e-12, .atol = 1e-12};
    double transient_time = 1000.0;
    int block = 16;              // minima per block
    double tolerance = 1e-11;    // agreement of successive block minima
    double t_max = 1e5;
    const std::atomic<bool>* cancel = nullptr;  // see flow_options::cancel
};

template <int N>
struct grazing_result {
    outcome status = outcome::ok;
    bool converged = false;
    double sigma_graze = std::numeric_limits<double>::quiet_NaN();
    double change = std::numeric_limits<double>::quiet_NaN();  // last block-to-block change
    double t_graze = 0.0;        // time of the minimum
    vec<N> x_graze;              // state at the minimum
    double y_max = std::numeric_limits<double>::quiet_NaN();  // largest maximum, last block
    double omega = std::numeric_limits<double>::quiet_NaN();  // angular frequency of y, last block
    long minima = 0;
    run_stats stats;
};

namespace detail {
template <int N>
struct grazing_observer : flow_observer {
    const grazing_options& opt;
    grazing_result<N>& res;
    double block_min = std::numeric_limits<double>::infinity();
    double block_t = 0.0;
    vec<N> block_x;
    double prev_block_min = std::numeric_limits<double>::quiet_NaN();
    int in_block = 0;
    double block_max = -std::numeric_limits<double>::infinity();
    double block_first_t = 0.0;

    grazing_observer(const grazing_options& o, grazing_result<N>& r) : opt(o), res(r) {}

    flow_control on_section(section_kind k, double t, const vec<N>& x)
    {
        if (t < opt.transient_time) return flow_control::proceed;
        if (k == section_kind::maximum) {
            block_max = std::max(block_max, x[0]);
            return flow_control::proceed;
        }
        ++res.minima;
        if (in_block == 0) block_first_t = t;
        if (x[0] < block_min) {
            block_min = x[0];
            block_t = t;
            block_x = x;
        }
        if (++in_block < opt.block) return flow_control::proceed;
        res.change = std::abs(block_min - prev_block_min);
        res.sigma_graze = block_min;
        res.t_graze = block_t;
        res.x_graze = block_x;
        res.y_max = block_max;
        res.omega = opt.block > 1 ? 2.0 * std::numbers::pi * (opt.block - 1) / (t - block_first_t)
                                  : std::numeric_limits<double>::quiet_NaN();
        block_max = -std::numeric_limits<double>::infinity();
        prev_block_min = block_min;
        block_min = std::numeric_limits<double>::infinity();
        in_block = 0;
        if (res.change <= opt.tolerance) {
            res.converged = true;
            return flow_control::stop;
        }
        return flow_control::proceed;
    }
};
}  // namespace detail

template <template <int> class Method = dop853, sticking_model Model>
grazing_result<Model::dim> grazing_value(const Model& model, const vec<Model::dim>& x0,
                                         const grazing_options& opt = {})
{
    if (opt.block < 1) throw input_error("grazing block must be >= 1 minima");
    if (!(opt.tolerance > 0.0)) throw input_error("grazing tolerance must be > 0");
    if (!x0.allFinite()) throw input_error("initial state must be finite");
    flow_options fo;
    fo.integration = opt.integration;
    fo.barrier = false;
    fo.track_maxima = true;
    fo.track_minima = true;
    fo.t_max = opt.t_max;
    fo.cancel = opt.cancel;
    hybrid_flow<Model, Method> flow(model, fo);
    flow.start(0.0, x0);
    grazing_result<Model::dim> res;
    detail::grazing_observer<Model::dim> obs(opt, res);
    res.status = flow.run(obs);
    res.stats = flow.stats();
    return res;
}

}  // namespace vimpact
