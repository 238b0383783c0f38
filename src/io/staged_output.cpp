#include "vimpact/io/staged_output.hpp"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <string_view>

#include <sys/stat.h>
#include <unistd.h>

#include "vimpact/core/input_error.hpp"

namespace fs = std::filesystem;

namespace vimpact {
namespace {

constexpr std::string_view staging_prefix = ".vimpact-staging-";

// The staging directory's name for a target name: the name cut to 64 bytes, so that a target
// whose own name is near the 255-byte limit still gets one, then the process id.
std::string staging_stem(const fs::path& target)
{
    return std::string(staging_prefix) + target.filename().string().substr(0, 64) + "-";
}

// Removes the staging directories of `target` left by processes that no longer run (killed
// by a signal before they could clean up).
void remove_stale_staging(const fs::path& parent, const fs::path& target)
{
    const std::string stem = staging_stem(target);
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(parent, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() <= stem.size() || name.compare(0, stem.size(), stem) != 0) continue;
        const std::string pid_text = name.substr(stem.size());
        if (pid_text.find_first_not_of("0123456789") != std::string::npos || pid_text.size() > 9) continue;
        const auto pid = static_cast<pid_t>(std::stol(pid_text));
        if (pid == ::getpid() || (::kill(pid, 0) != 0 && errno == ESRCH)) {
            std::error_code ignored;
            fs::remove_all(entry.path(), ignored);
        }
    }
}

}  // namespace

void check_output_target(const fs::path& target)
{
    std::error_code ec;
    const fs::path abs = fs::absolute(target, ec);
    if (ec) throw input_error("output directory " + target.string() + ": " + ec.message());
    const auto status = fs::status(abs, ec);
    if (target.empty()) throw input_error("output directory: the name is empty");
    if (fs::exists(status) && !fs::is_directory(status))
        throw input_error("output directory " + target.string() + " exists and is not a directory");
    if (abs.lexically_normal() == abs.root_path())
        throw input_error("output directory " + target.string() + " is the root directory: name a directory for the run");
    for (const auto& part : abs)
        if (part.string().size() > 255)
            throw input_error("output directory: the name '" + part.string().substr(0, 40) + "...' has " +
                              std::to_string(part.string().size()) + " characters (at most 255)");
    // The staging directory goes beside the target, and missing components are created: the
    // nearest existing ancestor must be a directory we may write in.
    fs::path place = abs.parent_path();
    while (!place.empty() && !fs::exists(place, ec)) {
        if (place == place.parent_path()) break;
        place = place.parent_path();
    }
    if (!fs::is_directory(place, ec))
        throw input_error("output directory " + target.string() + ": " + place.string() + " is not a directory");
    if (::access(place.c_str(), W_OK | X_OK) != 0)
        throw input_error("output directory " + target.string() + ": cannot write in " + place.string());
    // Permissions do not tell everything (/proc, read-only mounts): make and remove a
    // directory where the run will make its own.
    const fs::path probe = place / (std::string(staging_prefix) + "probe-" + std::to_string(::getpid()));
    if (::mkdir(probe.c_str(), 0700) != 0)
        throw input_error("output directory " + target.string() + ": cannot create a directory in " + place.string() +
                          " (" + std::strerror(errno) + ")");
    ::rmdir(probe.c_str());
    if (fs::is_directory(status) && ::access(abs.c_str(), W_OK | X_OK) != 0)
        throw input_error("output directory " + target.string() + ": cannot write in it");
}

staged_output::staged_output(fs::path target) : m_target(std::move(target))
{
    check_output_target(m_target);
    std::error_code ec;
    fs::path parent = fs::absolute(m_target, ec).parent_path();
    if (!fs::exists(parent, ec)) {
        fs::create_directories(parent, ec);
        if (ec) throw input_error("output directory: cannot create " + parent.string() + ": " + ec.message());
    }
    remove_stale_staging(parent, m_target);
    m_staging = parent / (staging_stem(m_target) + std::to_string(::getpid()));
    fs::create_directories(m_staging, ec);
    if (ec) throw input_error("output directory: cannot write in " + parent.string() + ": " + ec.message());
}

staged_output::~staged_output()
{
    if (!m_committed) {
        std::error_code ec;
        fs::remove_all(m_staging, ec);
    }
}

fs::path staged_output::file(const std::string& name)
{
    m_files.push_back(name);
    return m_staging / name;
}

void staged_output::commit()
{
    std::error_code ec;
    // Every name is checked before anything moves, so that a refusal leaves the target as it was.
    if (fs::is_directory(m_target, ec))
        for (const auto& entry : fs::directory_iterator(m_staging)) {
            const fs::path to = m_target / entry.path().filename();
            if (fs::is_directory(to, ec) && !entry.is_directory())
                throw input_error("output directory " + m_target.string() + ": " + to.string() +
                                  " is a directory; the run's file of that name cannot replace it");
        }
    if (!fs::exists(m_target, ec)) {
        fs::rename(m_staging, m_target, ec);
        if (!ec) {
            m_committed = true;
            return;
        }
        fs::create_directories(m_target, ec);
    }
    for (const auto& entry : fs::directory_iterator(m_staging)) {
        fs::rename(entry.path(), m_target / entry.path().filename(), ec);
        if (ec) throw std::runtime_error("cannot move " + entry.path().string() + " into " +
                                         m_target.string() + ": " + ec.message());
    }
    fs::remove_all(m_staging, ec);
    m_committed = true;
}

}  // namespace vimpact
