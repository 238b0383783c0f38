#include "job_runner.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>

#include "interrupts.hpp"
#include "parse.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/jobs/job_ranks.hpp"

namespace fs = std::filesystem;

namespace vimpact::cli {

void add_job_options(CLI::App& app, job_args& a)
{
    app.add_option("--threads", a.threads, "Worker threads (default 0: every core); results do not depend on it");
    app.add_option("--batch", a.batch,
                   "Jobs integrated together in SIMD lanes (default 0: the SIMD width of the build; 1: one at a time; "
                   "a plugin, or a model file of a dimension the build has no fixed-size states for, always one at a "
                   "time); results do not depend on it");
    app.add_option("--shard", a.shard,
                   "Run only shard I/N of the jobs (with --out; the last shard to finish writes the result)");
    app.add_flag("--resume", a.resume, "Continue an interrupted run of the same command in --out");
}

// "[#####     ] 120/400 jobs  8.1 jobs/s  ETA 0:00:35" on a terminal, at most 5 times a second.
struct job_session::progress {
    using clock = std::chrono::steady_clock;
    clock::time_point start = clock::now(), last = start;
    long first_done = -1;  // jobs done when the first report came (resumed ones)
    bool shown = false;

    void update(long done, long total)
    {
        const auto now = clock::now();
        if (first_done < 0) first_done = done > 0 ? done - 1 : 0;
        if (done < total && now - last < std::chrono::milliseconds(200)) return;
        last = now;
        shown = true;
        const double secs = std::chrono::duration<double>(now - start).count();
        const double rate = secs > 0.0 ? static_cast<double>(done - first_done) / secs : 0.0;
        const long eta = rate > 0.0 ? static_cast<long>(static_cast<double>(total - done) / rate) : -1;
        constexpr int width = 30;
        const int filled = total > 0 ? static_cast<int>(width * done / total) : width;
        std::string bar(static_cast<std::size_t>(filled), '#');
        bar.resize(width, ' ');
        char buf[160];
        if (eta >= 0)
            std::snprintf(buf, sizeof buf, "\r[%s] %ld/%ld jobs  %.1f jobs/s  ETA %ld:%02ld:%02ld ", bar.c_str(), done,
                          total, rate, eta / 3600, (eta / 60) % 60, eta % 60);
        else
            std::snprintf(buf, sizeof buf, "\r[%s] %ld/%ld jobs ", bar.c_str(), done, total);
        std::cerr << buf << std::flush;
    }
    void end()
    {
        if (shown) std::cerr << '\n';
        shown = false;
    }
};

job_session::job_session(const job_args& a, const std::optional<fs::path>& out) : m_out(out)
{
    if (a.threads < 0) throw input_error("--threads must be >= 0 (got " + std::to_string(a.threads) + ")");
    m_options.threads = a.threads;
    if (a.batch < 0 || a.batch > 1024)
        throw input_error("--batch = " + std::to_string(a.batch) + " is outside its valid range [0, 1024] (0: the SIMD width)");
    m_options.batch = a.batch;
    if (!a.shard.empty()) m_options.shard = parse_shard(a.shard);
    if (!out && m_options.shard.count > 1) throw input_error("--shard needs --out (the shards meet in its journal)");
    if (!out && a.resume) throw input_error("--resume needs --out (the directory of the interrupted run)");
    m_options.resume = a.resume;
    if (out) {
        m_options.journal = journal_beside(*out);
        std::error_code ec;
        if (!a.resume && m_options.shard.count == 1 && fs::exists(*m_options.journal, ec))
            throw input_error(m_options.journal->string() +
                              " holds an unfinished run: add --resume to continue it, or remove it");
    }
    m_options.stop = &interrupt_flag();
    // Started by mpirun or srun as one of several ranks: they share the jobs (rank 0 keeps the
    // journal and writes DIR); with --shard, the ranks of each MPI run share that shard's.
    m_options.ranks = mpi_world_ranks();
    if (m_options.ranks && m_options.ranks->rank() != 0) return;  // no progress bar but rank 0's
    if (::isatty(2)) {
        m_progress = std::make_shared<progress>();
        m_options.progress = [p = m_progress](long done, long total) { p->update(done, total); };
    }
}

job_session::~job_session() = default;

bool job_session::complete(const job_report& r)
{
    if (m_progress) m_progress->end();
    if (!r.coordinator) {  // a rank other than 0: rank 0 reports and writes
        m_exit_code = r.stopped ? 130 : 0;
        return false;
    }
    if (r.stopped) {
        std::cerr << "vimpact: interrupted: " << r.resumed + r.computed << " of " << r.owned << " jobs done"
                  << (m_out ? " and kept in " + m_options.journal->string() +
                                  "; run the same command with --resume to finish"
                            : std::string("; nothing written (use --out to make a run resumable)"))
                  << '\n';
        m_exit_code = 130;
        return false;
    }
    if (r.written_elsewhere) {
        std::cerr << "vimpact: shard " << m_options.shard.index << "/" << m_options.shard.count << " done ("
                  << r.owned << " jobs); another shard completed the run and wrote " << m_out->string() << '\n';
        return false;
    }
    if (!r.complete()) {
        std::cerr << "vimpact: shard " << m_options.shard.index << "/" << m_options.shard.count << " done ("
                  << r.owned << " jobs); " << r.done << " of " << r.jobs << " jobs of the run are in "
                  << m_options.journal->string() << "; the last shard to finish writes " << m_out->string() << '\n';
        return false;
    }
    return true;
}

void job_session::finish()
{
    if (m_options.journal) remove_journal(*m_options.journal);
}

}  // namespace vimpact::cli
