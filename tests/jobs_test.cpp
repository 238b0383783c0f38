// The job loop: order, determinism across thread counts, chains, shards, resume, stop, errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <tuple>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "jobs/journal.hpp"
#include "jobs/job_loop.hpp"
#include "vimpact/jobs/job_ranks.hpp"

namespace {

using vimpact::job_loop_options;
using vimpact::job_schedule;
using vimpact::run_jobs;

// A job whose duration varies (so threads finish out of order) and whose value depends only
// on its index and predecessor.
double value(long job, const double* prev) { return (prev ? *prev : 0.0) * 0.5 + std::sin(static_cast<double>(job)); }

double work(long job, const double* prev)
{
    std::this_thread::sleep_for(std::chrono::microseconds(50 * ((job * 7919) % 13)));
    return value(job, prev);
}

std::vector<std::pair<long, double>> collect(const job_schedule& s, job_loop_options o,
                                             const std::unordered_map<long, double>& done = {})
{
    std::vector<std::pair<long, double>> out;
    run_jobs<double>(s, o, vimpact::finished_in(done), work, [&](long j, double&& v) { out.emplace_back(j, v); });
    return out;
}

TEST(JobLoop, DeliversEveryJobInOrderWhateverTheThreadCount)
{
    const job_schedule s{200, 0};
    job_loop_options o;
    o.threads = 1;
    const auto one = collect(s, o);
    ASSERT_EQ(one.size(), 200u);
    for (long j = 0; j < 200; ++j) EXPECT_EQ(one[static_cast<std::size_t>(j)].first, j);
    for (int t : {2, 3, 8}) {
        o.threads = t;
        o.window = 3;  // a small window forces workers to wait for delivery
        EXPECT_EQ(collect(s, o), one) << t << " threads";
    }
}

TEST(JobLoop, ChainedJobsSeeTheirPredecessor)
{
    // Two interleaved chains (an upward and a downward sweep): job j continues from j - 2.
    const job_schedule s{40, 2};
    job_loop_options o;
    o.threads = 1;
    const auto one = collect(s, o);
    o.threads = 4;
    const auto four = collect(s, o);
    EXPECT_EQ(one, four);
    double expect0 = 0.0, expect1 = 0.0;
    for (long j = 0; j < 40; ++j) {
        double& e = j % 2 ? expect1 : expect0;
        e = e * 0.5 + std::sin(static_cast<double>(j));
        EXPECT_DOUBLE_EQ(one[static_cast<std::size_t>(j)].second, e) << j;
    }
}

TEST(JobLoop, ShardsPartitionTheJobsAndTogetherEqualTheWhole)
{
    for (const job_schedule s : {job_schedule{37, 0}, job_schedule{37, 3}}) {
        job_loop_options o;
        o.threads = 2;
        const auto whole = collect(s, o);
        std::map<long, double> merged;
        for (long i = 0; i < 4; ++i) {
            o.shard = {i, 4};
            // A shard of a chained run computes its chains from their start, so the values agree.
            for (const auto& [j, v] : collect(s, o)) {
                EXPECT_TRUE(merged.emplace(j, v).second) << "job " << j << " in two shards";
                EXPECT_EQ(s.chain_of(j) % 4, i);
            }
        }
        ASSERT_EQ(merged.size(), whole.size());
        for (const auto& [j, v] : whole) EXPECT_EQ(merged.at(j), v);
    }
}

TEST(JobLoop, ResumeSkipsFinishedJobsAndChainsContinueFromThem)
{
    const job_schedule s{30, 1};
    job_loop_options o;
    o.threads = 2;
    const auto whole = collect(s, o);
    std::unordered_map<long, double> done;
    for (long j = 0; j < 12; ++j) done.emplace(j, whole[static_cast<std::size_t>(j)].second);
    const auto rest = collect(s, o, done);
    ASSERT_EQ(rest.size(), 18u);
    for (std::size_t k = 0; k < rest.size(); ++k) EXPECT_EQ(rest[k], whole[k + 12]);
}

// A stop delivers what finished before it and nothing that was still running (such a job may
// have been cut short by the same flag, so a resume must compute it again).
TEST(JobLoop, StopKeepsJobsFinishedBeforeItAndDropsRunningOnes)
{
    std::atomic<bool> stop{false};
    const job_schedule s{400, 0};
    job_loop_options o;
    o.threads = 2;
    o.stop = &stop;
    std::mutex mutex;
    std::set<long> finished_before_stop;
    std::vector<long> got;
    const auto summary = run_jobs<double>(
        s, o, {},
        [&](long j, const double*) {
            if (j == 50) stop.store(true);
            const double v = work(j, nullptr);
            if (!stop.load()) {
                const std::lock_guard lock(mutex);
                finished_before_stop.insert(j);
            }
            return v;
        },
        [&](long j, double&&) { got.push_back(j); });
    EXPECT_TRUE(summary.stopped);
    EXPECT_GE(got.size(), 40u);  // with 2 threads, every job up to about 48 ended before job 50 began
    EXPECT_TRUE(std::is_sorted(got.begin(), got.end()));
    for (const long j : got) EXPECT_TRUE(finished_before_stop.count(j)) << "job " << j << " ended after the stop";
    EXPECT_EQ(std::find(got.begin(), got.end(), 50L), got.end());
    EXPECT_EQ(summary.computed, static_cast<long>(got.size()));
}

TEST(JobLoop, AJobsExceptionReachesTheCaller)
{
    job_loop_options o;
    o.threads = 2;
    auto run = [](long j, const double*) -> double {
        if (j == 17) throw std::runtime_error("job 17 failed");
        return 1.0;
    };
    EXPECT_THROW(run_jobs<double>(job_schedule{100, 0}, o, {}, run, [](long, double&&) {}), std::runtime_error);
    auto bad_sink = [](long j, double&&) {
        if (j == 5) throw std::runtime_error("disk full");
    };
    EXPECT_THROW(run_jobs<double>(job_schedule{100, 0}, o, {}, [](long, const double*) { return 1.0; }, bad_sink),
                 std::runtime_error);
}

TEST(JobLoop, RejectsInvalidShards)
{
    job_loop_options o;
    o.shard = {3, 3};
    EXPECT_THROW(collect(job_schedule{5, 0}, o), vimpact::input_error);
    o.shard = {0, 0};
    EXPECT_THROW(collect(job_schedule{5, 0}, o), vimpact::input_error);
}

// ---- ranks -----------------------------------------------------------------------------
// The job loop across ranks, the ranks being threads of this process that exchange the same
// messages as MPI ranks do (jobs/job_ranks.hpp): the protocol is tested with or without MPI.

struct mail_hub {
    std::mutex mutex;
    std::vector<std::deque<vimpact::rank_message>> boxes;
};

class local_ranks final : public vimpact::job_ranks {
public:
    local_ranks(mail_hub& hub, int rank) : m_hub(hub), m_rank(rank) {}
    [[nodiscard]] int rank() const override { return m_rank; }
    [[nodiscard]] int size() const override { return static_cast<int>(m_hub.boxes.size()); }
    void send(int to, int tag, std::string bytes) override
    {
        const std::lock_guard lock(m_hub.mutex);
        m_hub.boxes[static_cast<std::size_t>(to)].push_back({m_rank, tag, std::move(bytes)});
    }
    std::optional<vimpact::rank_message> receive() override
    {
        const std::lock_guard lock(m_hub.mutex);
        auto& box = m_hub.boxes[static_cast<std::size_t>(m_rank)];
        if (box.empty()) return std::nullopt;
        auto m = std::move(box.front());
        box.pop_front();
        return m;
    }
    void flush() override {}

private:
    mail_hub& m_hub;
    int m_rank;
};

// The wire form of a double record: "job value" with every bit of the value.
vimpact::job_loop_io<double> wire()
{
    vimpact::job_loop_io<double> io;
    io.encode = [](long j, const double& v) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%ld %a", j, v);
        return std::string(buf);
    };
    io.decode = [](std::string_view line) {
        const std::string s(line);
        const auto sp = s.find(' ');
        return std::pair<long, double>(std::stol(s.substr(0, sp)), std::strtod(s.c_str() + sp + 1, nullptr));
    };
    return io;
}

