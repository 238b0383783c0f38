#include "journal.hpp"

#include <fcntl.h>
#include <algorithm>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string_view>
#include <system_error>
#include <thread>

namespace fs = std::filesystem;

namespace vimpact {

fs::path journal_beside(const fs::path& out)
{
    fs::path p = out;
    if (!p.has_filename()) p = p.parent_path();  // "dir/" -> "dir"
    return p.parent_path() / (p.filename().string() + ".jobs");
}

namespace {

// A journal being removed: renamed to this name first (journal_beside's name and this suffix).
constexpr std::string_view removed_suffix = ".removed-";

// Directories left by removals that a kill cut short: nothing reads them, whoever removes them.
void remove_removed(const fs::path& dir)
{
    const std::string stem = dir.filename().string() + std::string(removed_suffix);
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir.parent_path().empty() ? "." : dir.parent_path(), ec))
        if (e.path().filename().string().starts_with(stem)) fs::remove_all(e.path(), ec);
}

}  // namespace

void remove_journal(const fs::path& dir)
{
    // One rename takes the journal away whole, then its files go: a process killed in between
    // (Open MPI's SIGKILL a second after its SIGTERM, a second Ctrl-C) leaves either the whole
    // journal, which a resume reads, or a directory that no run reads and the next removes -
    // never a journal that lost some of its files (its lines, or the spec.json without which
    // every later run of DIR is refused).
    const fs::path gone = dir.parent_path() / (dir.filename().string() + std::string(removed_suffix) +
                                               std::to_string(::getpid()));
    remove_removed(dir);  // what removals cut short left (one of them may bear this pid)
    std::error_code ec;
    fs::rename(dir, gone, ec);
    if (ec) return;  // no journal; or one that cannot be moved, and stays whole
    detail::journal_fault fault;
    try {
        fault = detail::journal_fault::from_environment();
    } catch (const input_error&) {  // refused when the journal was opened
    }
    bool first = true;
    for (const auto& e : fs::directory_iterator(gone, ec)) {
        fs::remove_all(e.path(), ec);
        if (first && fault.at == detail::journal_fault::point::removal) fault.fire(nullptr);
        first = false;
    }
    fs::remove_all(gone, ec);
}

