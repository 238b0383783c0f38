#pragma once
// A described record (core/record.hpp) as the JSON of a run's summary: the command line's
// --json and run.json's result. Keyed by the fields' names: a number (null when not finite:
// JSON has no NaN or infinity), flag or text as itself, an outcome by its name, a per-surface
// field {surface: value} (a missing entry 0, or null for reals), a state vector an array, a
// spectrum [[re, im], ...], a group a nested object. A series is left out: its points are a
// table of their own. The same record is Python's record_dict (python/bindings/records.hpp)
// and, bit for bit, a many-job run's journal line (src/io/record_json.hpp).
#include <cmath>
#include <complex>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "vimpact/core/outcome.hpp"
#include "vimpact/core/record.hpp"
#include "vimpact/core/state_series.hpp"
#include "vimpact/model/model_info.hpp"

namespace vimpact {

// A number, or null when it is not finite.
inline nlohmann::json finite_or_null(double v)
{
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

// How a summary names a field where it differs from the description: `key` another key, a
// key of a nested object ("stats/protocol"), or "" to leave the field out.
struct summary_key {
    std::string_view field;
    std::string_view key;
};
struct summary_form {
    std::vector<summary_key> keys;
    bool tabular = false;  // only the fields a table has: a sweep's rows without its tables
};

template <class R>
nlohmann::json summary_json(const R& r, const model_info& info, const summary_form& form = {});

namespace summary_detail {

using json = nlohmann::json;

template <class T>
json value(const T& v, const model_info& info)
{
    if constexpr (std::is_floating_point_v<T>) {
        return finite_or_null(v);
    } else if constexpr (std::is_same_v<T, outcome>) {
        return std::string(to_string(v));
    } else if constexpr (std::is_same_v<T, std::vector<long>> || std::is_same_v<T, std::vector<double>>) {
        const json missing = std::is_same_v<T, std::vector<long>> ? json(0L) : json(nullptr);
        json by = json::object();
        for (std::size_t s = 0; s < info.surfaces.size(); ++s)
            by[info.surfaces[s].name] = s < v.size() ? value(v[s], info) : missing;
        return by;
    } else if constexpr (std::is_same_v<T, Eigen::VectorXd>) {
        json a = json::array();
        for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(finite_or_null(v[i]));
        return a;
    } else if constexpr (std::is_same_v<T, std::vector<std::complex<double>>>) {
        json a = json::array();
        for (const auto& z : v) a.push_back({finite_or_null(z.real()), finite_or_null(z.imag())});
        return a;
    } else {
        static_assert(std::is_integral_v<T> || std::is_same_v<T, std::string>, "a field type without a summary form");
        return v;
    }
}

struct writer {
    json& out;
    const model_info& info;
    const summary_form& form;

    void put(const field& f, json v)
    {
        std::string_view key = f.name;
        for (const auto& k : form.keys)
            if (k.field == f.name) key = k.key;
        if (key.empty() || (form.tabular && !f.tabular)) return;
        const auto slash = key.find('/');
        if (slash == std::string_view::npos) out[std::string(key)] = std::move(v);
        else out[std::string(key.substr(0, slash))][std::string(key.substr(slash + 1))] = std::move(v);
    }
    template <class T>
    void operator()(const field& f, const T& v)
    {
        if constexpr (!std::is_same_v<T, state_series>) put(f, value(v, info));
    }
    template <class G>
    void group(const field& f, const G& g)
    {
        put(f, summary_json(g, info));
    }
};

}  // namespace summary_detail

template <class R>
nlohmann::json summary_json(const R& r, const model_info& info, const summary_form& form)
{
    nlohmann::json out = nlohmann::json::object();
    summary_detail::writer w{out, info, form};
    describe(w, r);
    return out;
}

}  // namespace vimpact