struct ranks_run {
    std::vector<std::pair<long, double>> delivered;  // by rank 0
    std::vector<vimpact::job_loop_summary> summaries;
    std::vector<std::string> errors;                 // per rank, empty when it returned
};

template <class Run>
ranks_run run_ranks(int n, const job_schedule& s, job_loop_options o, Run run)
{
    mail_hub hub;
    hub.boxes.resize(static_cast<std::size_t>(n));
    ranks_run out;
    out.summaries.resize(static_cast<std::size_t>(n));
    out.errors.resize(static_cast<std::size_t>(n));
    std::vector<std::jthread> threads;
    for (int r = 0; r < n; ++r)
        threads.emplace_back([&, r] {
            job_loop_options mine = o;
            mine.ranks = std::make_shared<local_ranks>(hub, r);
            try {
                out.summaries[static_cast<std::size_t>(r)] = run_jobs<double>(
                    s, mine, wire(), run, [&](long j, double&& v) { out.delivered.emplace_back(j, v); });
            } catch (const std::exception& e) {
                out.errors[static_cast<std::size_t>(r)] = e.what();
            }
        });
    threads.clear();  // joins
    return out;
}

TEST(JobLoopRanks, EveryJobOnceInOrderAndBitForBitWhateverTheRanksAndThreads)
{
    for (const job_schedule s : {job_schedule{300, 0}, job_schedule{60, 2}}) {
        job_loop_options o;
        o.threads = 1;
        const auto one = collect(s, o);
        for (const auto& [ranks, threads, window] : {std::tuple{2, 1, 0L}, std::tuple{3, 2, 0L}, std::tuple{4, 1, 3L}}) {
            o.threads = threads;
            o.window = window;
            const auto r = run_ranks(ranks, s, o, work);
            EXPECT_EQ(r.delivered, one) << ranks << " ranks x " << threads << " threads, chains " << s.chains;
            for (const auto& e : r.errors) EXPECT_EQ(e, "");
            EXPECT_TRUE(r.summaries[0].coordinator);
            EXPECT_EQ(r.summaries[0].computed, s.jobs);
            long remote = 0;
            for (int k = 1; k < ranks; ++k) {
                EXPECT_FALSE(r.summaries[static_cast<std::size_t>(k)].coordinator);
                remote += r.summaries[static_cast<std::size_t>(k)].computed;
            }
            if (!s.chained()) {
                EXPECT_GT(remote, 0) << "the other ranks computed nothing";
            }
        }
    }
}

