#include "jobs/job_dispenser.hpp"

#include <algorithm>

namespace vimpact {

job_dispenser::job_dispenser(const job_schedule& schedule, std::function<bool(long)> todo, long count, long window,
                             long threads, long divisor, long granule)
    : m_schedule(schedule),
      m_todo(std::move(todo)),
      m_window(std::max(1L, window)),
      m_threads(std::max(1L, threads)),
      m_divisor(std::max(1L, divisor)),
      m_granule(std::max(1L, granule)),
      m_unassigned(count)
{
    m_next = next_todo(0);
    m_undelivered = m_next;
}

long job_dispenser::next_todo(long job) const
{
    while (job < m_schedule.jobs && !m_todo(job)) ++job;
    return job;
}

std::vector<long> job_dispenser::grant(long want)
{
    std::vector<long> out;
    if (want <= 0 || exhausted()) return out;
    const long share = std::max(1L, (m_unassigned + m_divisor * m_threads - 1) / (m_divisor * m_threads));
    // Whole granules: a share that is not a whole number of batches (near the end of the
    // list) would leave lanes empty, and misalign every later grant of that thread.
    const long n = want >= m_granule ? std::min(want / m_granule, (share + m_granule - 1) / m_granule) * m_granule
                                     : std::min(want, share);
    bool cut = false;
    while (static_cast<long>(out.size()) < n && m_next < m_schedule.jobs) {
        if (m_next >= m_undelivered + m_window) {
            cut = true;
            break;
        }
        if (const long p = m_schedule.predecessor(m_next); p >= 0 && m_todo(p)) {
            // The predecessor is computed by this run: it must have arrived.
            const auto c = m_completed.find(p);
            if (c == m_completed.end()) break;
            m_completed.erase(c);
        }
        out.push_back(m_next);
        --m_unassigned;
        m_next = next_todo(m_next + 1);
    }
    // Cut short by the window, a grant keeps whole granules; the rest goes with a later one
    // (a piece would leave lanes empty, and every grant after it would be misaligned too).
    // Nothing at all only while jobs before it are out: their delivery moves the window.
    // Otherwise (a resumed run whose window holds less than a granule still to compute)
    // waiting would never end, and the piece goes.
    if (cut && m_granule > 1 && !m_schedule.chained() && !out.empty()) {
        std::size_t keep = out.size() / static_cast<std::size_t>(m_granule) * static_cast<std::size_t>(m_granule);
        if (keep == 0 && m_undelivered >= out.front()) keep = out.size();
        if (keep < out.size()) {
            m_next = out[keep];
            m_unassigned += static_cast<long>(out.size() - keep);
            out.resize(keep);
        }
    }
    return out;
}

void job_dispenser::completed(long job)
{
    if (m_schedule.chained() && job + m_schedule.chains < m_schedule.jobs) m_completed.insert(job);
}

long rank_capacity(long threads, double mean_job_seconds, long batch, double batch_seconds)
{
    batch = std::max(1L, batch);
    // Both bounds are whole batches.
    const long least = 4 * batch * threads, most = std::max(64L / batch, 4L) * batch * threads;
    if (!(mean_job_seconds > 0.0)) return least;
    const double want = static_cast<double>(threads) * batch_seconds / mean_job_seconds;
    return want >= static_cast<double>(most) ? most : std::max(least, static_cast<long>(want) / batch * batch);
}

void job_dispenser::delivered_below(long job) { m_undelivered = std::max(m_undelivered, job); }

}  // namespace vimpact
