#pragma once
// A described record (core/record.hpp) as a JSON object keyed by its fields' names, and back,
// bit for bit: a many-job run's journal lines. A group is a nested object.
#include <complex>
#include <string>
#include <type_traits>

#include "io/json_codec.hpp"
#include "vimpact/core/outcome.hpp"
#include "vimpact/core/record.hpp"

namespace vimpact::detail {

template <class R>
json record_json(const R& r);
template <class R>
R record_from(const json& j);

inline json value_json(double v) { return number(v); }
inline json value_json(const std::string& v) { return v; }
inline json value_json(outcome v) { return std::string(to_string(v)); }
inline json value_json(const std::vector<double>& v) { return numbers(v); }
inline json value_json(const Eigen::VectorXd& v) { return vector_json(v); }
inline json value_json(const state_series& v) { return to_json(v); }
inline json value_json(const std::vector<Eigen::VectorXd>& v)
{
    json a = json::array();
    for (const auto& x : v) a.push_back(vector_json(x));
    return a;
}
inline json value_json(const std::vector<std::complex<double>>& v)
{
    json a = json::array();
    for (const auto& z : v) a.push_back({number(z.real()), number(z.imag())});
    return a;
}
template <class T>
    requires std::is_integral_v<T> || std::same_as<T, std::vector<long>>
json value_json(const T& v)
{
    return v;
}

inline void value_from(const json& j, double& v) { v = number_from(j); }
inline void value_from(const json& j, outcome& v) { v = outcome_from(j); }
inline void value_from(const json& j, std::vector<double>& v) { v = numbers_from(j); }
inline void value_from(const json& j, Eigen::VectorXd& v) { v = vector_from(j); }
inline void value_from(const json& j, state_series& v) { v = series_from(j); }
inline void value_from(const json& j, std::vector<Eigen::VectorXd>& v)
{
    v.clear();
    for (const auto& x : j) v.push_back(vector_from(x));
}
inline void value_from(const json& j, std::vector<std::complex<double>>& v)
{
    v.clear();
    for (const auto& z : j) v.emplace_back(number_from(z.at(0)), number_from(z.at(1)));
}
template <class T>
    requires std::is_integral_v<T> || std::same_as<T, std::string> || std::same_as<T, std::vector<long>>
void value_from(const json& j, T& v)
{
    v = j.get<T>();
}

struct record_json_writer {
    json out = json::object();
    template <class T>
    void operator()(const field& f, const T& v)
    {
        out[std::string(f.name)] = value_json(v);
    }
    template <class R>
    void group(const field& f, const R& r)
    {
        out[std::string(f.name)] = record_json(r);
    }
};

// A missing key or a value of the wrong type throws nlohmann's exceptions: the journal reader
// names the job and the file (jobs/journal.hpp).
struct record_json_reader {
    const json& in;
    template <class T>
    void operator()(const field& f, T& v)
    {
        value_from(in.at(std::string(f.name)), v);
    }
    template <class R>
    void group(const field& f, R& r)
    {
        r = record_from<R>(in.at(std::string(f.name)));
    }
};

template <class R>
json record_json(const R& r)
{
    record_json_writer w;
    describe(w, r);
    return std::move(w.out);
}

template <class R>
R record_from(const json& j)
{
    R r;
    record_json_reader rd{j};
    describe(rd, r);
    return r;
}

}  // namespace vimpact::detail
