#pragma once
// The journal of a many-job run (jobs/job_options.hpp states the contract) and the one
// function every many-job analysis runs its jobs through: run_journaled.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/json_line.hpp"
#include "vimpact/core/input_error.hpp"
#include "jobs/job_loop.hpp"
#include "vimpact/jobs/job_options.hpp"

namespace vimpact::detail {

using json = nlohmann::json;

// A job's line in a journal, and on the wire between ranks: {"job":J,"record":{...}}.
std::string journal_line(long job, const json& record);

// A test hook: the environment variable VIMPACT_TEST_JOURNAL_FAULT makes the process that
// keeps a journal interrupt itself at a chosen point of its writing, so that tests of kills
// and resumes do not depend on timing (docs/sweeps.md, "Testing interruptions"):
//   K:term, K:int, K:kill  SIGTERM, SIGINT or SIGKILL right after the write that holds the
//                          K-th line this process journals;
//   K:torn                 that write cut in the middle of the K-th line, then SIGKILL (a
//                          process killed inside a write);
//   K:pause                after that write, no further step until the run's stop flag is set
//                          (by the signal the test sends), so the run cannot end before it;
//   remove:kill, remove:term  SIGKILL or SIGTERM while the journal of a complete run is being
//                          removed (its outputs written).
struct journal_fault {
    enum class point { none, line, removal };
    enum class action { term, interrupt, kill, torn, pause };
    point at = point::none;
    long line = 0;
    action act = action::kill;

    // The variable's fault; none when it is unset. Throws input_error naming it when malformed.
    static journal_fault from_environment();
    // Acts (a signal on this process, or the pause); `stop` is the run's stop flag (may be null).
    void fire(const std::atomic<bool>* stop) const;
};

class journal {
public:
    // Opens (or creates) the journal for `spec`; throws input_error for a journal of another
    // run, or of this run when `resume` is false and this is not a shard of it. Indexes the
    // jobs finished so far (of any shard): where each one's line is, not its record.
    journal(const std::filesystem::path& dir, const json& spec, const job_options& o, long jobs);
    ~journal();
    journal(const journal&) = delete;
    journal& operator=(const journal&) = delete;

    [[nodiscard]] bool has(long job) const;
    // Finished before this process opened the journal (or found by reread).
    [[nodiscard]] bool had(long job) const;
    // The record of a finished job, read back from its file.
    [[nodiscard]] json load(long job) const;
    // Jobs with a line (finished before, or appended since).
    [[nodiscard]] long count() const { return m_count; }
    // Appends one finished job's line; flush() writes the lines appended since the last one
    // to the file (one write for the results that arrived together).
    void append(long job, const std::string& line);
    void flush() const;
    // Waits for the journal's completion lock (an flock on DIR/lock, released by the kernel when
    // its holder ends, so a killed holder cannot block the others) and returns its handle, or
    // null when the journal was removed meanwhile: another shard completed the run and wrote it.
    [[nodiscard]] std::shared_ptr<void> lock_completion() const;
    // Indexes again every shard file: the jobs other processes finished meanwhile.
    void reread();
    [[nodiscard]] const std::filesystem::path& dir() const { return m_dir; }

private:
    void index_all(bool repair_own);
    void index_file(const std::filesystem::path& file, bool repair);
    void note(long job, std::size_t file, std::uint64_t offset, bool appended);
    void write_unwritten() const;

