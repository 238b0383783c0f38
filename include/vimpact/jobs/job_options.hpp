#pragma once
// What every many-job analysis (sweep, map, basins, response, and the stability sweeps) takes
// besides its own options, and what it reports about its jobs.
//
// Journal: with `journal` set, every finished job is appended to a journal directory as one
// JSON line, flushed as it is written, so a run killed at any moment keeps every finished job.
// The directory holds spec.json (what is being computed: the analysis, the model and every
// option that changes a result) and one file per shard, shard-I-of-N.jsonl. A run finds the
// jobs already in the journal (of any shard) and computes only the others; with `resume`
// false a journal of a whole run that already exists is refused (it would be resumed by
// mistake), while shards of one run meet in it. When every job of the run is done, the
// result is complete; the caller writes its outputs from it and then removes the journal
// (remove_journal), so that a crash while writing loses nothing.
#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>

#include "vimpact/jobs/job_loop.hpp"

namespace vimpact {

struct job_options {
    int threads = 0;  // 0: every core; results never depend on it
    // Jobs integrated together in SIMD lanes (hybrid/flow_lanes.hpp): 0 the SIMD width of the
    // build (8 with AVX-512, 4 with AVX2), 1 one at a time. Results never depend on it; a model
    // that cannot run in lanes (a model file) runs one at a time whatever is asked.
    int batch = 0;
    shard_spec shard{};
    std::optional<std::filesystem::path> journal;
    bool resume = false;
    const std::atomic<bool>* stop = nullptr;  // set: no new job starts, the run returns what finished
    std::function<void(long done, long total)> progress;  // called in job order as jobs finish
};

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
    int threads = 0;
    int batch = 1;  // jobs per SIMD batch this run used (job_options::batch resolved for the model)
    // Held by the shard that completes a journaled run while its caller writes the outputs and
    // removes the journal; other shards wait for it. Released with the report.
    std::shared_ptr<void> completion_lock;
    [[nodiscard]] bool complete() const { return done == jobs; }
};

// The journal directory beside an output directory: DIR.jobs for DIR.
std::filesystem::path journal_beside(const std::filesystem::path& out);

// Removes a journal directory (after the caller has written its outputs).
void remove_journal(const std::filesystem::path& journal);

}  // namespace vimpact
