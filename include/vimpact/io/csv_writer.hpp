#pragma once
// CSV with a header line; numbers in shortest round-trip form so files read back bit for bit.
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

namespace vimpact {

class csv_writer {
public:
    csv_writer(const std::filesystem::path& path, const std::vector<std::string>& header);
    void row(std::initializer_list<double> values);
    void row(const std::vector<double>& values);
    // Cells already formatted (labels next to numbers); they must not contain commas.
    void text_row(const std::vector<std::string>& cells);
    void close();

private:
    std::ofstream m_out;
    std::filesystem::path m_path;
    std::size_t m_columns;
};

}  // namespace vimpact