namespace detail {

namespace {

constexpr int offset_bits = 48;
constexpr std::uint64_t offset_mask = (std::uint64_t{1} << offset_bits) - 1;
constexpr std::uint64_t file_mask = (std::uint64_t{1} << 15) - 1;
constexpr std::uint64_t appended_bit = std::uint64_t{1} << 63;  // by this process, since it opened

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

std::string shard_file_name(const shard_spec& s)
{
    return "shard-" + std::to_string(s.index) + "-of-" + std::to_string(s.count) + ".jsonl";
}

// The line of a journal file that starts at `offset`.
std::string read_line(int fd, std::uint64_t offset, const fs::path& file)
{
    std::string line;
    char buf[4096];
    for (;;) {
        const ssize_t n = ::pread(fd, buf, sizeof buf, static_cast<off_t>(offset + line.size()));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw std::runtime_error("cannot read " + file.string() + ": a journal line ends early");
        const auto* nl = static_cast<const char*>(std::memchr(buf, '\n', static_cast<std::size_t>(n)));
        if (nl) {
            line.append(buf, static_cast<std::size_t>(nl - buf));
            return line;
        }
        line.append(buf, static_cast<std::size_t>(n));
    }
}

}  // namespace

std::string journal_line(long job, const json& record) { return json{{"job", job}, {"record", record}}.dump(); }

journal_fault journal_fault::from_environment()
{
    constexpr const char* name = "VIMPACT_TEST_JOURNAL_FAULT";
    const char* v = std::getenv(name);
    journal_fault f;
    if (!v || !*v) return f;
    const std::string text(v);
    const auto colon = text.find(':');
    const std::string when = text.substr(0, colon), what = colon == std::string::npos ? "" : text.substr(colon + 1);
    auto refuse = [&]() -> journal_fault {
        throw input_error(std::string(name) + " = '" + text +
                          "' is not a journal fault (a test hook): K:term, K:int, K:kill, K:torn or K:pause with "
                          "K >= 1 lines, or remove:kill or remove:term");
    };
    if (when == "remove") {
        f.at = point::removal;
        if (what == "kill") f.act = action::kill;
        else if (what == "term") f.act = action::term;
        else return refuse();
        return f;
    }
    char* end = nullptr;
    const long k = std::strtol(when.c_str(), &end, 10);
    if (when.empty() || *end != '\0' || k < 1) return refuse();
    f.at = point::line;
    f.line = k;
    if (what == "term") f.act = action::term;
    else if (what == "int") f.act = action::interrupt;
    else if (what == "kill") f.act = action::kill;
    else if (what == "torn") f.act = action::torn;
    else if (what == "pause") f.act = action::pause;
    else return refuse();
    return f;
}

void journal_fault::fire(const std::atomic<bool>* stop) const
{
    switch (act) {
    case action::term: std::raise(SIGTERM); break;
    case action::interrupt: std::raise(SIGINT); break;
    case action::kill:
    case action::torn: std::raise(SIGKILL); break;
    case action::pause:
        // Polled: the flag is set from a signal handler, which may run on any thread.
        while (!(stop && stop->load())) std::this_thread::sleep_for(std::chrono::milliseconds(5));
        break;
    }
}

journal::journal(const fs::path& dir, const json& spec, const job_options& o, long jobs)
    : m_dir(dir), m_jobs(jobs), m_fault(journal_fault::from_environment()), m_stop(o.stop)
{
    std::error_code ec;
    const fs::path spec_file = dir / "spec.json";
    // Shards may start at the same moment: the journal appears whole (spec.json and the lock
    // file inside) by one rename of a directory made aside, or not at all; whoever loses the
    // race opens the winner's.
    bool created = false;
    if (!fs::exists(dir, ec)) {
        const fs::path aside = dir.parent_path() / (dir.filename().string() + ".new-" + std::to_string(::getpid()));
        fs::remove_all(aside, ec);
        fs::create_directories(aside, ec);
        if (ec) throw input_error("cannot create the journal " + dir.string() + ": " + ec.message());
        write_atomically(aside / "spec.json", spec.dump(2) + "\n");
        write_atomically(aside / "lock", "");
        fs::rename(aside, dir, ec);  // fails when another process made `dir` first (not empty)
        created = !ec;
        if (!created) fs::remove_all(aside, ec);
    }
    if (!created) {
        if (!fs::is_directory(dir, ec)) throw input_error(dir.string() + " exists and is not a journal directory");
        std::ifstream in(spec_file);
        if (!in)
            throw input_error("the journal " + dir.string() + " has no spec.json (not a journal, or damaged); remove it");
        const json old = json::parse(in, nullptr, false);
        if (old.is_discarded())
            throw input_error("the journal " + dir.string() + " has a damaged spec.json; remove it");
        if (old != spec)
            throw input_error("the journal " + dir.string() +
                              " belongs to a different run (analysis, model, options or grid differ); remove it or "
                              "choose another output");
        if (!o.resume && o.shard.count == 1)
            throw input_error(dir.string() + " holds an unfinished run of this analysis: resume it, or remove it");
        if (!fs::exists(dir / "lock", ec)) std::ofstream(dir / "lock", std::ios::app);  // a journal of an older version
    }
    remove_removed(dir);
    m_own = dir / shard_file_name(o.shard);
    m_fd = ::open(m_own.c_str(), O_RDWR | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (m_fd < 0) throw std::runtime_error("cannot write " + m_own.string() + ": " + std::strerror(errno));
    try {
        // One process at a time appends to a shard's file (an flock, released by the kernel when
        // the holder ends): a second one, say a resume started while the interrupted run is still
        // ending, would cut the first one's newest lines as a torn tail and misplace its own.
        // A file system without locks (ENOLCK, EOPNOTSUPP) goes on unguarded, as before.
        while (::flock(m_fd, LOCK_EX | LOCK_NB) != 0 && errno != ENOLCK && errno != EOPNOTSUPP) {
            if (errno == EINTR) continue;
            if (errno == EWOULDBLOCK)
                throw input_error(m_own.string() + " is being written by another process (the same run started " +
                                  "twice, or an interrupted one still ending): let it end, then resume");
            throw std::runtime_error("cannot lock " + m_own.string() + ": " + std::strerror(errno));
        }
        index_all(true);
        m_own_size = static_cast<std::uint64_t>(::lseek(m_fd, 0, SEEK_END));
    } catch (...) {
        ::close(m_fd);  // the destructor does not run: the lock goes with the file
        for (const int fd : m_read_fds)
            if (fd >= 0) ::close(fd);
        throw;
    }
}

journal::~journal()
{
    try {
        flush();
    } catch (...) {  // a destructor must not throw: the lines are lost, as in a crash
    }
    if (m_fd >= 0) ::close(m_fd);
    for (const int fd : m_read_fds)
        if (fd >= 0) ::close(fd);
}

void journal::note(long job, std::size_t file, std::uint64_t offset, bool appended)
{
    // Grown to the highest job noted, not sized for the run: jobs arrive about in order, so the
    // index follows the work done, however long the grid.
    if (static_cast<std::size_t>(job) >= m_where.size())
        m_where.resize(std::max(static_cast<std::size_t>(job) + 1, std::min(2 * m_where.size(),
                                                                             static_cast<std::size_t>(m_jobs))),
                       0);
    auto& w = m_where[static_cast<std::size_t>(job)];
    if (w != 0) return;  // a job journaled twice (two runs of one shard): the first line serves
    if (file + 1 > file_mask) throw input_error("the journal " + m_dir.string() + " has too many files");
    w = (static_cast<std::uint64_t>(file + 1) << offset_bits) | offset | (appended ? appended_bit : 0);
    ++m_count;
}

void journal::index_all(bool repair_own)
{
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(m_dir))
        if (e.path().extension() == ".jsonl") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) index_file(f, repair_own && f == m_own);
}

