#pragma once
// Period classification of recorded section points: the smallest N such that the states
// repeat with period N within a tolerance, compared on the full state (phases modulo their
// period), not on one coordinate alone. Labels: P0 (no impacts after the transient), P1, P2,
// ..., "aperiodic" (no N up to half the points), or the outcome of a failed run.
#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/option.hpp"
#include "vimpact/core/record.hpp"

namespace vimpact {

struct period_label {
    std::string label;            // "P0", "P1", ..., "aperiodic", or a failed run's outcome
    int period = -1;              // N for PN (0 for P0); -1 aperiodic or failed
    long impacts_per_period = 0;  // on every surface
    std::vector<long> impacts_by_surface;  // per period
    double closure = 0.0;         // max distance between points N apart (periodic labels)
    // False when the record has not settled: it is aperiodic as a whole but its last half
    // is periodic, or it still converges onto a periodic orbit (converging_period; for a
    // periodic label, onto one whose period divides it: a P4 approached with a multiplier
    // near -1 closes to the tolerance as P8 first), so the transient ended only during the
    // recording or not at all, and a longer one would give that period. A warning about the
    // protocol, not about the orbit.
    bool settled = true;
};

template <class V, record_of<period_label> L>
void describe(V& v, L& l)
{
    v(field{"label", "P0 (no impact after the transient), P1, P2, ..., aperiodic, or a failed run's outcome"},
      l.label);
    v(field{"period", "N of a label PN (0 for P0); -1 aperiodic or failed"}, l.period);
    v(field{"impacts", "impacts per period on every surface"}, l.impacts_per_period);
    v(field{"closure", "largest max-norm distance between section points one period apart", "state"}, l.closure);
    v(field{"settled", "false while the record still converges onto an orbit or is periodic only in its last "
                       "half (a longer transient gives the period)"},
      l.settled);
    v(field{"impacts_by_surface", "impacts per period on each surface", "", field_span::per_surface,
            "impacts_{surface}"},
      l.impacts_by_surface);
}

// Whether recorded points still converge onto a periodic orbit: the smallest N for which the
// distances d_i between points N apart shrink geometrically over the record, 0 if none. Near a
// periodic orbit whose slowest multiplier mu is inside the unit circle d_i falls like
// |mu|^(i/N), however close |mu| is to 1 and whatever the period tolerance; over a chaotic or
// quasi-periodic record the distances fluctuate, over a drifting one they stay. The record is
// cut into 8 blocks of whole multiples of N points (a complex multiplier makes d_i oscillate
// within one) and the logarithm of each block's largest distance is fitted by a line: N is
// converging when the line falls by at least a factor of 2 over the record, its slope more
// than 10 standard errors below 0. Only the N that `candidate` accepts are tried. Generic in
// the distance d(i, j), like smallest_period.
template <class Distance, class Candidate>
int converging_period(int n, Distance&& d, Candidate&& candidate)
{
    constexpr int blocks = 8;
    for (int p = 1; p * (blocks + 1) <= n; ++p) {
        if (!candidate(p)) continue;
        const int length = (n - p) / blocks / p * p;
        double y[blocks];
        bool usable = true;
        for (int b = 0; b < blocks && usable; ++b) {
            double worst = 0.0;
            for (int i = b * length; i < (b + 1) * length; ++i) worst = std::max(worst, d(i, i + p));
            usable = worst > 0.0 && std::isfinite(worst);
            y[b] = usable ? std::log(worst) : 0.0;
        }
        if (!usable) continue;
        // Least squares y = c + slope (b - centre).
        const double centre = 0.5 * (blocks - 1);
        double mean = 0.0, sxx = 0.0, sxy = 0.0;
        for (const double v : y) mean += v / blocks;
        for (int b = 0; b < blocks; ++b) {
            sxx += (b - centre) * (b - centre);
            sxy += (b - centre) * (y[b] - mean);
        }
        const double slope = sxy / sxx;
        double rss = 0.0;
        for (int b = 0; b < blocks; ++b) {
            const double r = y[b] - mean - slope * (b - centre);
            rss += r * r;
        }
        const double standard_error = std::sqrt(rss / (blocks - 2) / sxx);
        if (slope * (blocks - 1) <= -std::log(2.0) && slope < -10.0 * standard_error) return p;
    }
    return 0;
}

// The paper's period tolerance for its Figures 2 and 5 (Figure 4 used 1e-5).
inline constexpr double default_period_tolerance = 1e-8;
// The period tolerance as the analyses that label their runs declare it (core/option.hpp).
inline constexpr option period_tolerance_option{
    "tol", "period tolerance on the section state; the paper used 1e-8, and 1e-5 for its Figure 4", above(0.0)};

// Smallest N <= n/2 with max_i d(i, i + N) <= tol, 0 if none; d(i, j) the max-norm distance
// of points i and j. Generic in the distance so it can be tested on synthetic data.
template <class Distance>
int smallest_period(int n, double tol, Distance&& d, double* closure = nullptr)
{
    for (int p = 1; 2 * p <= n; ++p) {
        double worst = 0.0;
        for (int i = 0; i + p < n && worst <= tol; ++i) worst = std::max(worst, d(i, i + p));
        if (worst <= tol) {
            if (closure) *closure = worst;
            return p;
        }
    }
    return 0;
}

// The max-norm distance of two states of `m`, phases compared modulo their period.
double state_distance(const model_info& m, const Eigen::Ref<const Eigen::VectorXd>& a,
                      const Eigen::Ref<const Eigen::VectorXd>& b);

// Throws input_error unless tol > 0 and finite.
void check_period_tolerance(double tol);

period_label classify_period(const model& m, const simulation& run, double tol);

// The reading order of labels, in every summary and legend: P0, P1, P2, ... by period (P2
// before P10), then "aperiodic", then the outcomes of failed runs alphabetically.
bool label_before(std::string_view a, std::string_view b);

struct classified_run {
    simulation run;
    period_label label;
};

// The protocol, then the classification of its points.
classified_run run_and_classify(const model& m, const Eigen::VectorXd& x0, const protocol_options& o, double tol);


}  // namespace vimpact