    std::filesystem::path m_dir;
    long m_jobs;
    std::filesystem::path m_own;                // this shard's file
    std::vector<std::filesystem::path> m_files; // indexed files (their number in m_where)
    std::vector<std::uint64_t> m_where;         // per job: appended << 63 | (file + 1) << 48 | offset; 0: none
    long m_count = 0;
    int m_fd = -1;                              // m_own, appending
    std::uint64_t m_own_size = 0;
    mutable std::vector<int> m_read_fds;        // per indexed file, opened when first read
    mutable std::string m_unwritten;            // appended lines not yet written
    mutable long m_written_lines = 0;           // by this process
    journal_fault m_fault;                      // the test hook's, if any
    const std::atomic<bool>* m_stop = nullptr;  // the run's stop flag (the hook's pause)
};

// Every rank must run the same jobs: each sends rank 0 one hash of its spec (with the spec,
// to name what differs), and rank 0 answers once it has them all. A mismatch is an input_error
// on every rank naming the first differences (rank 0 tells the others with tag_abort), raised
// before rank 0 opens a journal or anything is written.
void check_same_run(job_ranks& ranks, const json& spec);
// The hash the ranks compare: FNV-1a (64 bits) of the spec's canonical text.
std::string spec_hash(const json& spec);

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

// Runs the jobs of `schedule` (this shard) through the job loop, the journal when o.journal
// is set, and the ranks when o.ranks is set, and hands `each` every job's record in job order
// (jobs/job_options.hpp, Streaming). run(job, const Record* predecessor) computes a job;
// encode/decode translate a record to and from its journal form. Returns the report.
template <class Record, class Run, class Encode, class Decode, class Each>
job_report run_journaled(const json& spec, const job_schedule& schedule, const job_options& o, Run&& run,
                         Encode&& encode, Decode&& decode, Each&& each)
{
    validate(o.shard);
    (void)resolve_threads(o.threads);
    if (!o.journal && o.shard.count > 1)
        throw input_error("a shard of a run needs a journal (the shards meet in it)");
    if (!o.journal && o.resume) throw input_error("resuming needs the journal of the interrupted run");
    if (o.ranks) check_same_run(*o.ranks, spec);
    job_report report;
    report.jobs = schedule.jobs;
    job_loop_options lo;
    lo.threads = o.threads;
    // The analysis passes its batch resolved for the model (jobs per SIMD batch; >= 1 used).
    lo.batch = std::max(1, o.batch);
    report.batch = static_cast<int>(lo.batch);
    lo.shard = o.shard;
    lo.stop = o.stop;
    lo.progress = o.progress;
    lo.ranks = o.ranks;
    lo.timed = o.timed;
    // Records travel between ranks as journal lines: the coordinator appends them as they
    // come, and one codec serves the journal, a resume and the wire.
    job_loop_io<Record> io;
    io.encode = [&](long job, const Record& r) { return journal_line(job, encode(r)); };
    io.decode = [&](std::string_view line) {
        const json j = parse_json_line(line);
        return std::pair<long, Record>(j.at("job").get<long>(), decode(j.at("record")));
    };
    auto fill = [&](const job_loop_summary& s) {
        report.owned = s.owned;
        report.resumed = s.resumed;
        report.computed = s.computed;
        report.stopped = s.stopped;
        report.threads = s.threads;
        report.ranks = s.ranks;
        report.coordinator = s.coordinator;
    };
    if (o.ranks && o.ranks->rank() != 0) {
        fill(run_jobs<Record>(schedule, lo, io, run, [](long, Record&&) {}));
        return report;
    }

    std::optional<journal> jr;
    try {
        if (o.journal) jr.emplace(*o.journal, spec, o, schedule.jobs);
    } catch (...) {
        if (o.ranks) abort_ranks(*o.ranks, std::current_exception());
        throw;
    }
    auto from_journal = [&](long job) { return decode_record<Record>(decode, job, jr->load(job), *o.journal); };
    if (jr) {
        // Those finished before this call: the jobs it computes are journaled as they arrive.
        io.finished = [&](long job) { return jr->had(job); };
        io.load = from_journal;
        io.arrived = [&](long job, const Record& r, const std::string* line) {
            jr->append(job, line ? *line : journal_line(job, encode(r)));
        };
        io.flush = [&] { jr->flush(); };
    }
    // The stream: every job in order, the jobs this call did not compute read from the
    // journal in their place; a job that is nowhere (a stop left a gap) ends it.
    const bool streaming = o.shard.count == 1;
    long next_out = 0;
    bool gap = false;
    auto stream_to = [&](long end) {
        for (; next_out < end && !gap; ++next_out) {
            if (!jr || !jr->has(next_out)) {
                gap = true;
                return;
            }
            each(next_out, from_journal(next_out));
        }
    };
    const job_loop_summary s = run_jobs<Record>(schedule, lo, io, run, [&](long job, Record&& r) {
        if (!streaming) return;
        stream_to(job);
        if (gap) return;
        each(job, std::move(r));
        next_out = job + 1;
    });
    fill(s);
    report.done = jr && !streaming ? jr->count() : s.resumed + s.computed;
    if (!s.stopped && streaming) stream_to(schedule.jobs);
    // Shards finishing at the same time: one at a time, under the journal's lock, each counts
    // what the others wrote meanwhile; the first to find the run complete keeps the lock until
    // its caller has written the outputs and removed the journal, and the others then find the
    // journal gone. So the result is written exactly once, and a writer killed midway leaves
    // the journal (and the lock free) to the next.
    if (jr && !s.stopped && !streaming) {
        report.completion_lock = jr->lock_completion();
        if (!report.completion_lock) {
            report.written_elsewhere = true;
        } else {
            jr->reread();
            report.done = jr->count();
            if (report.done < schedule.jobs) report.completion_lock.reset();
            else stream_to(schedule.jobs);
        }
    }
    return report;
}

}  // namespace vimpact::detail
