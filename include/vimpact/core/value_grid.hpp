#pragma once
// The values of a parameter (or state) axis of a many-job run: n evenly spaced values from a
// to b, kept as (a, b, n) so that a run over ten million values holds three numbers, not
// eighty megabytes; or the values one by one, as a caller listed them. Optionally mapped: the
// values given in other units (an SI flow speed) and the map to the parameter they set,
// applied value by value, so that each job's value is computed as if the list had been
// converted first.
//
// Value i of a range is a + i (b - a)/(n - 1) (a when n = 1, b exactly for the last): it
// depends only on (a, b, n, i), never on rounding accumulated over the others.
#include <cstddef>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace vimpact {

class value_grid {
public:
    // The largest n of a range: more points than any run can use.
    static constexpr long max_points = 100'000'000;

    value_grid() = default;
    // The values as listed (implicit: an analysis's `values = {...}` or a vector).
    value_grid(std::vector<double> values) : m_list(std::move(values)) {}  // NOLINT(google-explicit-constructor)
    value_grid(std::initializer_list<double> values) : m_list(values) {}
    // n values from a to b inclusive; throws input_error unless 1 <= n <= max_points and a, b
    // are finite.
    static value_grid range(double a, double b, long n);

    // Value i is map(given value i); `what` names the map in a job's spec (the run is another
    // when it changes), e.g. the SI inputs and the quantity.
    [[nodiscard]] value_grid mapped(std::function<double(double)> map, std::string what) const;

    [[nodiscard]] std::size_t size() const { return m_range ? static_cast<std::size_t>(m_n) : m_list.size(); }
    [[nodiscard]] bool empty() const { return size() == 0; }
    [[nodiscard]] double operator[](std::size_t i) const
    {
        const double v = given(i);
        return m_map ? m_map->map(v) : v;
    }
    [[nodiscard]] double front() const { return (*this)[0]; }
    [[nodiscard]] double back() const { return (*this)[size() - 1]; }
    // Value i before the map (as the caller gave it; the same as [i] when not mapped).
    [[nodiscard]] double given(std::size_t i) const
    {
        if (!m_range) return m_list[i];
        const auto k = static_cast<long>(i);
        if (m_n == 1) return m_a;
        if (k == m_n - 1) return m_b;
        return m_a + static_cast<double>(k) * (m_b - m_a) / static_cast<double>(m_n - 1);
    }
    // The grid without its map: the values as given.
    [[nodiscard]] value_grid unmapped() const;

    [[nodiscard]] bool is_range() const { return m_range; }
    [[nodiscard]] bool is_mapped() const { return m_map != nullptr; }
    [[nodiscard]] double range_from() const { return m_a; }
    [[nodiscard]] double range_to() const { return m_b; }
    [[nodiscard]] const std::string& map_name() const;
    // Every value, for a grid known to be small (a test, a chart's few gaps).
    [[nodiscard]] std::vector<double> values() const;

    class const_iterator {
    public:
        using iterator_category = std::input_iterator_tag;
        using value_type = double;
        using difference_type = std::ptrdiff_t;
        using pointer = void;
        using reference = double;
        const_iterator(const value_grid* g, std::size_t i) : m_g(g), m_i(i) {}
        double operator*() const { return (*m_g)[m_i]; }
        const_iterator& operator++()
        {
            ++m_i;
            return *this;
        }
        const_iterator operator++(int)
        {
            const_iterator old = *this;
            ++m_i;
            return old;
        }
        bool operator==(const const_iterator& o) const { return m_i == o.m_i; }
        bool operator!=(const const_iterator& o) const { return m_i != o.m_i; }

    private:
        const value_grid* m_g;
        std::size_t m_i;
    };
    [[nodiscard]] const_iterator begin() const { return {this, 0}; }
    [[nodiscard]] const_iterator end() const { return {this, size()}; }

private:
    struct value_map {
        std::function<double(double)> map;
        std::string what;
    };
    std::vector<double> m_list;
    double m_a = 0.0, m_b = 0.0;
    long m_n = 0;
    bool m_range = false;
    std::shared_ptr<const value_map> m_map;
};

}  // namespace vimpact
