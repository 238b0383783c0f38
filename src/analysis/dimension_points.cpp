#include "vimpact/analysis/dimension_points.hpp"

#include <charconv>
#include <fstream>
#include <numbers>
#include <string_view>

#include "vimpact/core/format.hpp"

namespace vimpact {

namespace {

std::string trim(std::string_view s)
{
    std::size_t b = 0, e = s.size();
    while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r' || s[b] == '"')) ++b;
    while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r' || s[e - 1] == '"')) --e;
    return std::string(s.substr(b, e - b));
}

std::vector<std::string> split_csv_line(std::string_view line)
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

std::string join(const std::vector<std::string>& v)
{
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + v[i];
    return s;
}

}  // namespace

point_table read_point_table(const std::filesystem::path& path)
{
    std::ifstream in(path);
    if (!in || std::filesystem::is_directory(path))
        throw input_error("cannot read points file '" + path.string() + "'");
    const std::string name = "points file '" + path.string() + "'";
    point_table t;
    std::string line;
    if (!std::getline(in, line)) throw input_error(name + " is empty (expected a header line, then rows of numbers)");
    t.header = split_csv_line(line);
    for (const auto& h : t.header)
        if (h.empty()) throw input_error(name + ": empty column name in the header line");
    t.columns.resize(t.header.size());
    long line_no = 1;
    while (std::getline(in, line)) {
        ++line_no;
        if (trim(line).empty()) continue;
        const auto cells = split_csv_line(line);
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

std::vector<std::size_t> select_columns(const std::vector<std::string>& header, const std::string& names,
                                        const std::string& source)
{
    std::vector<std::size_t> idx;
    if (trim(names).empty()) {
        for (std::size_t c = 0; c < header.size(); ++c)
            if (header[c] != "t") idx.push_back(c);
        if (idx.empty()) throw input_error(source + " has no coordinate columns (columns: " + join(header) + ")");
        return idx;
    }
    for (const auto& want : split_csv_line(names)) {
        std::size_t c = 0;
        while (c < header.size() && header[c] != want) ++c;
        if (c == header.size())
            throw input_error("columns: no column '" + want + "' in " + source + " (columns: " + join(header) + ")");
        for (auto k : idx)
            if (k == c) throw input_error("columns: column '" + want + "' is named twice");
        idx.push_back(c);
    }
    return idx;
}

point_set make_point_set(const point_table& t, const std::vector<std::size_t>& columns)
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

point_table state_point_table(const model_info& info, const state_series& states)
{
    point_table t;
    t.header = coordinate_names(info);
    t.columns.resize(t.header.size());
    for (auto& c : t.columns) c.reserve(states.size());
    std::vector<double> y(t.header.size());
    for (std::size_t i = 0; i < states.size(); ++i) {
        state_coordinates(info, states.x(i).data(), y.data());
        for (std::size_t c = 0; c < y.size(); ++c) t.columns[c].push_back(y[c]);
    }
    return t;
}

}  // namespace vimpact
