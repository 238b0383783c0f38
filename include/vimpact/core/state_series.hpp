#pragma once
// Timed states of any dimension, stored row by row: section points, time series, the states
// before and after impacts. Contiguous (n x dim, row-major), so a front end hands them out as
// one array without copying row by row.
#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace vimpact {

class state_series {
public:
    state_series() = default;
    explicit state_series(int dim) : m_dim(dim) {}

    [[nodiscard]] int dim() const { return m_dim; }
    [[nodiscard]] std::size_t size() const { return m_t.size(); }
    [[nodiscard]] bool empty() const { return m_t.empty(); }
    [[nodiscard]] double t(std::size_t i) const { return m_t[i]; }
    [[nodiscard]] Eigen::Map<const Eigen::VectorXd> x(std::size_t i) const
    {
        return Eigen::Map<const Eigen::VectorXd>(m_x.data() + i * static_cast<std::size_t>(m_dim), m_dim);
    }
    [[nodiscard]] double x(std::size_t i, int k) const { return m_x[i * static_cast<std::size_t>(m_dim) + static_cast<std::size_t>(k)]; }
    [[nodiscard]] const std::vector<double>& times() const { return m_t; }
    [[nodiscard]] const std::vector<double>& values() const { return m_x; }  // row-major, size() x dim()

    template <class Vector>
    void push_back(double t, const Vector& x)
    {
        m_t.push_back(t);
        for (int k = 0; k < m_dim; ++k) m_x.push_back(x[k]);
    }
    void reserve(std::size_t n)
    {
        m_t.reserve(n);
        m_x.reserve(n * static_cast<std::size_t>(m_dim));
    }
    void clear()
    {
        m_t.clear();
        m_x.clear();
    }

private:
    int m_dim = 0;
    std::vector<double> m_t;
    std::vector<double> m_x;
};

// Impacts: the state just before the reset and just after, and the surface hit.
struct impact_series {
    state_series pre, post;  // pre.t(i) == post.t(i): the impact time
    std::vector<int> surface;

    impact_series() = default;
    explicit impact_series(int dim) : pre(dim), post(dim) {}
    [[nodiscard]] std::size_t size() const { return surface.size(); }
    template <class Vector>
    void push_back(double t, int s, const Vector& before, const Vector& after)
    {
        pre.push_back(t, before);
        post.push_back(t, after);
        surface.push_back(s);
    }
    void clear()
    {
        pre.clear();
        post.clear();
        surface.clear();
    }
};

}  // namespace vimpact
