#pragma once
// Point sets for the correlation dimension: n points in R^d stored row by row, the one
// squared distance every counting path uses, the reader for point files (CSV with a header
// line, columns chosen by name) and the coordinates of a model's recorded states. The readers
// are compiled into the library (src/analysis/dimension_points.cpp).
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <vector>

#include "vimpact/core/input_error.hpp"
#include "vimpact/core/state_series.hpp"
#include "vimpact/model/model_info.hpp"

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

// A table of numbers with column names: a points file, or recorded states as coordinates.
struct point_table {
    std::vector<std::string> header;
    std::vector<std::vector<double>> columns;  // columns[c][row]
};

// Reads a CSV file: a header line of column names, then one row of numbers per line (blank
// lines ignored). Throws input_error naming the file, line and column of anything malformed.
point_table read_point_table(const std::filesystem::path& path);

// Column indices for a comma-separated list of names; an empty list means every column
// except one named "t" (time orders the points, it is not a coordinate). `source` names the
// table in messages.
std::vector<std::size_t> select_columns(const std::vector<std::string>& header, const std::string& names,
                                        const std::string& source);

point_set make_point_set(const point_table& t, const std::vector<std::size_t>& columns);

// The coordinates of recorded states of a model (section points of a run), one column per
// state variable, named after it; a phase (a variable with a period p) becomes the pair
// NAME_cos, NAME_sin = s cos(x / s), s sin(x / s) with s = p / 2 pi, so that states a period
// apart are the same point and small differences keep their size (the rule of attractor
// signatures, analysis/basins.hpp).
point_table state_point_table(const model_info& info, const state_series& states);

}  // namespace vimpact