// Indexes the complete lines of a journal file. A torn last line (killed while writing) is
// skipped and, with `repair` (this process's own file, locked), cut from the file so appends
// start on a fresh line; nothing else is ever cut: a file that cannot be read to its end is an
// error, not a shorter journal. A complete line that is not a record of this run is damage
// nobody should resume over: an input_error.
void journal::index_file(const fs::path& file, bool repair)
{
    std::size_t number = 0;
    while (number < m_files.size() && m_files[number] != file) ++number;
    if (number == m_files.size()) {
        m_files.push_back(file);
        m_read_fds.push_back(-1);
    }
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error("cannot read the journal file " + file.string() + ": " + std::strerror(errno));
    std::string text;  // the line being read
    std::uint64_t pos = 0;  // where it starts
    long line = 0;
    auto index_line = [&] {
        ++line;
        const auto parsed = try_parse_json_line(text);
        const json r = parsed ? *parsed : json();
        const bool valid = parsed && r.is_object() && r.contains("job") && r["job"].is_number_integer() &&
                           r["job"].get<long>() >= 0 && r["job"].get<long>() < m_jobs && r.contains("record");
        if (!valid)
            throw input_error("the journal file " + file.string() + " is damaged at line " + std::to_string(line) +
                              "; remove the journal " + file.parent_path().string() + " and run again");
        if (pos > offset_mask) throw input_error("the journal file " + file.string() + " is too large");
        note(r["job"].get<long>(), number, pos, false);
        pos += text.size() + 1;
        text.clear();
    };
    try {
        char buf[1 << 16];
        for (;;) {
            const ssize_t n = ::read(fd, buf, sizeof buf);
            if (n < 0 && errno == EINTR) continue;
            if (n < 0) throw std::runtime_error("cannot read the journal file " + file.string() + ": " + std::strerror(errno));
            if (n == 0) break;
            const char* at = buf;
            const char* const end = buf + n;
            while (const char* nl = static_cast<const char*>(std::memchr(at, '\n', static_cast<std::size_t>(end - at)))) {
                text.append(at, static_cast<std::size_t>(nl - at));
                index_line();
                at = nl + 1;
            }
            text.append(at, static_cast<std::size_t>(end - at));
        }
    } catch (...) {
        ::close(fd);
        throw;
    }
    ::close(fd);
    if (repair && !text.empty() && ::ftruncate(m_fd, static_cast<off_t>(pos)) != 0)
        throw std::runtime_error("cannot cut the torn last line of " + file.string() + ": " + std::strerror(errno));
}

