#pragma once
// Running a job-loop command from the command line: --threads, --shard, --resume, the
// progress bar, Ctrl-C, and the journal that makes a run resumable and shardable.
//
// The journal of `--out DIR` is the directory DIR.jobs beside it: spec.json (what is being
// computed; a resume must match it) and one file per shard, shard-I-of-N.jsonl, with one JSON
// line per finished job, flushed as it is written. A run killed at any moment keeps every
// finished job (a torn last line is dropped on resume). When every job is done the final
// files are written to DIR (all at once, through a staging directory) and the journal is
// removed. Shards share the journal: every run reads all shard files as finished work, so the
// last shard to finish writes DIR, and re-running the command with --resume and no --shard
// combines whatever shards there are and computes the missing jobs.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "vimpact/jobs/job_loop.hpp"

namespace vimpact::cli {

struct job_args {
    int threads = 0;
    std::string shard;
    bool resume = false;
};

void add_job_options(CLI::App& app, job_args& a);

shard_spec parse_shard(const std::string& text);  // "i/n", 0 <= i < n

struct job_command {
    nlohmann::json spec;                 // command, configuration, grid: identifies the run
    job_schedule schedule;
    std::optional<std::filesystem::path> out;
    // Computes job j; `previous` is the predecessor's record for chained jobs, else null.
    std::function<nlohmann::json(long job, const nlohmann::json* previous)> run;
    // Writes the final outputs from every record, in job order; `dir` is null without --out.
    std::function<void(const std::vector<nlohmann::json>& records, const std::filesystem::path* dir)> finish;
};

struct job_command_result {
    int exit_code = 0;
    job_loop_summary summary;
    bool complete = false;  // every job of the whole run is done and finish() ran
};

// Runs the command's jobs (this shard), journals them, and calls finish() when all are done.
job_command_result run_job_command(const job_command& cmd, const job_args& args);

std::filesystem::path journal_dir(const std::filesystem::path& out);

}  // namespace vimpact::cli
