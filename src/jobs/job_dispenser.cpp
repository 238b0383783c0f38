#include "vimpact/jobs/job_dispenser.hpp"

#include <algorithm>

namespace vimpact {

job_dispenser::job_dispenser(const job_schedule& schedule, std::function<bool(long)> todo, long count, long window,
                             long threads, long divisor)
    : m_schedule(schedule),
      m_todo(std::move(todo)),
      m_window(std::max(1L, window)),
      m_threads(std::max(1L, threads)),
      m_divisor(std::max(1L, divisor)),
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
    const long share = (m_unassigned + m_divisor * m_threads - 1) / (m_divisor * m_threads);
    const long n = std::min(want, std::max(1L, share));
    while (static_cast<long>(out.size()) < n && m_next < m_schedule.jobs) {
        if (m_next >= m_undelivered + m_window) break;
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
    return out;
}

void job_dispenser::completed(long job)
{
    if (m_schedule.chained() && job + m_schedule.chains < m_schedule.jobs) m_completed.insert(job);
}

long rank_capacity(long threads, double mean_job_seconds, long batch, double batch_seconds)
{
    const long least = std::max(4L, 2 * batch) * threads, most = std::max(64L, 2 * batch) * threads;
    if (!(mean_job_seconds > 0.0)) return least;
    const double want = static_cast<double>(threads) * batch_seconds / mean_job_seconds;
    return want >= static_cast<double>(most) ? most : std::max(least, static_cast<long>(want));
}

void job_dispenser::delivered_below(long job) { m_undelivered = std::max(m_undelivered, job); }

}  // namespace vimpact
