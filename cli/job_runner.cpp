#include "job_runner.hpp"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>

#include "common_options.hpp"
#include "vimpact/core/input_error.hpp"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace vimpact::cli {

void add_job_options(CLI::App& app, job_args& a)
{
    app.add_option("--threads", a.threads, "Worker threads (default 0: every core); results do not depend on it");
    app.add_option("--shard", a.shard, "Run only shard I/N of the jobs (with --out; the last shard to finish writes the result)");
    app.add_flag("--resume", a.resume, "Continue an interrupted run of the same command in --out");
}

shard_spec parse_shard(const std::string& text)
{
    const auto slash = text.find('/');
    const std::string what = "--shard '" + text + "'";
    if (slash == std::string::npos) throw input_error(what + " must be I/N with 0 <= I < N");
    const double i = parse_number(text.substr(0, slash), "--shard I");
    const double n = parse_number(text.substr(slash + 1), "--shard N");
    if (i != std::floor(i) || n != std::floor(n) || n < 1 || i < 0 || i >= n)
        throw input_error(what + " must be I/N with integers 0 <= I < N");
    return {static_cast<long>(i), static_cast<long>(n)};
}

fs::path journal_dir(const fs::path& out)
{
    fs::path p = out;
    if (!p.has_filename()) p = p.parent_path();  // "dir/" -> "dir"
    return p.parent_path() / (p.filename().string() + ".jobs");
}

namespace {

// Set by SIGINT/SIGTERM; the job loop polls it. A lock-free atomic is async-signal-safe.
std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void on_interrupt(int) { g_interrupted.store(true); }

class signal_guard {
public:
    signal_guard()
    {
        g_interrupted.store(false);
        struct sigaction sa {};
        sa.sa_handler = on_interrupt;
        sigemptyset(&sa.sa_mask);
        sigaction(SIGINT, &sa, &m_old_int);
        sigaction(SIGTERM, &sa, &m_old_term);
    }
    ~signal_guard()
    {
        sigaction(SIGINT, &m_old_int, nullptr);
        sigaction(SIGTERM, &m_old_term, nullptr);
    }
    signal_guard(const signal_guard&) = delete;
    signal_guard& operator=(const signal_guard&) = delete;

private:
    struct sigaction m_old_int {}, m_old_term {};
};

// "\r  120/400 jobs  8.1 jobs/s  ETA 0:00:35" on a terminal, at most 5 times a second.
class progress_bar {
public:
    explicit progress_bar(bool enabled) : m_enabled(enabled), m_start(clock::now()), m_last(m_start) {}

    void update(long done, long total, long resumed)
    {
        if (!m_enabled) return;
        const auto now = clock::now();
        if (done < total && now - m_last < std::chrono::milliseconds(200)) return;
        m_last = now;
        const double secs = std::chrono::duration<double>(now - m_start).count();
        const double rate = secs > 0.0 ? static_cast<double>(done - resumed) / secs : 0.0;
        const long eta = rate > 0.0 ? static_cast<long>(static_cast<double>(total - done) / rate) : -1;
        char buf[160];
        const int width = 30;
        const int filled = total > 0 ? static_cast<int>(width * done / total) : width;
        std::string bar(static_cast<std::size_t>(filled), '#');
        bar.resize(width, ' ');
        if (eta >= 0)
            std::snprintf(buf, sizeof buf, "\r[%s] %ld/%ld jobs  %.1f jobs/s  ETA %ld:%02ld:%02ld ", bar.c_str(),
                          done, total, rate, eta / 3600, (eta / 60) % 60, eta % 60);
        else
            std::snprintf(buf, sizeof buf, "\r[%s] %ld/%ld jobs ", bar.c_str(), done, total);
        std::cerr << buf << std::flush;
    }
    void finish()
    {
        if (m_enabled) std::cerr << '\n';
    }

private:
    using clock = std::chrono::steady_clock;
    bool m_enabled;
    clock::time_point m_start, m_last;
};

// Complete lines of a journal file; a torn last line (killed while writing) is dropped and,
// when `repair` is set, cut from the file so appends start on a fresh line.
std::vector<json> read_journal_file(const fs::path& file, bool repair)
{
    std::vector<json> out;
    std::ifstream in(file, std::ios::binary);
    std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::size_t pos = 0, good_end = 0;
    while (pos < content.size()) {
        const auto nl = content.find('\n', pos);
        if (nl == std::string::npos) break;
        auto j = json::parse(content.begin() + static_cast<std::ptrdiff_t>(pos),
                             content.begin() + static_cast<std::ptrdiff_t>(nl), nullptr, false);
        if (j.is_discarded() || !j.contains("job")) break;
        out.push_back(std::move(j));
        pos = nl + 1;
        good_end = pos;
    }
    if (repair && good_end < content.size()) fs::resize_file(file, good_end);
    return out;
}

void write_atomically(const fs::path& p, const std::string& text)
{
    const fs::path tmp = p.string() + ".tmp" + std::to_string(::getpid());
    {
        std::ofstream o(tmp);
        o << text;
        if (!o) throw std::runtime_error("cannot write " + tmp.string());
    }
    fs::rename(tmp, p);
}

// Opens the journal: checks the spec, returns every finished record of any shard.
std::unordered_map<long, json> open_journal(const fs::path& jdir, const json& spec, bool resume, long jobs)
{
    std::unordered_map<long, json> finished;
    std::error_code ec;
    const fs::path spec_file = jdir / "spec.json";
    if (fs::exists(jdir, ec)) {
        std::ifstream in(spec_file);
        const json old = in ? json::parse(in, nullptr, false) : json();
        if (old != spec) {
            if (resume || old.is_discarded() || old.is_null())
                throw input_error("--resume: the journal " + jdir.string() +
                                  " belongs to a different run (command, parameters or grid differ); "
                                  "remove it or choose another --out");
            throw input_error(jdir.string() + " holds an unfinished different run; remove it or choose another --out");
        }
        // Same spec: a shard joining its siblings is normal; a repeat of a whole run needs --resume.
        for (const auto& e : fs::directory_iterator(jdir)) {
            if (e.path().extension() != ".jsonl") continue;
            for (auto& r : read_journal_file(e.path(), false)) {
                const long j = r["job"].get<long>();
                if (j >= 0 && j < jobs) finished.emplace(j, std::move(r));
            }
        }
        return finished;
    }
    fs::create_directories(jdir, ec);
    if (ec) throw input_error("--out: cannot create " + jdir.string() + ": " + ec.message());
    write_atomically(spec_file, spec.dump(2) + "\n");
    return finished;
}

}  // namespace

