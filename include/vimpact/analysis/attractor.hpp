#pragma once
// Identifying attractors across many runs (basins of attraction): two runs reached the same
// attractor when they carry the same label and
// - periodic (a period N was found): the N section points of one cycle match those of the
//   other, in any cyclic order, within `tolerance` in the max norm;
// - aperiodic: the bounding boxes of their recorded section points agree within
//   `box_fraction` of the box's extent in every coordinate. A recorded sample of a chaotic
//   attractor covers it only roughly, so this is a coarse test: it separates attractors that
//   occupy different regions, not interleaved ones (documented in docs/sweeps.md);
// - failed runs (an outcome other than ok) form one class per outcome.
// Ids are given in the order runs are offered, so they are deterministic for a job order.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vimpact/core/record.hpp"

namespace vimpact {

struct attractor_signature {
    std::string label;                     // P0, P1, ..., aperiodic, or a failed outcome
    int period = -1;                       // N when a cycle was found, else -1
    std::vector<Eigen::VectorXd> cycle;    // the N section points of one cycle
    Eigen::VectorXd lo, hi;                // bounding box of all recorded section points
};

// Units "signature": the state's, with each phase a (cos, sin) pair scaled by period / 2 pi.
template <class V, record_of<attractor_signature> S>
void describe(V& v, S& s)
{
    v(field{"label", "the run's period label"}, s.label);
    v(field{"period", "N when a cycle was found, else -1"}, s.period);
    v(field{"cycle", "the N section points of one cycle", "signature"}, s.cycle);
    v(field{"lo", "lower corner of the bounding box of the recorded section points", "signature"}, s.lo);
    v(field{"hi", "its upper corner", "signature"}, s.hi);
}

struct attractor_match_options {
    double tolerance = 1e-6;
    double box_fraction = 0.05;
};

// Builds a signature from section coordinates; `period` <= 0 means no cycle was found.
template <class Coordinates>
attractor_signature make_signature(std::string label, int period, const std::vector<Coordinates>& coords)
{
    attractor_signature s;
    s.label = std::move(label);
    if (coords.empty()) return s;
    const auto k = coords.front().size();
    s.lo = Eigen::VectorXd::Constant(k, std::numeric_limits<double>::infinity());
    s.hi = Eigen::VectorXd::Constant(k, -std::numeric_limits<double>::infinity());
    for (const auto& c : coords)
        for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(k); ++i) {
            s.lo[i] = std::min(s.lo[i], static_cast<double>(c[i]));
            s.hi[i] = std::max(s.hi[i], static_cast<double>(c[i]));
        }
    if (period > 0 && static_cast<std::size_t>(period) <= coords.size()) {
        s.period = period;
        for (int i = 0; i < period; ++i) s.cycle.emplace_back(coords[static_cast<std::size_t>(i)]);
    }
    return s;
}

inline bool same_attractor(const attractor_signature& a, const attractor_signature& b,
                           const attractor_match_options& opt)
{
    if (a.label != b.label || a.period != b.period) return false;
    if (a.period > 0) {
        // Same set of cycle points: each point of a has a partner in b (cyclic order may differ).
        for (const auto& p : a.cycle) {
            const bool found = std::any_of(b.cycle.begin(), b.cycle.end(), [&](const Eigen::VectorXd& q) {
                if (q.size() != p.size()) return false;
                for (Eigen::Index i = 0; i < p.size(); ++i)
                    if (!(std::abs(p[i] - q[i]) <= opt.tolerance)) return false;
                return true;
            });
            if (!found) return false;
        }
        return true;
    }
    if (a.lo.size() == 0 || b.lo.size() == 0) return a.lo.size() == b.lo.size();  // failed runs
    if (a.lo.size() != b.lo.size()) return false;
    // Scalar loops: GCC 12 warns falsely on Eigen's vectorised min/max of dynamic vectors.
    for (Eigen::Index i = 0; i < a.lo.size(); ++i) {
        const double extent = std::max(a.hi[i], b.hi[i]) - std::min(a.lo[i], b.lo[i]);
        const double allowed = opt.box_fraction * extent + opt.tolerance;
        if (std::abs(a.lo[i] - b.lo[i]) > allowed || std::abs(a.hi[i] - b.hi[i]) > allowed) return false;
    }
    return true;
}

// The attractors seen so far; identify() returns the id of the matching one or adds it.
class attractor_catalogue {
public:
    explicit attractor_catalogue(attractor_match_options opt = {}) : m_opt(opt) {}

    int identify(const attractor_signature& s)
    {
        for (std::size_t i = 0; i < m_entries.size(); ++i)
            if (same_attractor(m_entries[i].signature, s, m_opt)) {
                ++m_entries[i].members;
                return static_cast<int>(i);
            }
        m_entries.push_back({s, 1});
        return static_cast<int>(m_entries.size() - 1);
    }

    struct entry {
        attractor_signature signature;  // of the first run that reached it
        long members = 0;
    };
    [[nodiscard]] const std::vector<entry>& entries() const { return m_entries; }

private:
    attractor_match_options m_opt;
    std::vector<entry> m_entries;
};

}  // namespace vimpact
