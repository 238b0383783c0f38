#pragma once
// The journal of a many-job run (jobs/job_options.hpp states the contract) and the one
// function every many-job analysis runs its jobs through: run_journaled.
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <nlohmann/json.hpp>

#include "vimpact/core/input_error.hpp"
#include "vimpact/jobs/job_options.hpp"

namespace vimpact::detail {

using json = nlohmann::json;

class journal {
public:
    // Opens (or creates) the journal for `spec`; throws input_error for a journal of another
    // run, or of this run when `resume` is false and this is not a shard of it.
    journal(const std::filesystem::path& dir, const json& spec, const job_options& o, long jobs);

    // Every finished record of any shard (job -> record), read at opening.
    [[nodiscard]] std::unordered_map<long, json>& finished() { return m_finished; }
    // Appends one finished job, flushed.
    void append(long job, const json& record);
    // Waits for the journal's completion lock (an flock on DIR/lock, released by the kernel when
    // its holder ends, so a killed holder cannot block the others) and returns its handle, or
    // null when the journal was removed meanwhile: another shard completed the run and wrote it.
    [[nodiscard]] std::shared_ptr<void> lock_completion() const;
    // Rereads every shard file: the jobs other processes finished meanwhile.
    [[nodiscard]] std::unordered_map<long, json> reread() const;
    [[nodiscard]] const std::filesystem::path& dir() const { return m_dir; }

private:
    std::filesystem::path m_dir;
    long m_jobs;
    std::unordered_map<long, json> m_finished;
    std::ofstream m_out;
};

// Runs the jobs of `schedule` (this shard) through the job loop and, when o.journal is set,
// the journal; returns the records of the whole run known to this call (resumed, computed, and
// those of other shards), by job, with the report. run(job, const Record* predecessor) computes
// a job; encode/decode translate a record to and from its journal line.
// A journal record decoded, or an input_error naming the job when the line is not a record
// of this analysis (an edited journal): damage to report, not an internal error.
template <class Record, class Decode>
Record decode_record(Decode& decode, long job, const json& r, const std::filesystem::path& journal)
{
    try {
        return decode(r);
    } catch (const json::exception&) {
        throw input_error("the journal " + journal.string() + " holds a damaged record of job " + std::to_string(job) +
                          "; remove the journal and run again");
    }
}

template <class Record, class Run, class Encode, class Decode>
std::map<long, Record> run_journaled(const json& spec, const job_schedule& schedule, const job_options& o, Run&& run,
                                     Encode&& encode, Decode&& decode, job_report& report)
{
    validate(o.shard);
    (void)resolve_threads(o.threads);
    if (!o.journal && o.shard.count > 1)
        throw input_error("a shard of a run needs a journal (the shards meet in it)");
    if (!o.journal && o.resume) throw input_error("resuming needs the journal of the interrupted run");
    std::optional<journal> j;
    std::unordered_map<long, Record> finished;
    std::map<long, Record> records;
    if (o.journal) {
        j.emplace(*o.journal, spec, o, schedule.jobs);
        for (auto& [job, r] : j->finished()) {
            finished.emplace(job, decode_record<Record>(decode, job, r, *o.journal));
            records.emplace(job, finished.at(job));
        }
        j->finished().clear();
    }
    job_loop_options lo;
    lo.threads = o.threads;
    lo.batch = report.batch;
    lo.shard = o.shard;
    lo.stop = o.stop;
    lo.progress = o.progress;
    const job_loop_summary s = run_jobs<Record>(schedule, lo, finished, run, [&](long job, Record&& r) {
        if (j) j->append(job, encode(r));
        records.insert_or_assign(job, std::move(r));
    });
    // Shards finishing at the same time: one at a time, under the journal's lock, each counts
    // what the others wrote meanwhile; the first to find the run complete keeps the lock until
    // its caller has written the outputs and removed the journal, and the others then find the
    // journal gone. So the result is written exactly once, and a writer killed midway leaves
    // the journal (and the lock free) to the next.
    if (j && !s.stopped && static_cast<long>(records.size()) < schedule.jobs) {
        report.completion_lock = j->lock_completion();
        if (!report.completion_lock) {
            report.written_elsewhere = true;
        } else {
            for (auto& [job, r] : j->reread())
                if (!records.count(job)) records.emplace(job, decode_record<Record>(decode, job, r, *o.journal));
            if (static_cast<long>(records.size()) < schedule.jobs) report.completion_lock.reset();
        }
    }
    report.jobs = schedule.jobs;
    report.owned = s.owned;
    report.resumed = s.resumed;
    report.computed = s.computed;
    report.done = static_cast<long>(records.size());
    report.stopped = s.stopped;
    report.threads = s.threads;
    return records;
}

// The records of a complete run in job order (the run must be complete).
template <class Record>
std::vector<Record> in_job_order(std::map<long, Record>&& records)
{
    std::vector<Record> out;
    out.reserve(records.size());
    for (auto& [job, r] : records) out.push_back(std::move(r));
    return out;
}

}  // namespace vimpact::detail
