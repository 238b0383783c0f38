#pragma once
// An output directory that is written completely or not at all: files go to a hidden staging
// directory beside the target and are moved into place by commit(). Without commit() (an
// error, an exception, Ctrl-C handled by unwinding) the staging directory is removed and the
// target is left as it was.
#include <filesystem>
#include <string>
#include <vector>

namespace vimpact {

// Throws input_error if `target` cannot become an output directory: it exists and is not a
// directory, a component of its path is not a directory, or the place is not writable. Creates
// nothing, so that a front end can refuse a bad target before any work.
void check_output_target(const std::filesystem::path& target);

class staged_output {
public:
    // Throws input_error if the target exists and is not a directory, or cannot be created.
    explicit staged_output(std::filesystem::path target);
    ~staged_output();
    staged_output(const staged_output&) = delete;
    staged_output& operator=(const staged_output&) = delete;

    [[nodiscard]] std::filesystem::path file(const std::string& name);
    [[nodiscard]] const std::filesystem::path& staging_dir() const { return m_staging; }
    [[nodiscard]] const std::filesystem::path& target() const { return m_target; }
    void commit();

private:
    std::filesystem::path m_target;
    std::filesystem::path m_staging;
    std::vector<std::string> m_files;
    bool m_committed = false;
};

}  // namespace vimpact
