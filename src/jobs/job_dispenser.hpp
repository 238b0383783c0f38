#pragma once
// How the coordinator of a many-job run hands out its jobs (jobs/job_loop.hpp): on demand,
// to whichever rank (or the coordinator's own threads) asks, in ascending job order, in
// blocks that shrink as the list runs out (guided self-scheduling), never further ahead of
// the first undelivered job than a window (the results wait there for in-order delivery, so
// the window bounds the coordinator's memory), and a chained job only once its predecessor's
// result has arrived. The simulation of the schedule (bench/schedule_sim.cpp) runs this same
// class.
#include <functional>
#include <unordered_set>
#include <vector>

#include "vimpact/jobs/job_schedule.hpp"

namespace vimpact {

// The jobs a rank of `threads` threads holds at most (running and queued; it asks for more
// when it holds half): four per thread, or, when its jobs are short, enough for about
// `batch_seconds` of work, so that its requests and reports (which carry its results) stay
// few per second whatever the job's length; at most 64 (or four batches) per thread. Threads that run `batch`
// jobs at a time (SIMD lanes) hold at least four batches each, so that when the rank asks
// (holding half) a batch still waits behind full lanes and no lane idles for the answer; the
// capacity is a whole number of batches. mean_job_seconds <= 0: not known yet.
long rank_capacity(long threads, double mean_job_seconds, long batch = 1, double batch_seconds = 0.1);

// The window of a run on several ranks, per computing thread of all ranks: room for every
// rank's largest holding twice over.
inline constexpr long ranks_window_per_thread = 128;

class job_dispenser {
public:
    // The jobs to compute are those of `schedule` for which `todo` holds (this shard's,
    // not finished before), `count` of them. `threads` counts the computing threads of all
    // ranks; a grant is at most ceil(unassigned / (divisor * threads)) jobs, that share rounded
    // up to a whole number of `granule` jobs (the batch a thread runs in its SIMD lanes).
    job_dispenser(const job_schedule& schedule, std::function<bool(long)> todo, long count, long window, long threads,
                  long divisor = 2, long granule = 1);

    // Up to `want` jobs, ascending; a whole number of granules when `want` holds one, except
    // at the end of the list, or when the window holds less than a granule still to compute
    // and no job before it is out (a resumed run). Fewer or none when the window, a chain
    // waiting for its predecessor or the end of the list allows no more.
    std::vector<long> grant(long want);
    // A job's result arrived (its successor in a chain may go).
    void completed(long job);
    // Every job to compute below `job` has been delivered (the window moves).
    void delivered_below(long job);

    [[nodiscard]] long unassigned() const { return m_unassigned; }
    [[nodiscard]] bool exhausted() const { return m_next >= m_schedule.jobs; }
    // The first job to compute at or after `job` (jobs: none).
    [[nodiscard]] long next_todo(long job) const;

private:
    job_schedule m_schedule;
    std::function<bool(long)> m_todo;
    long m_window, m_threads, m_divisor, m_granule;
    long m_next = 0;            // the next job to hand out
    long m_undelivered = 0;     // the first job not delivered
    long m_unassigned = 0;
    std::unordered_set<long> m_completed;  // chained runs: results whose successor has not gone yet
};

}  // namespace vimpact
