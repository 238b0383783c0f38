#pragma once
// One point of a sweep, map or basin: the paper's protocol from an initial state, then the
// period classification of its section points. Also the grid of parameter values and the
// hand-over of a final state to the next point of a branch-following sweep.
#include <cmath>
#include <string>
#include <vector>

#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol.hpp"

namespace vimpact {

template <int N>
struct classified_run {
    protocol_result<N> run;
    period_label label;
};

template <template <int> class Method = dop853, sticking_model Model>
classified_run<Model::dim> run_and_classify(const Model& model, const vec<Model::dim>& x0,
                                            const protocol_options& opt, double period_tol)
{
    classified_run<Model::dim> out{run_protocol<Method>(model, x0, opt), {}};
    out.label = classify_period(model, out.run, period_tol);
    return out;
}

// n values from a to b inclusive, evenly spaced (n = 1: a). Computed as a + i (b - a)/(n - 1)
// so every value depends only on (a, b, n, i), never on accumulated rounding.
inline std::vector<double> grid_values(double a, double b, long n)
{
    if (n < 1) throw input_error("a range needs n >= 1 points (got " + std::to_string(n) + ")");
    if (!std::isfinite(a) || !std::isfinite(b)) throw input_error("range ends must be finite");
    std::vector<double> v(static_cast<std::size_t>(n));
    for (long i = 0; i < n; ++i)
        v[static_cast<std::size_t>(i)] = n == 1 ? a : (i == n - 1 ? b : a + static_cast<double>(i) * (b - a) / static_cast<double>(n - 1));
    return v;
}

// The final state of one sweep point as the start of the next: unchanged when admissible for
// the next point's barrier; otherwise (the barrier moved above it) placed on the barrier with
// its velocity pointing away, so the orbit continues as closely as the new barrier allows.
template <sticking_model Model>
vec<Model::dim> continue_from(const Model& next, vec<Model::dim> x)
{
    constexpr int p = Model::position, v = Model::velocity;
    if (next.guard(x) < 0.0 || (next.guard(x) == 0.0 && x[v] < 0.0)) {
        x[p] = x[p] - next.guard(x);  // onto the barrier (guard is position - barrier)
        x[v] = std::abs(x[v]);
    }
    return x;
}

}  // namespace vimpact
