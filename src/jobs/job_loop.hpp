#pragma once
// The job loop shared by every sweep, map and basin computation: a list of independent jobs
// (a parameter point or an initial state), each running one analysis, computed by the
// threads of one process or of several (MPI ranks, jobs/job_ranks.hpp) and delivered to a
// sink in job order by the process that coordinates (rank 0).
//
// Guarantees, whatever the thread and rank counts:
// - Deterministic: a job's result depends only on its index (and, for chained jobs, on its
//   predecessor's result), never on scheduling; the sink sees results in ascending job order.
// - Balanced: jobs are handed out on demand in blocks that shrink toward the end of the list
//   (jobs/job_dispenser.hpp), so a rank that drew slow jobs simply asks less often.
// - Streaming: no job is handed out more than `window` jobs past the first undelivered one,
//   so the results waiting for in-order delivery are bounded and memory does not grow with
//   the number of jobs beyond what the sink keeps.
// - Shardable: a shard computes only its chains (jobs/job_schedule.hpp).
// - Resumable: jobs finished before (the caller's `finished`) are skipped, and serve as
//   predecessors of chained jobs.
// - Every result is handed to `arrived` as soon as the coordinator has it, in any order (a
//   journal writes it there, so a process killed at any moment loses only running jobs).
// - Interruptible: when `stop` becomes true, no new job starts; results finished before it are
//   still delivered (in ascending order, with gaps), and results of jobs that were running
//   (maybe cut short by the same flag) are dropped, so a resume computes them again.
//
// Ranks: every rank calls run_jobs with the same schedule. Rank 0 hands out jobs to its own
// threads and to the ranks that ask, receives their results as lines of `wire` (the journal's
// form) and delivers; the other ranks compute and return without delivering anything.
#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <unordered_map>
#include <utility>
#include <vector>

#include "vimpact/core/input_error.hpp"
#include "vimpact/jobs/job_options.hpp"
#include "jobs/job_dispenser.hpp"
#include "vimpact/jobs/job_ranks.hpp"
#include "vimpact/jobs/job_schedule.hpp"

