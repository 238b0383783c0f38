#include "journal.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>

#include <system_error>

namespace fs = std::filesystem;

namespace vimpact {

fs::path journal_beside(const fs::path& out)
{
    fs::path p = out;
    if (!p.has_filename()) p = p.parent_path();  // "dir/" -> "dir"
    return p.parent_path() / (p.filename().string() + ".jobs");
}

void remove_journal(const fs::path& dir)
{
    std::error_code ec;
    fs::remove_all(dir, ec);
}

namespace detail {

namespace {

// Complete lines of a journal file. A torn last line (killed while writing) is dropped and,
// with `repair`, cut from the file so appends start on a fresh line. A complete line that is
// not a record of this run is damage nobody should resume over: an input_error.
std::vector<json> read_journal_file(const fs::path& file, long jobs, bool repair)
{
    std::vector<json> out;
    std::ifstream in(file, std::ios::binary);
    const std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::size_t pos = 0, good_end = 0;
    long line = 0;
    while (pos < content.size()) {
        const auto nl = content.find('\n', pos);
        if (nl == std::string::npos) break;  // torn last line
        ++line;
        auto r = json::parse(content.begin() + static_cast<std::ptrdiff_t>(pos),
                             content.begin() + static_cast<std::ptrdiff_t>(nl), nullptr, false);
        const bool valid = !r.is_discarded() && r.is_object() && r.contains("job") && r["job"].is_number_integer() &&
                           r["job"].get<long>() >= 0 && r["job"].get<long>() < jobs && r.contains("record");
        if (!valid)
            throw input_error("the journal file " + file.string() + " is damaged at line " + std::to_string(line) +
                              "; remove the journal " + file.parent_path().string() + " and run again");
        out.push_back(std::move(r));
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

std::string shard_file_name(const shard_spec& s)
{
    return "shard-" + std::to_string(s.index) + "-of-" + std::to_string(s.count) + ".jsonl";
}

}  // namespace

journal::journal(const fs::path& dir, const json& spec, const job_options& o, long jobs) : m_dir(dir), m_jobs(jobs)
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
        for (const auto& e : fs::directory_iterator(dir)) {
            if (e.path().extension() != ".jsonl") continue;
            for (auto& r : read_journal_file(e.path(), jobs, false)) {
                const long j = r["job"].get<long>();
                m_finished.emplace(j, std::move(r["record"]));
            }
        }
    }
    const fs::path file = dir / shard_file_name(o.shard);
    if (fs::exists(file)) (void)read_journal_file(file, jobs, true);  // cut a torn last line
    m_out.open(file, std::ios::app);
    if (!m_out) throw std::runtime_error("cannot write " + file.string());
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

void journal::append(long job, const json& record)
{
    m_out << json{{"job", job}, {"record", record}}.dump() << '\n';
    m_out.flush();
    if (!m_out) throw std::runtime_error("cannot write the journal in " + m_dir.string());
}

std::unordered_map<long, json> journal::reread() const
{
    std::unordered_map<long, json> out;
    for (const auto& e : fs::directory_iterator(m_dir)) {
        if (e.path().extension() != ".jsonl") continue;
        for (auto& r : read_journal_file(e.path(), m_jobs, false)) out.emplace(r["job"].get<long>(), std::move(r["record"]));
    }
    return out;
}

}  // namespace detail
}  // namespace vimpact
