#pragma once
// Running a many-job analysis from the command line: --threads, --shard, --resume, the
// progress bar and Ctrl-C around one library call. The library keeps the journal
// (jobs/job_options.hpp) in DIR.jobs beside --out DIR; this layer decides what the report
// means for the user:
//   - stopped by Ctrl-C or SIGTERM: exit 130, the finished jobs stay in the journal;
//   - a shard whose run is not complete yet: a note; the last shard to finish writes DIR;
//   - complete: the command writes DIR (all at once), then the journal is removed.
#include <atomic>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "vimpact/jobs/job_options.hpp"

namespace vimpact::cli {

struct job_args {
    int threads = 0;
    int batch = 0;
    std::string shard;
    bool resume = false;
};

void add_job_options(CLI::App& app, job_args& a);

class job_session {
public:
    // Checks the options (before any work): --shard and --resume need --out, and without
    // --resume an unfinished run's journal is protected.
    job_session(const job_args& args, const std::optional<std::filesystem::path>& out);
    ~job_session();
    job_session(const job_session&) = delete;
    job_session& operator=(const job_session&) = delete;

    // The options for the library call (Ctrl-C sets their stop flag: cli/interrupts.hpp).
    [[nodiscard]] const job_options& options() const { return m_options; }

    // After the call: true when every job of the run is done and the outputs are to be
    // written; otherwise prints what happened and sets exit_code().
    bool complete(const job_report& report);
    // Removes the journal once the outputs are written.
    void finish();
    [[nodiscard]] int exit_code() const { return m_exit_code; }

private:
    struct progress;
    job_options m_options;
    std::optional<std::filesystem::path> m_out;
    std::shared_ptr<progress> m_progress;
    int m_exit_code = 0;
};

}  // namespace vimpact::cli
