#pragma once
// What every many-job analysis (sweep, map, basins, response, and the stability sweeps) takes
// besides its own options, and what it reports about its jobs.
//
// Journal: with `journal` set, every finished job is appended to a journal directory as one JSON line as soon
// as its result reaches the process that keeps the journal (in any order), so a run killed at any moment keeps
// every finished job; a torn last line (killed inside a write) is skipped, and cut by the file's next writer.
// The directory holds spec.json (what is being computed: the analysis, the model and every option that changes
// a result) and one file per shard, shard-I-of-N.jsonl, which one process at a time appends to (an flock). A
// run finds the jobs already in the journal (of any shard) and computes only the others; with `resume`
// false a journal of a whole run that already exists is refused (it would be resumed by
// mistake), while shards of one run meet in it. When every job of the run is done, the
// result is complete; the caller writes its outputs from it and then removes the journal
// (remove_journal), so that a crash while writing loses nothing.
//
// Streaming: an analysis called with a job_stream hands it every job's result in job order,
// the run's finished jobs read back from the journal in their place, and keeps none itself:
// memory does not grow with the number of jobs (the journal's index of finished jobs, 8 bytes
// a job, exists only when a run is resumed or completed by a shard). A run that is not a
// shard streams while it runs; a shard streams when it completes the run. Only a complete
// run has streamed every job; after a stop the stream ends early.
//
// Ranks: with `ranks` (MPI, jobs/job_ranks.hpp) every rank makes the same call; rank 0 keeps
// the journal, streams and reports, the others compute what rank 0 hands them and return a
// report with coordinator = false.
#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "vimpact/core/input_error.hpp"
#include "vimpact/jobs/job_schedule.hpp"

namespace vimpact {

class job_ranks;  // jobs/job_ranks.hpp

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

struct job_options {
    int threads = 0;  // 0: every core; results never depend on it
    // Jobs integrated together in SIMD lanes (hybrid/flow_lanes.hpp): 0 the SIMD width of the
    // build's lanes (8 with AVX-512 in the default build, 4 with AVX2: core/lanes.hpp), 1 one at a time. Results never depend on it; a model
    // that cannot run in lanes (a model file) runs one at a time whatever is asked.
    int batch = 0;
    shard_spec shard{};
    std::optional<std::filesystem::path> journal;
    bool resume = false;
    const std::atomic<bool>* stop = nullptr;  // set: no new job starts, the run returns what finished
    std::function<void(long done, long total)> progress;  // called in job order as jobs finish
    std::shared_ptr<job_ranks> ranks;  // several processes (MPI); null: this one alone
    std::function<void(long job, double seconds)> timed;  // each job's CPU time (its share of its thread's)
};

// Receives each job's result in job order (see Streaming above).
template <class Record>
using job_stream = std::function<void(long job, const Record&)>;

struct job_report {
    long jobs = 0;      // of the whole run
    long owned = 0;     // in this shard
    long resumed = 0;   // of them, found in the journal
    long computed = 0;  // by this call
    long done = 0;      // jobs of the whole run with a result (journal and this call)
    bool stopped = false;  // the stop flag ended the call early
    // A shard that found the journal removed at its end: another shard completed the run and
    // wrote its outputs (done counts only what this call knew).
    bool written_elsewhere = false;
    int threads = 0;   // computing threads of this process
    int ranks = 1;     // processes that computed (MPI ranks)
    // False on the ranks other than 0 of an MPI run: they computed jobs and report nothing else.
    bool coordinator = true;
    int batch = 1;  // jobs per SIMD batch this run used (job_options::batch resolved for the model)
    // Held by the shard that completes a journaled run while its caller writes the outputs and
    // removes the journal; other shards wait for it. Released with the report.
    std::shared_ptr<void> completion_lock;
    [[nodiscard]] bool complete() const { return done == jobs; }
};

// The journal directory beside an output directory: DIR.jobs for DIR.
std::filesystem::path journal_beside(const std::filesystem::path& out);

// Removes a journal (after the caller wrote its outputs): renamed aside, then deleted; killed midway, whole or gone.
void remove_journal(const std::filesystem::path& journal);

}  // namespace vimpact