namespace vimpact {

struct job_loop_options {
    int threads = 0;   // per rank; 0: this machine's cores shared among its ranks
    shard_spec shard{};
    // 0: 8 per computing thread (ranks_window_per_thread with several ranks; 16 batches with
    // lanes). The results waiting for in-order delivery are at most this many: with lanes and
    // large records (a sweep's recorded points) that is what bounds rank 0's memory.
    long window = 0;
    const std::atomic<bool>* stop = nullptr;
    std::function<void(long done, long total)> progress;  // called after each delivery
    std::shared_ptr<job_ranks> ranks;                      // null: this process alone
    // Jobs a thread runs at once in its SIMD lanes (a Run with a `stream` member, job_runners,
    // independent jobs only): the unit in which jobs are handed out and held. 1: one at a time.
    long batch = 1;
    // Each job's cost: the CPU time of the thread that ran it (its share of it, for jobs that
    // shared SIMD lanes), which a busy machine does not inflate as it does the wall time
    // (called from the computing threads).
    std::function<void(long job, double seconds)> timed;
};

struct job_loop_summary {
    long owned = 0;     // jobs in this shard
    long resumed = 0;   // of them, finished before this call
    long computed = 0;  // delivered by this call
    bool stopped = false;
    int threads = 0;    // computing threads of this rank
    int ranks = 1;
    bool coordinator = true;  // false on the ranks that deliver nothing
};

// What the loop knows besides the jobs: those finished before, the wire form of records for
// ranks in other processes, and who hears of each result as it arrives.
template <class Record>
struct job_loop_io {
    std::function<bool(long)> finished;        // null: none
    std::function<Record(long)> load;          // a finished job's record (a chained job's start)
    // One line (no newline) holding a job's number and record, and back (the journal's form).
    std::function<std::string(long, const Record&)> encode;
    std::function<std::pair<long, Record>(std::string_view)> decode;
    // On the coordinator, each result as it arrives, with its line when it came from a rank.
    std::function<void(long, const Record&, const std::string*)> arrived;
    // After the results that arrived together (each turn of the coordinator's loop, under a
    // millisecond), and at the end: a journal writes them out.
    std::function<void()> flush;
};

// The records of a map as finished jobs (tests, and callers holding them in memory).
template <class Record>
job_loop_io<Record> finished_in(const std::unordered_map<long, Record>& done)
{
    job_loop_io<Record> io;
    io.finished = [&done](long j) { return done.count(j) > 0; };
    io.load = [&done](long j) { return done.at(j); };
    return io;
}

// Where a stream runner takes its jobs and leaves its results: next() gives the next job,
// or none for now (a later call may give more); done(job, record) as each job ends.
using job_source = std::function<std::optional<long>()>;
template <class Record>
using job_sink = std::function<void(long, Record&&)>;

// A Run that takes independent jobs as its SIMD lanes free up, from the queue all the threads
// of a rank share (so no lane waits for the slowest job of a fixed batch):
//   stream(const job_source&, const job_sink<Record>&): takes jobs until the source gives
//     none while it has none running, and hands each result over as it ends;
//   single(job, const Record* predecessor_or_null) -> Record: jobs that continue from
//     another (chains), one at a time.
template <class Single, class Stream>
struct job_runners {
    Single single;
    Stream stream;
};
template <class Single, class Stream>
job_runners(Single, Stream) -> job_runners<Single, Stream>;

// A stream runner for lists without chains.
template <class Stream>
struct job_streamer {
    Stream stream;
};
template <class Stream>
job_streamer(Stream) -> job_streamer<Stream>;

// One job through a stream runner's stream(source, sink).
template <class Record, class Stream>
Record run_alone(Stream&& stream, long job)
{
    bool given = false;
    std::optional<Record> r;
    stream(job_source([&]() -> std::optional<long> {
               if (given) return std::nullopt;
               given = true;
               return job;
           }),
           job_sink<Record>([&](long, Record&& x) { r.emplace(std::move(x)); }));
    if (!r) throw std::logic_error("a stream runner ended without its job's result");
    return std::move(*r);
}

namespace detail {

template <class Record, class Run>
Record run_one(Run& run, long job, const Record* pred)
{
    if constexpr (requires { run.single; }) {
        return run.single(job, pred);
    } else if constexpr (requires { run.stream; }) {
        if (pred) throw std::logic_error("a stream runner was given a chained job");
        return run_alone<Record>(run.stream, job);
    } else {
        return run(job, pred);
    }
}

// The share of a thread's time each of its running jobs gets: the time between two events
// (a job taken or ended) split evenly among the jobs running then, so that jobs sharing SIMD
// lanes are each charged for their part, CPU and wall clock.
class job_shares {
public:
    // cpu: also the CPU time (a system call per event); the wall time always.
    explicit job_shares(bool cpu) : m_with_cpu(cpu) { m_open.reserve(64); }
    void begin(long job)
    {
        advance();
        m_open.push_back({job, 0.0, 0.0});
    }
    // The job's CPU and wall seconds.
    std::pair<double, double> end(long job)
    {
        advance();
        const auto it = std::find_if(m_open.begin(), m_open.end(), [job](const open_job& o) { return o.job == job; });
        if (it == m_open.end()) throw std::logic_error("a stream runner ended a job it was not given");
        const std::pair<double, double> r(it->cpu, it->wall);
        m_open.erase(it);
        return r;
    }
    [[nodiscard]] long open() const { return static_cast<long>(m_open.size()); }

private:
    struct open_job {
        long job;
        double cpu, wall;
    };
    void advance();