job_command_result run_job_command(const job_command& cmd, const job_args& args)
{
    const shard_spec shard = args.shard.empty() ? shard_spec{} : parse_shard(args.shard);
    (void)resolve_threads(args.threads);
    if (args.threads < 0) throw input_error("--threads must be >= 0");
    if (!cmd.out && shard.count > 1) throw input_error("--shard needs --out (the shards meet in its journal)");
    if (!cmd.out && args.resume) throw input_error("--resume needs --out (the directory of the interrupted run)");

    std::unordered_map<long, json> finished;
    std::optional<std::ofstream> journal;
    fs::path jdir;
    if (cmd.out) {
        jdir = journal_dir(*cmd.out);
        if (!args.resume && shard.count == 1 && fs::exists(jdir))
            throw input_error(jdir.string() + " holds an unfinished run: add --resume to continue it, or remove it");
        finished = open_journal(jdir, cmd.spec, args.resume, cmd.schedule.jobs);
        const fs::path file = jdir / ("shard-" + std::to_string(shard.index) + "-of-" + std::to_string(shard.count) + ".jsonl");
        if (fs::exists(file)) (void)read_journal_file(file, true);  // cut a torn last line
        journal.emplace(file, std::ios::app);
        if (!*journal) throw std::runtime_error("cannot write " + file.string());
    }

    // Records of the whole run, by job, for finish(): the finished ones and this call's.
    std::map<long, json> records;
    for (const auto& [j, r] : finished) records.emplace(j, r);

    signal_guard signals;
    progress_bar bar(::isatty(2) != 0);
    job_loop_options lo;
    lo.threads = args.threads;
    lo.shard = shard;
    lo.stop = &g_interrupted;
    long resumed_in_shard = 0;
    lo.progress = [&](long done, long total) { bar.update(done, total, resumed_in_shard); };
    for (const auto& [j, r] : finished)
        if (shard.owns_chain(cmd.schedule.chain_of(j))) ++resumed_in_shard;

    job_command_result res;
    res.summary = run_jobs<json>(
        cmd.schedule, lo, finished,
        [&](long job, const json* prev) {
            json r = cmd.run(job, prev);
            r["job"] = job;
            return r;
        },
        [&](long job, json&& r) {
            if (journal) {
                *journal << r.dump() << '\n';
                journal->flush();
                if (!*journal) throw std::runtime_error("cannot write the journal in " + jdir.string());
            }
            records.emplace(job, std::move(r));
        });
    bar.finish();

    if (res.summary.stopped) {
        std::cerr << "vimpact: interrupted: " << res.summary.resumed + res.summary.computed << " of "
                  << res.summary.owned << " jobs done"
                  << (cmd.out ? " and kept in " + jdir.string() + "; run the same command with --resume to finish"
                              : "; nothing written (use --out to make a run resumable)")
                  << '\n';
        res.exit_code = 130;
        return res;
    }
    if (static_cast<long>(records.size()) < cmd.schedule.jobs) {
        std::cerr << "vimpact: shard " << shard.index << "/" << shard.count << " done ("
                  << res.summary.owned << " jobs); " << records.size() << " of " << cmd.schedule.jobs
                  << " jobs of the run are in " << jdir.string()
                  << "; the last shard to finish writes " << cmd.out->string() << '\n';
        return res;
    }
    std::vector<json> ordered;
    ordered.reserve(records.size());
    for (auto& [j, r] : records) ordered.push_back(std::move(r));
    records.clear();
    journal.reset();
    const fs::path* dir = cmd.out ? &*cmd.out : nullptr;
    cmd.finish(ordered, dir);
    res.complete = true;
    if (cmd.out) {
        std::error_code ec;
        fs::remove_all(jdir, ec);
    }
    return res;
}

}  // namespace vimpact::cli
