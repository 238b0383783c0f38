#pragma once
// The job loop shared by every sweep, map and basin computation: a list of independent jobs
// (a parameter point or an initial state), each running one analysis, computed by a pool of
// threads and delivered to a sink in job order.
//
// Guarantees, whatever the thread count:
// - Deterministic: a job's result depends only on its index (and, for chained jobs, on its
//   predecessor's result), never on scheduling; the sink sees results in ascending job order.
// - Streaming: at most `window` finished results wait for delivery, so memory does not grow
//   with the number of jobs beyond what the sink keeps.
// - Shardable: shard i/n owns every chain c with c % n == i (for independent jobs, every n-th
//   job); n processes with i = 0..n-1 together compute every job exactly once.
// - Resumable: jobs already finished (read back by the caller) are skipped, and serve as
//   predecessors of chained jobs.
// - Interruptible: when `stop` becomes true, no new job starts; results finished before it are
//   still delivered (in ascending order, with gaps), so a later resume loses only the jobs
//   that were running (whose results may have been cut short by the same flag).
//
// Chained jobs (a parameter sweep that follows its branch): job j starts from the result of
// job j - chains. With chains = 2 an upward and a downward sweep interleave and run in parallel.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "vimpact/core/input_error.hpp"

namespace vimpact {

struct shard_spec {
    long index = 0;
    long count = 1;

    [[nodiscard]] bool owns_chain(long chain) const { return chain % count == index; }
};

struct job_schedule {
    long jobs = 0;
    long chains = 0;  // 0: independent jobs; c > 0: job j continues from job j - c

