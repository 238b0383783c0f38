#include "vimpact/io/csv_writer.hpp"

#include <stdexcept>

#include "vimpact/core/format.hpp"

namespace vimpact {

csv_writer::csv_writer(const std::filesystem::path& path, const std::vector<std::string>& header)
    : m_out(path), m_path(path), m_columns(header.size())
{
    if (!m_out) throw std::runtime_error("cannot write " + path.string());
    for (std::size_t i = 0; i < header.size(); ++i) m_out << (i ? "," : "") << header[i];
    m_out << '\n';
}

void csv_writer::row(std::initializer_list<double> values) { row(std::vector<double>(values)); }

void csv_writer::row(const std::vector<double>& values)
{
    if (values.size() != m_columns)
        throw std::logic_error("csv row has " + std::to_string(values.size()) + " values, header " +
                               std::to_string(m_columns));
    std::string line;
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (i) line += ',';
        line += format_double(values[i]);
    }
    line += '\n';
    m_out.write(line.data(), static_cast<std::streamsize>(line.size()));
}

void csv_writer::text_row(const std::vector<std::string>& cells)
{
    if (cells.size() != m_columns)
        throw std::logic_error("csv row has " + std::to_string(cells.size()) + " cells, header " +
                               std::to_string(m_columns));
    // One buffer and one unformatted write: a distributed run's coordinator writes a row per
    // result, up to 10^5 a second.
    std::size_t size = cells.size();
    for (const auto& c : cells) size += c.size();
    std::string line;
    line.reserve(size);
    for (std::size_t i = 0; i < cells.size(); ++i) {
        if (cells[i].find_first_of(",\n") != std::string::npos)
            throw std::logic_error("csv cell '" + cells[i] + "' contains a separator");
        if (i) line += ',';
        line += cells[i];
    }
    line += '\n';
    m_out.write(line.data(), static_cast<std::streamsize>(line.size()));
}

void csv_writer::close()
{
    m_out.close();
    if (!m_out) throw std::runtime_error("error writing " + m_path.string());
}

}  // namespace vimpact