// A stream runner as SIMD lanes run one: up to `width` jobs at once, in rounds of 50 us; job
// j lasts (j * 7919) % 13 + 1 rounds, and a lane whose job ends takes the next at once.
struct lanes_log {
    std::mutex mutex;
    std::vector<long> taken;  // jobs per stream call
    long most_at_once = 0;
};

auto lanes_stream(long width, lanes_log& log)
{
    return [width, &log](const vimpact::job_source& next, const vimpact::job_sink<double>& done) {
        std::vector<std::pair<long, long>> lanes;  // job, rounds left
        long taken = 0;
        for (;;) {
            while (static_cast<long>(lanes.size()) < width) {
                const std::optional<long> j = next();
                if (!j) break;
                lanes.emplace_back(*j, (*j * 7919) % 13 + 1);
                ++taken;
            }
            {
                const std::lock_guard lock(log.mutex);
                log.most_at_once = std::max(log.most_at_once, static_cast<long>(lanes.size()));
            }
            if (lanes.empty()) break;
            std::this_thread::sleep_for(std::chrono::microseconds(50));
            for (auto it = lanes.begin(); it != lanes.end();) {
                if (--it->second > 0) {
                    ++it;
                    continue;
                }
                done(it->first, value(it->first, nullptr));
                it = lanes.erase(it);
            }
        }
        const std::lock_guard lock(log.mutex);
        log.taken.push_back(taken);
    };
}

