// GCC 12 warns falsely (-Wrestrict) on std::string concatenations inlined here: the
// declaration's range text (value_range::text) and the labels "P" + N.
#pragma GCC diagnostic ignored "-Wrestrict"
#include "vimpact/analysis/period.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"

namespace vimpact {

double state_distance(const model_info& m, const Eigen::Ref<const Eigen::VectorXd>& a,
                      const Eigen::Ref<const Eigen::VectorXd>& b)
{
    double worst = 0.0;
    for (Eigen::Index k = 0; k < a.size(); ++k) {
        double d = b[k] - a[k];
        const double p = m.state[static_cast<std::size_t>(k)].period;
        if (p > 0.0) d -= p * std::round(d / p);
        worst = std::max(worst, std::abs(d));
    }
    return worst;
}

void check_period_tolerance(double tol) { detail::option_checker{}(period_tolerance_option, tol); }

namespace {

// (rank, period): PN -> (0, N), aperiodic -> (1, 0), anything else -> (2, 0).
std::pair<int, long> label_rank(std::string_view s)
{
    if (s.size() >= 2 && s.size() <= 19 && s[0] == 'P' &&
        std::all_of(s.begin() + 1, s.end(), [](char c) { return c >= '0' && c <= '9'; }))
        return {0, std::stol(std::string(s.substr(1)))};
    return {s == "aperiodic" ? 1 : 2, 0};
}

}  // namespace

bool label_before(std::string_view a, std::string_view b)
{
    const auto ra = label_rank(a), rb = label_rank(b);
    if (ra != rb) return ra < rb;
    return a < b;
}

period_label classify_period(const model& m, const simulation& r, double tol)
{
    period_label out;
    out.impacts_by_surface.assign(static_cast<std::size_t>(m.surface_count()), 0);
    if (r.status != outcome::ok) {
        out.label = std::string(to_string(r.status));
        return out;
    }
    if (!r.impacting) {
        out.label = "P0";
        out.period = 0;
        return out;
    }
    const auto& info = m.info();
    double closure = 0.0;
    const auto period_from = [&](int first, double* worst) {
        return smallest_period(
            static_cast<int>(r.points.size()) - first, tol,
            [&](int i, int j) {
                return state_distance(info, r.points.x(static_cast<std::size_t>(first + i)),
                                      r.points.x(static_cast<std::size_t>(first + j)));
            },
            worst);
    };
    const int n = static_cast<int>(r.points.size());
    const auto distance = [&](int i, int j) {
        return state_distance(info, r.points.x(static_cast<std::size_t>(i)), r.points.x(static_cast<std::size_t>(j)));
    };
    const int p = period_from(0, &closure);
    if (p == 0) {
        out.label = "aperiodic";
        out.settled = period_from(n / 2, nullptr) == 0 && converging_period(n, distance, [](int) { return true; }) == 0;
        return out;
    }
    out.settled = converging_period(n, distance, [p](int q) { return q < p && p % q == 0; }) == 0;
    out.period = p;
    char text[24];  // not "P" + to_string(p): GCC 12 warns falsely (-Wrestrict) on that
    std::snprintf(text, sizeof text, "P%d", p);
    out.label = text;
    out.closure = closure;
    const double t_a = r.points.t(0), t_b = r.points.t(static_cast<std::size_t>(p));
    for (std::size_t k = 0; k < r.impacts.size(); ++k) {
        const double t = r.impacts.pre.t(k);
        if (t > t_a && t <= t_b) {
            ++out.impacts_per_period;
            ++out.impacts_by_surface[static_cast<std::size_t>(r.impacts.surface[k])];
        }
    }
    return out;
}

classified_run run_and_classify(const model& m, const Eigen::VectorXd& x0, const protocol_options& o, double tol)
{
    check_period_tolerance(tol);
    classified_run c{simulate(m, x0, o), {}};
    c.label = classify_period(m, c.run, tol);
    return c;
}

}  // namespace vimpact