bool journal::has(long job) const
{
    return static_cast<std::size_t>(job) < m_where.size() && m_where[static_cast<std::size_t>(job)] != 0;
}

bool journal::had(long job) const
{
    return has(job) && (m_where[static_cast<std::size_t>(job)] & appended_bit) == 0;
}

json journal::load(long job) const
{
    const std::uint64_t w = has(job) ? m_where[static_cast<std::size_t>(job)] : 0;
    if (w == 0) throw std::logic_error("journal: job " + std::to_string(job) + " has no line");
    const std::size_t file = static_cast<std::size_t>((w >> offset_bits) & file_mask) - 1;
    if (!m_unwritten.empty()) flush();
    int& fd = m_read_fds[file];
    if (fd < 0) fd = ::open(m_files[file].c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error("cannot read " + m_files[file].string() + ": " + std::strerror(errno));
    const auto parsed = try_parse_json_line(read_line(fd, w & offset_mask, m_files[file]));
    const json r = parsed ? *parsed : json();
    if (!parsed || !r.is_object() || !r.contains("record"))
        throw input_error("the journal file " + m_files[file].string() + " is damaged at job " + std::to_string(job) +
                          "; remove the journal " + m_dir.string() + " and run again");
    return r["record"];
}

void journal::write_unwritten() const
{
    std::size_t done = 0;
    while (done < m_unwritten.size()) {
        const ssize_t n = ::write(m_fd, m_unwritten.data() + done, m_unwritten.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw std::runtime_error("cannot write the journal in " + m_dir.string() + ": " + std::strerror(errno));
        done += static_cast<std::size_t>(n);
    }
}

void journal::flush() const
{
    const bool counts = m_fault.at == journal_fault::point::line;  // only the test hook needs the count
    const long lines = counts ? static_cast<long>(std::count(m_unwritten.begin(), m_unwritten.end(), '\n')) : 0;
    const bool strikes = counts && m_written_lines < m_fault.line && m_written_lines + lines >= m_fault.line;
    if (strikes && m_fault.act == journal_fault::action::torn) {
        // The lines before the K-th whole, the K-th cut in its middle.
        std::size_t start = 0;
        for (long k = m_written_lines + 1; k < m_fault.line; ++k) start = m_unwritten.find('\n', start) + 1;
        const std::size_t end = m_unwritten.find('\n', start);
        m_unwritten.resize(start + (end - start) / 2);
        write_unwritten();
        m_fault.fire(m_stop);
    }
    write_unwritten();
    m_unwritten.clear();
    m_written_lines += lines;
    if (strikes) m_fault.fire(m_stop);
}

void journal::append(long job, const std::string& line)
{
    const std::size_t size = line.size() + 1;
    m_unwritten += line;
    m_unwritten += '\n';
    std::size_t number = 0;
    while (number < m_files.size() && m_files[number] != m_own) ++number;
    if (number == m_files.size()) {
        m_files.push_back(m_own);
        m_read_fds.push_back(-1);
    }
    note(job, number, m_own_size, true);
    m_own_size += size;
}

std::shared_ptr<void> journal::lock_completion() const
{
    const fs::path lock = m_dir / "lock";
    const int fd = ::open(lock.c_str(), O_RDWR | O_CLOEXEC);  // no O_CREAT: a removed journal stays removed
    if (fd < 0) return nullptr;
    auto handle = std::shared_ptr<void>(new int(fd), [](void* p) {
        const int* f = static_cast<int*>(p);
        ::close(*f);  // releases the lock
        delete f;
    });
    while (::flock(fd, LOCK_EX) != 0)
        if (errno != EINTR) throw std::runtime_error("cannot lock " + lock.string());
    // The journal's owner of the moment may have written the outputs and removed it while this
    // process waited (the lock then belonged to a file no longer in the directory).
    std::error_code ec;
    if (!fs::exists(m_dir / "spec.json", ec)) return nullptr;
    return handle;
}

void journal::reread()
{
    flush();
    index_all(false);
}

}  // namespace detail
}  // namespace vimpact
