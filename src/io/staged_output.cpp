#include "vimpact/io/staged_output.hpp"

#include <unistd.h>

#include "vimpact/core/input_error.hpp"

namespace fs = std::filesystem;

namespace vimpact {

void check_output_target(const fs::path& target)
{
    std::error_code ec;
    const fs::path abs = fs::absolute(target, ec);
    if (ec) throw input_error("output directory " + target.string() + ": " + ec.message());
    const auto status = fs::status(abs, ec);
    if (fs::exists(status) && !fs::is_directory(status))
        throw input_error("output directory " + target.string() + " exists and is not a directory");
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
    if (fs::is_directory(status) && ::access(abs.c_str(), W_OK | X_OK) != 0)
        throw input_error("output directory " + target.string() + ": cannot write in it");
}

staged_output::staged_output(fs::path target) : m_target(std::move(target))
{
    std::error_code ec;
    if (fs::exists(m_target, ec) && !fs::is_directory(m_target, ec))
        throw input_error("output directory " + m_target.string() + " exists and is not a directory");
    fs::path parent = fs::absolute(m_target, ec).parent_path();
    if (!fs::exists(parent, ec)) {
        fs::create_directories(parent, ec);
        if (ec) throw input_error("output directory: cannot create " + parent.string() + ": " + ec.message());
    }
    m_staging = parent / (".vimpact-staging-" + m_target.filename().string() + "-" +
                          std::to_string(::getpid()));
    fs::remove_all(m_staging, ec);
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
