#pragma once
// Point sets for the correlation dimension: n points in R^d stored row by row, the one
// squared distance every counting path uses, and the reader for point files (CSV with a
// header line, columns chosen by name).
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <charconv>
#include <string>
#include <string_view>
#include <vector>

#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"

namespace vimpact {

class point_set {
public:
    point_set() = default;
    explicit point_set(int dim) : m_dim(dim)
    {
        if (dim < 1) throw input_error("a point set needs dimension >= 1 (got " + std::to_string(dim) + ")");
    }

    [[nodiscard]] int dim() const { return m_dim; }
    [[nodiscard]] std::size_t size() const { return m_dim ? m_data.size() / static_cast<std::size_t>(m_dim) : 0; }
    [[nodiscard]] bool empty() const { return m_data.empty(); }
    [[nodiscard]] const double* point(std::size_t i) const { return m_data.data() + i * static_cast<std::size_t>(m_dim); }
    [[nodiscard]] double coordinate(std::size_t i, int k) const { return point(i)[k]; }
    [[nodiscard]] const std::vector<double>& data() const { return m_data; }

    void reserve(std::size_t n) { m_data.reserve(n * static_cast<std::size_t>(m_dim)); }
    // Throws input_error for a non-finite coordinate: distances to it mean nothing.
    void push_back(const double* x)
    {
        for (int k = 0; k < m_dim; ++k)
            if (!std::isfinite(x[k]))
                throw input_error("point " + std::to_string(size()) + " has a non-finite coordinate");
        if (x >= m_data.data() && x < m_data.data() + m_data.size()) {  // a point of this set: copy first
            const std::vector<double> copy(x, x + m_dim);
            m_data.insert(m_data.end(), copy.begin(), copy.end());
        } else {
            m_data.insert(m_data.end(), x, x + m_dim);
        }
    }
    void push_back(std::initializer_list<double> x)
    {
        if (static_cast<int>(x.size()) != m_dim)
            throw input_error("point has " + std::to_string(x.size()) + " coordinates, the set " +
                              std::to_string(m_dim));
        push_back(x.begin());
    }

private:
    int m_dim = 0;
    std::vector<double> m_data;
};

// The squared Euclidean distance, evaluated the same way wherever it is used (k-d tree
// leaves, brute force, centres), so that the counts of different paths agree exactly:
// with hardware FMA the compiler would otherwise fuse `s += d * d` in some inlined copies
// and not in others, and a pair on a bin edge could land in different bins.
inline double squared_distance(const double* a, const double* b, int dim)
{
    double s = 0.0;
    for (int k = 0; k < dim; ++k) {
        const double d = a[k] - b[k];
#ifdef FP_FAST_FMA
        s = std::fma(d, d, s);
#else
        s += d * d;  // no FMA instruction: nothing can be fused
#endif
    }
    return s;
}

// A CSV table of numbers with its header, as read from a points file.
struct point_table {
    std::vector<std::string> header;
    std::vector<std::vector<double>> columns;  // columns[c][row]
};

namespace detail {

inline std::string trim(std::string_view s)
{
    std::size_t b = 0, e = s.size();
    while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r' || s[b] == '"')) ++b;
    while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r' || s[e - 1] == '"')) --e;
    return std::string(s.substr(b, e - b));
}

inline std::vector<std::string> split_csv_line(std::string_view line)
{
    std::vector<std::string> out;
    std::size_t start = 0;
    for (;;) {
        const std::size_t comma = line.find(',', start);
        out.push_back(trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
        if (comma == std::string_view::npos) break;
        start = comma + 1;
    }
    return out;
}

inline std::string join(const std::vector<std::string>& v)
{
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + v[i];
    return s;
}

}  // namespace detail

// Reads a CSV file: a header line of column names, then one row of numbers per line (blank
// lines ignored). Throws input_error naming the file, line and column of anything malformed.
inline point_table read_point_table(const std::filesystem::path& path)
{
    std::ifstream in(path);
    if (!in || std::filesystem::is_directory(path))
        throw input_error("cannot read points file '" + path.string() + "'");
    const std::string name = "points file '" + path.string() + "'";
    point_table t;
    std::string line;
    if (!std::getline(in, line)) throw input_error(name + " is empty (expected a header line, then rows of numbers)");
    t.header = detail::split_csv_line(line);
    for (const auto& h : t.header)
        if (h.empty()) throw input_error(name + ": empty column name in the header line");
    t.columns.resize(t.header.size());
    long line_no = 1;
    while (std::getline(in, line)) {
        ++line_no;
        if (detail::trim(line).empty()) continue;
        const auto cells = detail::split_csv_line(line);
        if (cells.size() != t.header.size())
            throw input_error(name + " line " + std::to_string(line_no) + ": " + std::to_string(cells.size()) +
                              " values, the header has " + std::to_string(t.header.size()));
        for (std::size_t c = 0; c < cells.size(); ++c) {
            double v = 0.0;
            const char* b = cells[c].data();
            const char* e = b + cells[c].size();
            if (b < e && *b == '+') ++b;
            const auto [p, ec] = std::from_chars(b, e, v);
            if (ec != std::errc() || p != e || b == e || !std::isfinite(v))
                throw input_error(name + " line " + std::to_string(line_no) + ", column '" + t.header[c] +
                                  "': '" + cells[c] + "' is not a finite number");
            t.columns[c].push_back(v);
        }
    }
    return t;
}

// Column indices for a comma-separated list of names; an empty list means every column
// except one named "t" (time orders the points, it is not a coordinate).
inline std::vector<std::size_t> select_columns(const std::vector<std::string>& header, const std::string& names,
                                               const std::string& source)
{
    std::vector<std::size_t> idx;
    if (detail::trim(names).empty()) {
        for (std::size_t c = 0; c < header.size(); ++c)
            if (header[c] != "t") idx.push_back(c);
        if (idx.empty()) throw input_error(source + " has no coordinate columns (columns: " + detail::join(header) + ")");
        return idx;
    }
    for (const auto& want : detail::split_csv_line(names)) {
        std::size_t c = 0;
        while (c < header.size() && header[c] != want) ++c;
        if (c == header.size())
            throw input_error("--columns: no column '" + want + "' in " + source + " (columns: " + detail::join(header) + ")");
        for (auto k : idx)
            if (k == c) throw input_error("--columns: column '" + want + "' is named twice");
        idx.push_back(c);
    }
    return idx;
}

inline point_set make_point_set(const point_table& t, const std::vector<std::size_t>& columns)
{
    point_set ps(static_cast<int>(columns.size()));
    const std::size_t n = t.columns.empty() ? 0 : t.columns[0].size();
    ps.reserve(n);
    std::vector<double> x(columns.size());
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t k = 0; k < columns.size(); ++k) x[k] = t.columns[columns[k]][i];
        ps.push_back(x.data());
    }
    return ps;
}

}  // namespace vimpact