// Stream runners (SIMD lanes) take their jobs from the queue of their rank as lanes free up:
// a thread's lanes stay full through the list instead of waiting, batch after batch, for a
// batch's longest job. Every job is still delivered once, in order, with the value a job
// alone gives, on one rank or two.
TEST(JobLoopRanks, StreamRunnersRefillTheirLanesFromTheSharedQueue)
{
    constexpr long batch = 8, jobs = 400;
    const job_schedule s{jobs, 0};
    job_loop_options o;
    o.threads = 1;
    const auto one = collect(s, o);
    for (const int ranks : {1, 2}) {
        lanes_log log;
        const vimpact::job_streamer runner{lanes_stream(batch, log)};
        o.batch = batch;
        // A window that is not a whole number of batches cuts grants short.
        o.window = 4 * batch + 3;
        const auto r = ranks == 1 ? ranks_run{} : run_ranks(ranks, s, o, runner);
        std::vector<std::pair<long, double>> delivered = r.delivered;
        if (ranks == 1) run_jobs<double>(s, o, {}, runner, [&](long j, double&& v) { delivered.emplace_back(j, v); });
        EXPECT_EQ(delivered, one) << ranks << " rank(s)";
        long total = 0, most = 0;
        for (const long n : log.taken) {
            total += n;
            most = std::max(most, n);
        }
        EXPECT_EQ(total, jobs) << ranks << " rank(s)";
        EXPECT_EQ(log.most_at_once, batch) << ranks << " rank(s)";
        // A stream call that took no more than a batch would be the fixed batches this replaced.
        EXPECT_GT(most, 4 * batch) << ranks << " rank(s): " << log.taken.size() << " stream calls";
    }
}

// A stream runner's failure, on rank 0's threads or another rank's, ends the run with its
// error on every rank; a stop takes no new job into the lanes and delivers, in order, only
// what ended before it.
TEST(JobLoopRanks, AStreamRunnersFailureOrStopEndsTheRun)
{
    constexpr long batch = 8;
    const job_schedule s{300, 0};
    for (const int ranks : {1, 2}) {
        job_loop_options o;
        o.threads = 1;
        o.batch = batch;
        lanes_log log;
        auto lanes = lanes_stream(batch, log);
        const vimpact::job_streamer failing{[&](const vimpact::job_source& next, const vimpact::job_sink<double>& done) {
            lanes(
                [&]() -> std::optional<long> {
                    const std::optional<long> j = next();
                    if (j && *j == 137) throw vimpact::input_error("job 137 failed");
                    return j;
                },
                done);
        }};
        if (ranks == 1) {
            EXPECT_THROW(run_jobs<double>(s, o, {}, failing, [](long, double&&) {}), vimpact::input_error);
        } else {
            const auto r = run_ranks(ranks, s, o, failing);
            EXPECT_NE(r.errors[0].find("job 137 failed"), std::string::npos) << r.errors[0];
        }
    }
    std::atomic<bool> stop{false};
    job_loop_options o;
    o.threads = 2;
    o.batch = batch;
    o.stop = &stop;
    lanes_log log;
    auto lanes = lanes_stream(batch, log);
    std::mutex mutex;
    std::set<long> ended_before_stop;
    const vimpact::job_streamer stopping{[&](const vimpact::job_source& next, const vimpact::job_sink<double>& done) {
        lanes(
            [&]() -> std::optional<long> {
                const std::optional<long> j = next();
                if (j && *j == 100) stop.store(true);
                return j;
            },
            [&](long j, double&& v) {
                if (!stop.load()) {
                    const std::lock_guard lock(mutex);
                    ended_before_stop.insert(j);
                }
                done(j, std::move(v));
            });
    }};
    std::vector<long> got;
    const auto summary = run_jobs<double>(s, o, {}, stopping, [&](long j, double&&) { got.push_back(j); });
    EXPECT_TRUE(summary.stopped);
    EXPECT_GE(got.size(), 40u);
    EXPECT_LT(got.size(), 100u);
    EXPECT_TRUE(std::is_sorted(got.begin(), got.end()));
    for (const long j : got) EXPECT_TRUE(ended_before_stop.count(j)) << "job " << j << " ended after the stop";
}

