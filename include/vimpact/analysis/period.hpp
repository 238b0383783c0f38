#pragma once
// Period classification of recorded section points (SPEC §2): the smallest N such that the
// section states repeat with period N within a tolerance, compared on the model's full
// section coordinates (for the paper's model (y, x, w), not y alone).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "vimpact/analysis/protocol.hpp"

namespace vimpact {

struct period_label {
    std::string label;           // "P0", "P1", ..., "aperiodic", or a failed run's outcome
    int period = -1;             // N for PN (0 for P0); -1 aperiodic or failed
    long impacts_per_period = 0;
    double closure = 0.0;        // max distance between points N apart (periodic labels)
};

// Smallest period N <= points/2 with max_i |c_{i+N} - c_i|_inf <= tol; 0 if none.
// Generic in the coordinates so it can be tested on synthetic data.
template <class Coordinates>
int smallest_period(const std::vector<Coordinates>& c, double tol, double* closure = nullptr)
{
    const int n = static_cast<int>(c.size());
    for (int p = 1; 2 * p <= n; ++p) {
        double worst = 0.0;
        for (int i = 0; i + p < n && worst <= tol; ++i)
            worst = std::max(worst, (c[i + p] - c[i]).cwiseAbs().maxCoeff());
        if (worst <= tol) {
            if (closure) *closure = worst;
            return p;
        }
    }
    return 0;
}

template <sticking_model Model>
period_label classify_period(const Model& model, const protocol_result<Model::dim>& r, double tol)
{
    period_label out;
    if (r.status != outcome::ok) {
        out.label = std::string(to_string(r.status));
        return out;
    }
    if (!r.impacting) {
        out.label = "P0";
        out.period = 0;
        return out;
    }
    using coords = decltype(model.section_coordinates(r.points.front().x));
    std::vector<coords> c;
    c.reserve(r.points.size());
    for (const auto& p : r.points) c.push_back(model.section_coordinates(p.x));
    double closure = 0.0;
    const int p = smallest_period(c, tol, &closure);
    if (p == 0) {
        out.label = "aperiodic";
        return out;
    }
    out.period = p;
    out.label = "P" + std::to_string(p);
    out.closure = closure;
    const double t_a = r.points[0].t, t_b = r.points[p].t;
    out.impacts_per_period = std::count_if(r.impacts.begin(), r.impacts.end(), [&](const auto& e) {
        return e.t > t_a && e.t <= t_b;
    });
    return out;
}

}  // namespace vimpact
