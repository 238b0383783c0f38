// The job loop: order, determinism across thread counts, chains, shards, resume, stop, errors.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <set>
#include <thread>

#include "vimpact/jobs/job_loop.hpp"

namespace {

using vimpact::job_loop_options;
using vimpact::job_schedule;
using vimpact::run_jobs;

// A job whose duration varies (so threads finish out of order) and whose value depends only
// on its index and predecessor.
double work(long job, const double* prev)
{
    std::this_thread::sleep_for(std::chrono::microseconds(50 * ((job * 7919) % 13)));
    return (prev ? *prev : 0.0) * 0.5 + std::sin(static_cast<double>(job));
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

}  // namespace