// A job that continues from another goes to the runner's `single`, the others to its stream.
TEST(JobLoop, ChainedJobsOfAStreamRunnerRunAlone)
{
    const job_schedule s{60, 3};
    job_loop_options o;
    o.threads = 2;
    o.batch = 4;
    const auto expected = collect(s, o);
    lanes_log log;
    auto single = [](long j, const double* p) { return value(j, p); };
    std::vector<std::pair<long, double>> got;
    run_jobs<double>(s, o, {}, vimpact::job_runners{single, lanes_stream(4, log)},
                     [&](long j, double&& v) { got.emplace_back(j, v); });
    EXPECT_EQ(got, expected);
}

// A resumed run in lanes whose windows hold less than a batch still to compute ends, and
// delivers exactly the jobs left. A watchdog sets the stop flag after 60 s, so a dispenser
// that waits forever fails the test instead of hanging it.
TEST(JobLoopRanks, AResumedRunInBatchesWithFewJobsLeftEnds)
{
    constexpr long jobs = 600;
    const job_schedule s{jobs, 0};
    std::unordered_map<long, double> done;
    for (long j = 0; j < jobs; ++j)
        if (j % 37 != 0) done[j] = work(j, nullptr);
    lanes_log log;
    const vimpact::job_streamer runner{lanes_stream(8, log)};
    job_loop_options o;
    o.threads = 1;
    o.batch = 8;
    std::vector<std::pair<long, double>> expected;
    for (long j = 0; j < jobs; j += 37) expected.emplace_back(j, work(j, nullptr));
    std::atomic<bool> stop{false};
    o.stop = &stop;
    std::vector<std::pair<long, double>> one;
    vimpact::job_loop_summary summary;
    {
        std::mutex m;
        std::condition_variable finished;
        bool over = false;
        std::jthread watchdog([&] {
            std::unique_lock lock(m);
            if (!finished.wait_for(lock, std::chrono::seconds(60), [&] { return over; })) stop = true;
        });
        summary = run_jobs<double>(s, o, vimpact::finished_in(done), runner,
                                   [&](long j, double&& v) { one.emplace_back(j, v); });
        {
            const std::lock_guard lock(m);
            over = true;
        }
        finished.notify_all();
    }
    EXPECT_FALSE(summary.stopped) << "the run waited 60 s for jobs it was never granted";
    EXPECT_EQ(one, expected);
}

TEST(JobLoopRanks, MoreRanksThanJobs)
{
    job_loop_options o;
    o.threads = 1;
    const auto r = run_ranks(5, job_schedule{2, 0}, o, work);
    EXPECT_EQ(r.delivered, collect(job_schedule{2, 0}, o));
    for (const auto& e : r.errors) EXPECT_EQ(e, "");
}

