#include "vimpact/analysis/impact_statistics.hpp"

#include <algorithm>
#include <cmath>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/input_error.hpp"

namespace vimpact {

std::vector<impact_velocity> impact_velocities(const model& m, const impact_series& impacts)
{
    const auto& t = m.table();
    Eigen::VectorXd n(m.dim()), f(m.dim());
    std::vector<impact_velocity> out;
    out.reserve(impacts.size());
    for (std::size_t k = 0; k < impacts.size(); ++k) {
        const int i = impacts.surface[k];
        impact_velocity v;
        const auto pre = impacts.pre.x(k), post = impacts.post.x(k);
        t.gap_gradient(m.context(), i, pre.data(), n.data());
        t.rhs(m.context(), pre.data(), f.data());
        v.normal = -n.dot(f);
        t.gap_gradient(m.context(), i, post.data(), n.data());
        t.rhs(m.context(), post.data(), f.data());
        v.rebound = n.dot(f);
        v.energy = 0.5 * (v.normal * v.normal - v.rebound * v.rebound);
        out.push_back(v);
    }
    return out;
}

impact_statistics compute_impact_statistics(const model& m, const simulation& run)
{
    impact_statistics s;
    s.impacts = static_cast<long>(run.impacts.size());
    s.duration = run.t_record_end - run.t_record_start;
    const bool timed = s.duration > 0.0;
    s.rate = timed ? static_cast<double>(s.impacts) / s.duration : 0.0;
    s.contact_fraction = timed ? std::min(1.0, run.contact_time / s.duration) : 0.0;
    s.excursion_by_surface = run.max_gap;
    for (const double g : run.max_gap)
        if (std::isfinite(g) && !(g <= s.excursion)) s.excursion = g;
    if (s.impacts == 0) return s;
    double sum = 0.0, sum2 = 0.0, energy = 0.0;
    s.velocity_min = std::numeric_limits<double>::infinity();
    s.velocity_max = -std::numeric_limits<double>::infinity();
    for (const auto& v : impact_velocities(m, run.impacts)) {
        s.velocity_min = std::min(s.velocity_min, v.normal);
        s.velocity_max = std::max(s.velocity_max, v.normal);
        sum += v.normal;
        sum2 += v.normal * v.normal;
        energy += v.energy;
    }
    const auto n = static_cast<double>(s.impacts);
    s.velocity_mean = sum / n;
    s.velocity_rms = std::sqrt(sum2 / n);
    s.energy_per_impact = energy / n;
    s.power = timed ? energy / s.duration : impact_statistics::nan;
    return s;
}

const std::vector<const char*>& impact_statistics_names()
{
    static const std::vector<const char*> names{
        "impacts_recorded",      "duration",          "impact_rate",          "impact_velocity_min",
        "impact_velocity_mean",  "impact_velocity_rms", "impact_velocity_max", "energy_per_impact",
        "power",                 "contact_fraction",  "excursion"};
    return names;
}

std::vector<double> impact_statistics_values(const impact_statistics& s)
{
    return {static_cast<double>(s.impacts), s.duration,         s.rate,          s.velocity_min,
            s.velocity_mean,                s.velocity_rms,     s.velocity_max,  s.energy_per_impact,
            s.power,                        s.contact_fraction, s.excursion};
}

impact_statistics impact_statistics_from_values(const std::vector<double>& v)
{
    if (v.size() != impact_statistics_names().size())
        throw input_error("impact statistics need " + std::to_string(impact_statistics_names().size()) + " values (got " +
                          std::to_string(v.size()) + ")");
    impact_statistics s;
    s.impacts = static_cast<long>(v[0]);
    s.duration = v[1];
    s.rate = v[2];
    s.velocity_min = v[3];
    s.velocity_mean = v[4];
    s.velocity_rms = v[5];
    s.velocity_max = v[6];
    s.energy_per_impact = v[7];
    s.power = v[8];
    s.contact_fraction = v[9];
    s.excursion = v[10];
    return s;
}

}  // namespace vimpact
