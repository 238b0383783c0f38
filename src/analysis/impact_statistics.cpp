#include "vimpact/analysis/impact_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

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

namespace {

// The scalar fields of the description, in its order: their names, or their values read into
// or written from a list of doubles.
struct scalar_names {
    std::vector<const char*> names;
    template <class T>
    void operator()(const field& f, const T&)
    {
        if (f.span == field_span::one) names.push_back(f.name.data());
    }
};

struct scalar_values {
    std::vector<double> values;
    template <class T>
    void operator()(const field& f, const T& x)
    {
        if constexpr (std::is_arithmetic_v<T>)
            if (f.span == field_span::one) values.push_back(static_cast<double>(x));
    }
};

struct scalar_reader {
    const std::vector<double>& values;
    std::size_t next = 0;
    template <class T>
    void operator()(const field& f, T& x)
    {
        if constexpr (std::is_arithmetic_v<T>)
            if (f.span == field_span::one) x = static_cast<T>(values[next++]);
    }
};

}  // namespace

const std::vector<const char*>& impact_statistics_names()
{
    static const std::vector<const char*> names = [] {
        scalar_names v;
        const impact_statistics s;
        describe(v, s);
        return v.names;
    }();
    return names;
}

std::vector<double> impact_statistics_values(const impact_statistics& s)
{
    scalar_values v;
    describe(v, s);
    return v.values;
}

impact_statistics impact_statistics_from_values(const std::vector<double>& v)
{
    if (v.size() != impact_statistics_names().size())
        throw input_error("impact statistics need " + std::to_string(impact_statistics_names().size()) + " values (got " +
                          std::to_string(v.size()) + ")");
    impact_statistics s;
    scalar_reader r{v};
    describe(r, s);
    return s;
}

}  // namespace vimpact