TEST(JobLoopRanks, ResumedJobsAreNotComputedAgain)
{
    const job_schedule s{40, 1};
    job_loop_options o;
    o.threads = 2;
    const auto whole = collect(s, o);
    std::unordered_map<long, double> done;
    for (long j = 0; j < 15; ++j) done.emplace(j, whole[static_cast<std::size_t>(j)].second);
    mail_hub hub;
    hub.boxes.resize(2);
    std::vector<std::pair<long, double>> got;
    std::jthread other([&] {
        job_loop_options mine = o;
        mine.ranks = std::make_shared<local_ranks>(hub, 1);
        (void)run_jobs<double>(s, mine, wire(), work, [](long, double&&) {});
    });
    job_loop_options mine = o;
    mine.ranks = std::make_shared<local_ranks>(hub, 0);
    auto io = wire();
    const auto f = vimpact::finished_in(done);
    io.finished = f.finished;
    io.load = f.load;
    const auto summary = run_jobs<double>(s, mine, io, work, [&](long j, double&& v) { got.emplace_back(j, v); });
    EXPECT_EQ(summary.resumed, 15);
    ASSERT_EQ(got.size(), 25u);
    for (std::size_t k = 0; k < got.size(); ++k) EXPECT_EQ(got[k], whole[k + 15]);
}

TEST(JobLoopRanks, AJobsFailureOnAnyRankReachesRankZeroAndEveryRankEnds)
{
    job_loop_options o;
    o.threads = 1;
    const auto r = run_ranks(3, job_schedule{100, 0}, o, [](long j, const double* p) {
        if (j == 37) throw vimpact::input_error("job 37 failed");
        return work(j, p);
    });
    EXPECT_NE(r.errors[0].find("job 37 failed"), std::string::npos) << r.errors[0];
}

TEST(JobLoopRanks, RanksGivenDifferentSpecsAreRefusedBeforeAnyJobNamingTheDifference)
{
    using json = nlohmann::json;
    const json spec = {{"analysis", "sweep"}, {"values", {{"from", 12.0}, {"n", 131}, {"to", 25.0}}}};
    json other = spec;
    other["values"]["to"] = 26.0;
    for (const bool differ : {false, true}) {
        mail_hub hub;
        hub.boxes.resize(3);
        std::vector<std::string> errors(3);
        {
            std::vector<std::jthread> threads;
            for (int r = 0; r < 3; ++r)
                threads.emplace_back([&, r] {
                    local_ranks ranks(hub, r);
                    try {
                        vimpact::detail::check_same_run(ranks, differ && r == 2 ? other : spec);
                    } catch (const vimpact::input_error& e) {
                        errors[static_cast<std::size_t>(r)] = e.what();
                    }
                });
        }
        if (!differ) {
            for (const auto& e : errors) EXPECT_EQ(e, "");
            continue;
        }
        // Every rank ends with rank 0's message (exit code 2 on each).
        for (const auto& e : errors) EXPECT_EQ(e, errors[0]);
        EXPECT_EQ(errors[0], "MPI rank 2 was started with another run than rank 0 (values/to: 25.0 on rank 0, 26.0 on "
                             "rank 2): start every rank with the same command and options");
    }
    EXPECT_NE(vimpact::detail::spec_hash(spec), vimpact::detail::spec_hash(other));
    EXPECT_EQ(vimpact::detail::spec_hash(spec), vimpact::detail::spec_hash(json::parse(spec.dump())));
}

// ---- the dispenser's grants and a rank's capacity --------------------------------------
// Jobs for SIMD lanes are handed out and held in whole batches (a rank's request then keeps
// its lanes full with a batch to spare), and only the end of the list in a smaller piece.

TEST(JobDispenser, GrantsWholeGranulesUntilTheListEndsAndEveryJobOnce)
{
    constexpr long jobs = 1003, granule = 8;
    vimpact::job_dispenser d(job_schedule{jobs, 0}, [](long) { return true; }, jobs, jobs, 3, 2, granule);
    std::vector<long> order;
    const long wants[] = {16, 8, 40, 5, 24};
    for (int k = 0; !d.exhausted() && k < 10000; ++k) {
        const long want = wants[k % 5];
        const auto g = d.grant(want);
        ASSERT_FALSE(g.empty());
        const long n = static_cast<long>(g.size());
        EXPECT_LE(n, want);
        const bool last = g.back() == jobs - 1;
        if (want >= granule && !last) {
            EXPECT_EQ(n % granule, 0) << "grant " << k << " of " << n << " jobs for a want of " << want;
        }
        order.insert(order.end(), g.begin(), g.end());
    }
    ASSERT_EQ(static_cast<long>(order.size()), jobs);
    for (long j = 0; j < jobs; ++j) EXPECT_EQ(order[static_cast<std::size_t>(j)], j);
}