    std::vector<open_job> m_open;
    bool m_with_cpu;
    double m_cpu = 0.0, m_wall = 0.0;
};

// The messages between ranks (tags of job_ranks::send).
enum rank_tag : int {
    tag_hello = 1,   // rank -> 0: its thread count
    tag_start = 2,   // 0 -> rank: the jobs begin
    tag_abort = 3,   // 0 -> rank: the run failed before its jobs began ("kind\nmessage")
    tag_report = 4,  // rank -> 0: "want leaving\n" then one result line per line
    tag_grant = 5,   // 0 -> rank: one job per line ("job" or "job <predecessor's line>"); empty: no more
    tag_stop = 6,    // 0 -> rank: start no more jobs, report and leave
    tag_failed = 7,  // rank -> 0: a job or the rank failed ("kind\nmessage")
    tag_bye = 8,     // 0 -> rank: the run is over (a rank that left waits for it, asleep, rather
                     // than in MPI_Finalize, which spins)
    tag_spec = 9,    // rank -> 0, before anything else: the hash of its run's spec, a newline, the spec
    tag_same = 10,   // 0 -> rank: every rank has the same spec; the run may start
};

// An exception as a message and back: an input_error stays one (exit code 2).
inline std::string failure_text(const std::exception_ptr& e)
{
    try {
        std::rethrow_exception(e);
    } catch (const input_error& x) {
        return std::string("input\n") + x.what();
    } catch (const std::exception& x) {
        return std::string("internal\n") + x.what();
    } catch (...) {
        return "internal\nunknown failure";
    }
}

inline std::exception_ptr failure_from(const std::string& text, int rank)
{
    const auto nl = text.find('\n');
    const std::string kind = text.substr(0, nl), what = nl == std::string::npos ? text : text.substr(nl + 1);
    if (kind == "input") return std::make_exception_ptr(input_error(what));
    return std::make_exception_ptr(std::runtime_error("rank " + std::to_string(rank) + ": " + what));
}

// Tells the other ranks, waiting for the jobs to begin, that the run failed before (rank 0's
// journal refused, say), so that every rank ends with the same error.
inline void abort_ranks(job_ranks& ranks, const std::exception_ptr& e)
{
    for (int r = 1; r < ranks.size(); ++r) ranks.send(r, tag_abort, failure_text(e));
    ranks.flush();
}

// The threads of one rank: they compute the jobs queued to them and leave the results in
// an inbox for the rank's main thread, which talks to the other ranks and delivers.
inline double thread_seconds()
{
    timespec t{};
    ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

inline void job_shares::advance()
{
    const double cpu = m_with_cpu ? thread_seconds() : 0.0;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    if (!m_open.empty()) {
        const double n = static_cast<double>(m_open.size());
        for (open_job& o : m_open) {
            o.cpu += (cpu - m_cpu) / n;
            o.wall += (wall - m_wall) / n;
        }
    }
    m_cpu = cpu;
    m_wall = wall;
}

template <class Record, class Run>
class job_pool {
public:
    struct item {
        long job;
        std::optional<Record> predecessor;
    };

    job_pool(int threads, Run& run, const std::atomic<bool>* stop, std::function<void(long, double)> timed = {},
             long batch = 1)
        : m_run(run), m_stop(stop), m_timed(std::move(timed)), m_batch(std::max(1L, batch))
    {
        m_threads.reserve(static_cast<std::size_t>(threads));
        for (int i = 0; i < threads; ++i) m_threads.emplace_back([this] { work(); });
    }
    ~job_pool() { close(true); }
    job_pool(const job_pool&) = delete;
    job_pool& operator=(const job_pool&) = delete;

    void push(std::vector<item>&& items)
    {
        {
            const std::lock_guard lock(m_mutex);
            for (auto& i : items) m_queue.push_back(std::move(i));
        }
        m_changed.notify_all();
    }
    // The results computed since the last call.
    std::vector<std::pair<long, Record>> take()
    {
        const std::lock_guard lock(m_mutex);
        return std::exchange(m_inbox, {});
    }
    // Waits up to `d` for a result or a failure.
    void wait(std::chrono::microseconds d)
    {
        std::unique_lock lock(m_mutex);
        m_changed.wait_for(lock, d, [&] { return !m_inbox.empty() || m_failure; });
    }
    // The mean wall time of the jobs computed so far (0 before the first).
    [[nodiscard]] double mean_job_seconds() const
    {
        const std::lock_guard lock(m_mutex);
        return m_done > 0 ? m_wall / static_cast<double>(m_done) : 0.0;
    }
    [[nodiscard]] std::exception_ptr failure() const
    {
        const std::lock_guard lock(m_mutex);
        return m_failure;
    }
    // Jobs a thread runs at once (in its SIMD lanes).
    [[nodiscard]] long batch() const { return m_batch; }
    // Queued and running jobs.
    [[nodiscard]] long held() const
    {
        const std::lock_guard lock(m_mutex);
        return static_cast<long>(m_queue.size()) + m_busy;
    }
    // Ends the threads: after their running jobs, dropping the queue when `drop`.
    void close(bool drop)
    {
        {
            const std::lock_guard lock(m_mutex);
            if (drop) m_queue.clear();
            m_closing = true;
        }
        m_changed.notify_all();
        for (auto& t : m_threads)
            if (t.joinable()) t.join();
    }

private:
    [[nodiscard]] bool stopping() const { return m_failure || (m_stop && m_stop->load()); }

    void work()
    {
        std::unique_lock lock(m_mutex);
        for (;;) {
            // The stop flag is set from a signal handler, which cannot notify: poll it.
            while (!stopping() && m_queue.empty() && !m_closing) m_changed.wait_for(lock, std::chrono::milliseconds(50));
            if (stopping() || m_queue.empty()) break;
            if constexpr (requires { m_run.stream; }) {
                if (!m_queue.front().predecessor) {
                    run_stream(lock);
                    continue;
                }
            }
            item it = std::move(m_queue.front());
            m_queue.pop_front();
            ++m_busy;
            lock.unlock();
            std::optional<Record> result;
            std::exception_ptr failure;
            const double t0 = m_timed ? thread_seconds() : 0.0;
            const auto w0 = std::chrono::steady_clock::now();
            try {
                result.emplace(
                    run_one<Record>(m_run, it.job, it.predecessor ? &*it.predecessor : static_cast<const Record*>(nullptr)));
            } catch (...) {
                failure = std::current_exception();
            }
            if (m_timed && result) m_timed(it.job, thread_seconds() - t0);
            const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
            lock.lock();
            --m_busy;
            m_wall += wall;
            ++m_done;
            if (failure && !m_failure) m_failure = failure;
            // A job that was running when the stop flag was set may have been cut short (its
            // flows poll the same flag and end early): it is not a result, and a journal must
            // not keep it, so a resume computes it again.
            if (result && !stopping()) m_inbox.emplace_back(it.job, std::move(*result));
            m_changed.notify_all();
        }
        m_changed.notify_all();
    }

    // Independent jobs from the queue, as the runner's lanes free up (called and returning
    // with the lock held); each job's time is its share of the thread's (job_shares).
    void run_stream(std::unique_lock<std::mutex>& lock)
    {
        lock.unlock();
        job_shares shares(static_cast<bool>(m_timed));
        auto next = [&]() -> std::optional<long> {
            long job = 0;
            {
                const std::lock_guard g(m_mutex);
                if (stopping() || m_queue.empty() || m_queue.front().predecessor) return std::nullopt;
                job = m_queue.front().job;
                m_queue.pop_front();
                ++m_busy;
            }
            shares.begin(job);  // the clocks outside the lock; no allocation (reserved)
            return job;
        };
        auto done = [&](long job, Record&& r) {
            const auto [cpu, wall] = shares.end(job);
            {
                const std::lock_guard g(m_mutex);
                --m_busy;
                m_wall += wall;
                ++m_done;
                // As for a job alone (work): a job running when the stop flag was set may have
                // been cut short, and is not a result.
                if (!stopping()) m_inbox.emplace_back(job, std::move(r));
                m_changed.notify_all();
            }
            if (m_timed) m_timed(job, cpu);
        };
        std::exception_ptr failure;
        try {
            m_run.stream(job_source(next), job_sink<Record>(done));
            if (shares.open() > 0) throw std::logic_error("a stream runner returned with jobs it had not finished");
        } catch (...) {
            failure = std::current_exception();
        }
        lock.lock();
        m_busy -= shares.open();  // taken, never ended: the runner failed
        if (failure && !m_failure) m_failure = failure;
        m_changed.notify_all();
    }

    Run& m_run;
    const std::atomic<bool>* m_stop;
    std::function<void(long, double)> m_timed;
    long m_batch = 1;
    mutable std::mutex m_mutex;
    std::condition_variable m_changed;
    std::deque<item> m_queue;
    std::vector<std::pair<long, Record>> m_inbox;
    long m_busy = 0;
    double m_wall = 0.0;
    long m_done = 0;
    bool m_closing = false;
    std::exception_ptr m_failure;
    std::vector<std::jthread> m_threads;
};

// How long a rank's main thread sleeps between looks at its messages: short after activity,
// doubling while nothing happens, up to 2 ms (each look costs CPU that the jobs' threads
// could use; a rank's prefetch covers the answer's delay).
class poll_interval {
public:
    std::chrono::microseconds next(bool active)
    {
        m_us = active ? 100 : std::min<long>(2 * m_us, 2000);
        return std::chrono::microseconds(m_us);
    }

private:
    long m_us = 100;
};

inline int rank_threads(const job_loop_options& opt)
{
    const int t = resolve_threads(opt.threads);
    if (opt.threads > 0 || !opt.ranks) return t;
    return std::max(1, t / std::max(1, opt.ranks->local_size()));
}

// A rank other than 0: asks for jobs, computes them with its threads, sends the results.
template <class Record, class Run>
job_loop_summary run_rank(const job_loop_options& opt, const job_loop_io<Record>& io, Run& run)
{
    job_ranks& ranks = *opt.ranks;
    job_loop_summary summary;
    summary.coordinator = false;
    summary.ranks = ranks.size();
    summary.threads = rank_threads(opt);
    ranks.send(0, tag_hello, std::to_string(summary.threads));
    for (;;) {  // the journal is opened on rank 0 before the jobs begin, and may be refused
        if (auto m = ranks.receive()) {
            if (m->tag == tag_start) break;
            if (m->tag == tag_abort) std::rethrow_exception(failure_from(m->bytes, 0));
        }
        std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    using pool_t = job_pool<Record, Run>;
    pool_t pool(summary.threads, run, opt.stop, opt.timed, opt.batch);
    // Prefetch: ask when half the rank's capacity is held (running and queued), for enough
    // to fill it (rank_capacity: more jobs when they are short), so the threads never wait
    // for the answer. Results go with the requests, or when half a capacity of them or 0.1 s
    // has gathered: few messages for rank 0, and little lost if this rank is killed.
    bool asked = false, no_more = false, stop = false, bye = false;
    std::exception_ptr failure;
    std::string lines;
    long unsent = 0;
    poll_interval poll;
    bool active = false;
    auto oldest = std::chrono::steady_clock::now();
    for (;;) {
        const long capacity = rank_capacity(summary.threads, pool.mean_job_seconds(), pool.batch());
        // Held before the results are taken: a job done meanwhile is then among them.
        const long held = pool.held();
        active = false;
        for (auto& [job, r] : pool.take()) {
            active = true;
            if (unsent == 0) oldest = std::chrono::steady_clock::now();
            lines += io.encode(job, r);
            lines += '\n';
            ++unsent;
            ++summary.computed;
        }
        if (!failure && (failure = pool.failure())) {
            ranks.send(0, tag_failed, failure_text(failure));
            stop = true;
        }
        if (opt.stop && opt.stop->load()) stop = true;
        const bool leaving = (stop || no_more) && held == 0;
        const long want = stop || no_more || asked || held > capacity / 2 ? 0 : capacity - held;
        const bool due = unsent > 0 && (stop || 2 * unsent >= capacity ||
                                         std::chrono::steady_clock::now() - oldest > std::chrono::milliseconds(100));
        if (due || want > 0 || leaving) {
            ranks.send(0, tag_report, std::to_string(want) + " " + (leaving ? "1" : "0") + "\n" + lines);
            lines.clear();
            unsent = 0;
            if (want > 0) asked = true;
        }
        if (leaving) break;
        while (auto m = ranks.receive()) {
            active = true;
            if (m->tag == tag_grant) {
                asked = false;
                if (m->bytes.empty()) {
                    no_more = true;
                    continue;
                }
                std::vector<typename pool_t::item> items;
                std::string_view rest(m->bytes);
                while (!rest.empty()) {
                    const auto nl = rest.find('\n');
                    std::string_view line = rest.substr(0, nl);
                    rest.remove_prefix(nl == std::string_view::npos ? rest.size() : nl + 1);
                    const auto sp = line.find(' ');
                    typename pool_t::item it{std::stol(std::string(line.substr(0, sp))), std::nullopt};
                    if (sp != std::string_view::npos) it.predecessor.emplace(io.decode(line.substr(sp + 1)).second);
                    items.push_back(std::move(it));
                }
                if (!stop) pool.push(std::move(items));
            } else if (m->tag == tag_stop) {
                stop = true;
            } else if (m->tag == tag_bye) {  // rank 0 stopped waiting for this rank's report
                stop = true;
                bye = true;
            }
        }
        if (stop) {
            // Running jobs end (and are reported); queued ones are left for a resume.
            pool.close(true);
        }
        pool.wait(poll.next(active));
    }
    pool.close(true);
    ranks.flush();
    while (!bye) {
        while (auto m = ranks.receive()) bye = bye || m->tag == tag_bye;
        if (!bye) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    summary.stopped = stop;
    if (failure) std::rethrow_exception(failure);
    return summary;
}

}  // namespace detail

// Run(job, const Record* predecessor_or_null) -> Record;  Sink(job, Record&&), called on the
// calling thread of rank 0 in ascending job order for the jobs this call computed.
template <class Record, class Run, class Sink>
job_loop_summary run_jobs(const job_schedule& schedule, const job_loop_options& opt, const job_loop_io<Record>& io,
                          Run&& run, Sink&& sink)
{
    validate(opt.shard);
    if (schedule.jobs < 0 || schedule.chains < 0) throw input_error("job count must be >= 0");
    if (opt.ranks && opt.ranks->rank() != 0) return detail::run_rank<Record>(opt, io, run);

    job_loop_summary summary;
    auto finished = [&](long j) { return io.finished && io.finished(j); };
    long todo_count = 0;
    for (long j = 0; j < schedule.jobs; ++j) {
        if (!opt.shard.owns_chain(schedule.chain_of(j))) continue;
        ++summary.owned;
        if (finished(j)) ++summary.resumed;
        else ++todo_count;
    }
    auto todo = [&](long j) { return opt.shard.owns_chain(schedule.chain_of(j)) && !finished(j); };

    // The other ranks say how many threads they have; then the jobs begin.
    job_ranks* ranks = opt.ranks.get();
    const int nranks = ranks ? ranks->size() : 1;
    summary.ranks = nranks;
    std::vector<long> rank_threads(static_cast<std::size_t>(nranks), 0);
    int hellos = 0;
    while (hellos < nranks - 1) {
        if (auto m = ranks->receive()) {
            if (m->tag == detail::tag_hello) {
                rank_threads[static_cast<std::size_t>(m->from)] = std::stol(m->bytes);
                ++hellos;
            }
        } else {
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
    }
    for (int r = 1; r < nranks; ++r) ranks->send(r, detail::tag_start, {});

    const int own_threads =
        todo_count == 0 ? 1 : static_cast<int>(std::min<long>(detail::rank_threads(opt), std::max(1L, todo_count)));
    summary.threads = own_threads;
    rank_threads[0] = own_threads;
    long all_threads = 0;
    for (const long t : rank_threads) all_threads += t;
    const long batch = schedule.chained() ? 1L : std::max(1L, opt.batch);
    // The own threads hold `hold` batches each: with lanes, three, so that a batch still waits
    // behind full lanes when they are topped up. The window has room for that, and by default,
    // with lanes, for 16 batches per thread: a lane's slow job (near grazing, 8 times the mean)
    // must not hold the others back while they run a hundred jobs past it.
    const long hold = batch > 1 ? 3 : 2;
    const long per_thread = std::max(nranks > 1 ? ranks_window_per_thread : 8L, batch > 1 ? 16 * batch : 0L);
    const long window = std::max(opt.window > 0 ? opt.window : per_thread * all_threads, hold * batch * all_threads);
    // With shards a window of jobs spans fewer of this shard's: widen it by the shard count.
    job_dispenser dispenser(schedule, todo, todo_count, window * opt.shard.count, all_threads, 2, batch);

    using pool_t = detail::job_pool<Record, Run>;
    pool_t pool(own_threads, run, opt.stop, opt.timed, batch);
    std::map<long, Record> ready;                  // arrived, waiting for in-order delivery
    std::unordered_map<long, Record> successors;   // chained results still needed as predecessors
    std::vector<long> wants(static_cast<std::size_t>(nranks), 0);
    std::vector<bool> gone(static_cast<std::size_t>(nranks), false);
    gone[0] = true;
    int remote_left = nranks - 1;
    long next_delivery = dispenser.next_todo(0);
    long outstanding = 0;  // handed out, not arrived
    std::exception_ptr failure;
    bool stopping = false;
    auto stop_requested = [&] { return opt.stop && opt.stop->load(); };

    auto predecessor_of = [&](long job) -> std::optional<Record> {
        const long p = schedule.predecessor(job);
        if (p < 0) return std::nullopt;
        if (auto s = successors.find(p); s != successors.end()) {
            std::optional<Record> r(std::move(s->second));
            successors.erase(s);
            return r;
        }
        return io.load(p);
    };
    auto arrive = [&](long job, Record&& r, const std::string* line) {
        try {
            if (io.arrived) io.arrived(job, r, line);
        } catch (...) {
            if (!failure) failure = std::current_exception();
        }
        dispenser.completed(job);
        if (schedule.chained() && job + schedule.chains < schedule.jobs) successors.emplace(job, r);
        ready.emplace(job, std::move(r));
        --outstanding;
    };
    auto stop_all = [&] {
        if (stopping) return;
        stopping = true;
        for (int r = 1; r < nranks; ++r)
            if (!gone[static_cast<std::size_t>(r)]) ranks->send(r, detail::tag_stop, {});
    };
    auto deliver = [&] {
        while (!failure) {
            auto node = ready.extract(next_delivery);
            if (node.empty()) return;
            next_delivery = dispenser.next_todo(next_delivery + 1);
            dispenser.delivered_below(next_delivery);
            try {
                sink(node.key(), std::move(node.mapped()));
            } catch (...) {
                failure = std::current_exception();
                return;
            }
            ++summary.computed;
            if (opt.progress) opt.progress(summary.resumed + summary.computed, summary.owned);
        }
    };
    // A stop or a failure waits this long for the other ranks' last reports (a rank killed
    // by a signal never sends one).
    std::optional<std::chrono::steady_clock::time_point> stop_deadline;
    detail::poll_interval poll;

    for (;;) {
        bool busy = false;
        for (auto& [job, r] : pool.take()) {
            arrive(job, std::move(r), nullptr);
            busy = true;
        }
        if (!failure) failure = pool.failure();
        while (ranks) {
            auto m = ranks->receive();
            if (!m) break;
            busy = true;
            const auto from = static_cast<std::size_t>(m->from);
            if (m->tag == detail::tag_report) {
                std::string_view rest(m->bytes);
                const auto nl = rest.find('\n');
                std::string_view head = rest.substr(0, nl);
                rest.remove_prefix(nl == std::string_view::npos ? rest.size() : nl + 1);
                const auto sp = head.find(' ');
                wants[from] += std::stol(std::string(head.substr(0, sp)));  // a report without a request: 0
                const bool leaving = head.substr(sp + 1) == "1";
                while (!rest.empty()) {
                    const auto e = rest.find('\n');
                    const std::string line(rest.substr(0, e));
                    rest.remove_prefix(e == std::string_view::npos ? rest.size() : e + 1);
                    auto [job, r] = io.decode(line);
                    arrive(job, std::move(r), &line);
                }
                if (leaving && !gone[from]) {
                    gone[from] = true;
                    --remote_left;
                    // A rank that leaves before the list is done was stopped (its own signal):
                    // the whole run stops, and a resume finishes it.
                    if (!dispenser.exhausted()) stop_all();
                }
            } else if (m->tag == detail::tag_failed) {
                if (!failure) failure = detail::failure_from(m->bytes, m->from);
            }
        }
        if (busy && io.flush) {
            try {
                io.flush();
            } catch (...) {
                if (!failure) failure = std::current_exception();
            }
        }
        if ((failure || stop_requested()) && !stopping) {
            stop_all();
            pool.close(true);
        }
        if (stopping) {
            if (!stop_deadline) stop_deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
            if (remote_left == 0 || std::chrono::steady_clock::now() > *stop_deadline) break;
        } else {
            // Hand out: the own threads first (no message), then the ranks that asked. The
            // own threads hold `hold` batches each (a batch: the jobs a thread runs together in
            // its SIMD lanes), and are topped up a whole batch at a time.
            const long own_want = hold * batch * own_threads - pool.held();
            if (own_want >= std::max(batch, static_cast<long>(own_threads))) {
                auto jobs = dispenser.grant(own_want);
                if (!jobs.empty()) {
                    std::vector<typename pool_t::item> items;
                    for (const long j : jobs) items.push_back({j, predecessor_of(j)});
                    outstanding += static_cast<long>(jobs.size());
                    pool.push(std::move(items));
                    busy = true;
                }
            }
            for (int r = 1; r < nranks; ++r) {
                auto& want = wants[static_cast<std::size_t>(r)];
                if (want <= 0 || gone[static_cast<std::size_t>(r)]) continue;
                if (dispenser.exhausted()) {
                    ranks->send(r, detail::tag_grant, {});  // no more: it leaves when its jobs are done
                    want = 0;
                    continue;
                }
                const auto jobs = dispenser.grant(want);
                if (jobs.empty()) continue;  // the window or a chain: later
                std::string text;
                for (const long j : jobs) {
                    text += std::to_string(j);
                    if (auto p = predecessor_of(j)) {
                        text += ' ';
                        text += io.encode(schedule.predecessor(j), *p);
                    }
                    text += '\n';
                }
                outstanding += static_cast<long>(jobs.size());
                ranks->send(r, detail::tag_grant, std::move(text));
                want = 0;
                busy = true;
            }
            deliver();
            if (failure) continue;
            if (dispenser.exhausted() && outstanding == 0 && remote_left == 0) break;
        }
        const auto pause = poll.next(busy);
        if (!busy) pool.wait(ranks ? pause : std::chrono::microseconds(50'000));
    }
    pool.close(true);
    for (auto& [job, r] : pool.take()) arrive(job, std::move(r), nullptr);
    if (io.flush && !failure) io.flush();
    // After a stop: hand over what did finish, in ascending order, so a resume keeps it.
    if (!failure) {
        deliver();
        while (!ready.empty() && !failure) {
            next_delivery = ready.begin()->first;
            deliver();
        }
    }
    if (ranks) {
        for (int r = 1; r < nranks; ++r)
            ranks->send(r, detail::tag_bye, {});
        ranks->flush();
    }
    if (failure) std::rethrow_exception(failure);
    summary.stopped = summary.resumed + summary.computed < summary.owned;
    return summary;
}

}  // namespace vimpact
