#pragma once
// Period classification of recorded section points: the smallest N such that the states
// repeat with period N within a tolerance, compared on the full state (phases modulo their
// period), not on one coordinate alone. Labels: P0 (no impacts after the transient), P1, P2,
// ..., "aperiodic" (no N up to half the points), or the outcome of a failed run.
#include <algorithm>
#include <string>
#include <vector>

#include "vimpact/analysis/protocol.hpp"

namespace vimpact {

struct period_label {
    std::string label;            // "P0", "P1", ..., "aperiodic", or a failed run's outcome
    int period = -1;              // N for PN (0 for P0); -1 aperiodic or failed
    long impacts_per_period = 0;  // on every surface
    std::vector<long> impacts_by_surface;  // per period
    double closure = 0.0;         // max distance between points N apart (periodic labels)
    // False when the record has not settled: it is aperiodic as a whole but its last half
    // is periodic, so the transient ended only during the recording and a longer one would
    // give that period. A warning about the protocol, not about the orbit.
    bool settled = true;
};

// The paper's period tolerance for its Figures 2 and 5 (Figure 4 used 1e-5).
inline constexpr double default_period_tolerance = 1e-8;

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

struct classified_run {
    simulation run;
    period_label label;
};

// The protocol, then the classification of its points.
classified_run run_and_classify(const model& m, const Eigen::VectorXd& x0, const protocol_options& o, double tol);


}  // namespace vimpact