TEST(JobDispenser, AGrantCutByTheWindowKeepsWholeGranules)
{
    // Window 20 ahead of the first undelivered job, granule 8.
    vimpact::job_dispenser d(job_schedule{100, 0}, [](long) { return true; }, 100, 20, 1, 1, 8);
    EXPECT_EQ(d.grant(16), std::vector<long>({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15}));
    EXPECT_TRUE(d.grant(16).empty());  // only 16 .. 19 fit: half a granule, kept for later
    EXPECT_EQ(d.unassigned(), 84);
    d.delivered_below(8);              // the window now ends before 28: one granule fits
    EXPECT_EQ(d.grant(16), std::vector<long>({16, 17, 18, 19, 20, 21, 22, 23}));
    EXPECT_EQ(d.unassigned(), 76);
}

TEST(JobDispenser, AResumedRunWithFewJobsLeftInTheWindowStillProgresses)
{
    // Every 50th job left to compute, a window of 16 jobs, granule 8: a window never holds a
    // granule, and with nothing out a grant must still give what it holds.
    constexpr long jobs = 1000;
    auto todo = [](long j) { return j % 50 == 0; };
    vimpact::job_dispenser d(job_schedule{jobs, 0}, todo, jobs / 50, 16, 1, 2, 8);
    std::vector<long> got;
    for (int k = 0; !d.exhausted() && k < 1000; ++k) {
        const auto g = d.grant(16);
        ASSERT_FALSE(g.empty()) << "no job granted with none out, after " << got.size();
        got.insert(got.end(), g.begin(), g.end());
        d.delivered_below(d.next_todo(g.back() + 1));  // every granted job delivered
    }
    ASSERT_EQ(got.size(), 20u);
    for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], 50 * static_cast<long>(i));
}

TEST(JobDispenser, GuidedShareShrinksTowardsTheEnd)
{
    // granule 1: ceil(unassigned / (2 threads)) at most, so later grants are smaller.
    vimpact::job_dispenser d(job_schedule{100, 0}, [](long) { return true; }, 100, 100, 2, 2, 1);
    EXPECT_EQ(d.grant(1000).size(), 25u);  // ceil(100 / 4)
    EXPECT_EQ(d.grant(1000).size(), 19u);  // ceil(75 / 4)
    EXPECT_EQ(d.grant(3).size(), 3u);
}

TEST(JobDispenser, RankCapacityIsWholeBatchesWithinItsBounds)
{
    for (const long threads : {1L, 2L, 5L})
        for (const long batch : {1L, 3L, 4L, 8L, 100L})
            for (const double mean : {0.0, 1e-5, 3e-4, 1.1e-3, 7e-3, 0.05, 2.0}) {
                const long c = vimpact::rank_capacity(threads, mean, batch);
                EXPECT_EQ(c % batch, 0) << threads << " threads, batch " << batch << ", mean " << mean;
                EXPECT_GE(c, 4 * batch * threads);
                EXPECT_LE(c, std::max(64L, 4 * batch) * threads);
            }
    // Short jobs: about 0.1 s of work per thread, down to a whole batch.
    EXPECT_EQ(vimpact::rank_capacity(1, 0.1 / 29.5, 4), 28);
    EXPECT_EQ(vimpact::rank_capacity(1, 0.1 / 29.5, 1), 29);
    // Four batches at least.
    EXPECT_EQ(vimpact::rank_capacity(1, 0.1 / 29.5, 8), 32);
}

}  // namespace