    [[nodiscard]] bool chained() const { return chains > 0; }
    [[nodiscard]] long chain_of(long job) const { return chained() ? job % chains : job; }
    [[nodiscard]] long predecessor(long job) const { return chained() && job >= chains ? job - chains : -1; }
};

struct job_loop_options {
    int threads = 0;   // 0: every hardware thread
    // Jobs a worker takes at once (independent jobs only), for a Run with a `many` member
    // (job_runners): several jobs integrated together in SIMD lanes. 1: one at a time.
    long batch = 1;
    shard_spec shard{};
    long window = 0;   // finished results allowed to wait for in-order delivery (0: 8 per thread)
    const std::atomic<bool>* stop = nullptr;
    std::function<void(long done, long total)> progress;  // called after each delivery
};

struct job_loop_summary {
    long owned = 0;     // jobs in this shard
    long resumed = 0;   // of them, finished before this call
    long computed = 0;  // delivered by this call
    bool stopped = false;
    int threads = 0;
};

inline void validate(const shard_spec& s)
{
    if (s.count < 1 || s.index < 0 || s.index >= s.count)
        throw input_error("shard " + std::to_string(s.index) + "/" + std::to_string(s.count) +
                          " is invalid (need 0 <= i < n, n >= 1)");
}

// The most worker threads any analysis starts.
inline constexpr int max_threads = 1024;

inline int resolve_threads(int requested)
{
    if (requested < 0 || requested > max_threads)
        throw input_error("threads = " + std::to_string(requested) + " is outside its valid range [0, " +
                          std::to_string(max_threads) + "] (0: every core)");
    if (requested > 0) return requested;
    const unsigned hw = std::thread::hardware_concurrency();
    return hw == 0 ? 1 : static_cast<int>(hw);
}

// A Run that can also take several independent jobs at once:
//   single(job, const Record* predecessor_or_null) -> Record;
//   many(std::span<const long> jobs) -> std::vector<Record> (in the order of `jobs`).
template <class Single, class Many>
struct job_runners {
    Single single;
    Many many;
};
template <class Single, class Many>
job_runners(Single, Many) -> job_runners<Single, Many>;

namespace detail {
template <class Record, class Run>
Record run_one(Run& run, long job, const Record* pred)
{
    if constexpr (requires { run.single; }) return run.single(job, pred);
    else return run(job, pred);
}
}  // namespace detail

// Run(job, const Record* predecessor_or_null) -> Record, or job_runners;  Sink(job, Record&&).
// `finished` holds the results of jobs done before (resume); they are not delivered again.
template <class Record, class Run, class Sink>
job_loop_summary run_jobs(const job_schedule& schedule, const job_loop_options& opt,
                          const std::unordered_map<long, Record>& finished, Run&& run, Sink&& sink)
{
    validate(opt.shard);
    if (schedule.jobs < 0 || schedule.chains < 0) throw input_error("job count must be >= 0");
    job_loop_summary summary;
    std::vector<long> todo;
    for (long j = 0; j < schedule.jobs; ++j) {
        if (!opt.shard.owns_chain(schedule.chain_of(j))) continue;
        ++summary.owned;
        if (finished.count(j)) ++summary.resumed;
        else todo.push_back(j);
    }
    const int threads = std::max(1, std::min<int>(resolve_threads(opt.threads),
                                                  static_cast<int>(std::max<std::size_t>(todo.size(), 1))));
    summary.threads = threads;
    constexpr bool can_batch = requires(std::decay_t<Run>& r, std::span<const long> js) { r.many(js); };
    const long batch = can_batch && !schedule.chained() ? std::max(1L, opt.batch) : 1L;
    const long window = std::max(opt.window > 0 ? opt.window : 8L * threads, 2L * batch * threads);
    const long total = static_cast<long>(todo.size());

    std::mutex mutex;
    std::condition_variable changed;
    long next_take = 0;                          // position in todo of the next job to start
    long delivered = 0;                          // positions delivered in order
    std::map<long, Record> ready;                // finished, waiting for delivery (by position)
    std::unordered_map<long, Record> successors; // chained results still needed as predecessors
    std::exception_ptr failure;
    bool abort = false;
    int running_workers = threads;

    auto stop_requested = [&] { return abort || (opt.stop && opt.stop->load()); };
    // The stop flag is set from a signal handler, which cannot notify: poll it.
    auto wait = [&](std::unique_lock<std::mutex>& lock, auto&& pred) {
        while (!pred()) changed.wait_for(lock, std::chrono::milliseconds(50));
    };

    // Runs f() without the lock; false when it threw (the failure is kept, the loop aborts).
    auto unlocked = [&](std::unique_lock<std::mutex>& lock, auto&& f) {
        lock.unlock();
        try {
            f();
        } catch (...) {
            lock.lock();
            if (!failure) failure = std::current_exception();
            abort = true;
            changed.notify_all();
            return false;
        }
        lock.lock();
        return true;
    };

    auto worker = [&] {
        std::unique_lock lock(mutex);
        for (;;) {
            wait(lock, [&] {
                return stop_requested() || next_take >= total || next_take < delivered + window;
            });
            if (stop_requested() || next_take >= total) break;
            if constexpr (can_batch) {
                const long take = std::min({batch, total - next_take, delivered + window - next_take});
                if (take > 1) {
                    const long first = next_take;
                    next_take += take;
                    std::vector<long> jobs(todo.begin() + first, todo.begin() + first + take);
                    std::vector<Record> results;
                    if (!unlocked(lock, [&] { results = run.many(std::span<const long>(jobs)); })) break;
                    if (opt.stop && opt.stop->load()) break;
                    for (long k = 0; k < take; ++k)
                        ready.emplace(first + k, std::move(results[static_cast<std::size_t>(k)]));
                    changed.notify_all();
                    continue;
                }
            }
            const long pos = next_take++;
            const long job = todo[static_cast<std::size_t>(pos)];
            const long pred = schedule.predecessor(job);
            std::optional<Record> pred_record;
            if (pred >= 0) {
                // The predecessor precedes this job in todo (or was finished before), so it is
                // being computed by another worker: wait for it.
                wait(lock, [&] {
                    return stop_requested() || finished.count(pred) || successors.count(pred);
                });
                if (stop_requested()) break;
                if (auto f = finished.find(pred); f != finished.end()) {
                    pred_record = f->second;
                } else {
                    auto s = successors.find(pred);
                    pred_record = std::move(s->second);
                    successors.erase(s);
                }
            }
            std::optional<Record> result;
            if (!unlocked(lock, [&] {
                    result.emplace(detail::run_one<Record>(
                        run, job, pred_record ? &*pred_record : static_cast<const Record*>(nullptr)));
                }))
                break;
            // A job that was running when the stop flag was set may have been cut short (its
            // flows poll the same flag and end early): it is not a result, and a journal must
            // not keep it, so a resume computes it again.
            if (opt.stop && opt.stop->load()) break;
            if (schedule.chained() && job + schedule.chains < schedule.jobs) successors.emplace(job, *result);
            ready.emplace(pos, std::move(*result));
            changed.notify_all();
        }
        --running_workers;
        changed.notify_all();
    };

    std::vector<std::jthread> pool;
    pool.reserve(static_cast<std::size_t>(threads));
    for (int i = 0; i < threads; ++i) pool.emplace_back(worker);

    auto deliver = [&](std::map<long, Record>::node_type node, std::unique_lock<std::mutex>& lock) {
        lock.unlock();
        try {
            sink(todo[static_cast<std::size_t>(node.key())], std::move(node.mapped()));
        } catch (...) {
            lock.lock();
            if (!failure) failure = std::current_exception();
            abort = true;
            changed.notify_all();
            return false;
        }
        ++summary.computed;
        if (opt.progress) opt.progress(summary.resumed + summary.computed, summary.owned);
        lock.lock();
        return true;
    };

    {
        std::unique_lock lock(mutex);
        for (;;) {
            wait(lock, [&] { return ready.count(delivered) || running_workers == 0 || abort; });
            if (abort) break;
            if (ready.count(delivered)) {
                auto node = ready.extract(delivered);
                ++delivered;
                changed.notify_all();  // the window moved
                if (!deliver(std::move(node), lock)) break;
                continue;
            }
            break;  // every worker has left and the next result will not come
        }
        // After a stop: hand over what did finish, in ascending order, so a resume keeps it.
        if (!failure) {
            wait(lock, [&] { return running_workers == 0; });
            while (!ready.empty() && !abort) {
                auto node = ready.extract(ready.begin());
                if (!deliver(std::move(node), lock)) break;
            }
        }
    }
    for (auto& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
    summary.stopped = summary.resumed + summary.computed < summary.owned;
    return summary;
}

}  // namespace vimpact
