#pragma once
// What every binding shares: running library work with the GIL released and Ctrl-C honoured,
// numpy conversions of the library's values, and the options read from the keyword dicts
// that vimpact/_api.py sends. Nothing here analyses anything: it converts.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/analysis/protocol_declaration.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/option.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/core/names.hpp"
#include "vimpact/core/state_series.hpp"
#include "vimpact/jobs/job_options.hpp"
#include "vimpact/model/model.hpp"
#include "vimpact/model/model_phrases.hpp"

namespace vimpact::python {

namespace py = pybind11;

// Any array-like of numbers, read as contiguous float64.
using input_array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// How often the calling thread looks for Ctrl-C (and reports progress) while the work runs.
inline constexpr std::chrono::milliseconds poll_interval{50};

// Runs work(cancel) on a worker thread while the calling thread, with the GIL released,
// wakes every poll_interval to take the GIL briefly, run Python's signal handlers
// (PyErr_CheckSignals: a pending Ctrl-C raises KeyboardInterrupt there) and call poll().
// When either raises, `cancel` is set (the library polls it after every integration step and
// between jobs), the worker is joined and the Python exception is raised. The work must not
// touch Python objects. Only the main thread sees signals, so called from another Python
// thread the work is not interruptible (Python's own rule for signals).
template <class Work, class Poll>
auto run_released(Work&& work, Poll&& poll)
{
    using result_type = std::decay_t<decltype(work(std::declval<const std::atomic<bool>&>()))>;
    std::atomic<bool> cancel{false};
    std::optional<result_type> result;
    std::exception_ptr failure;       // from the work
    std::exception_ptr poll_failure;  // a C++ exception from poll()
    bool python_error = false;        // a Python exception is set (KeyboardInterrupt, or from poll)
    std::mutex mutex;
    std::condition_variable finished;
    bool done = false;
    {
        py::gil_scoped_release release;
        std::thread worker([&] {
            try {
                result.emplace(work(static_cast<const std::atomic<bool>&>(cancel)));
            } catch (...) {
                failure = std::current_exception();
            }
            std::lock_guard lock(mutex);
            done = true;
            finished.notify_all();
        });
        std::unique_lock lock(mutex);
        while (!finished.wait_for(lock, poll_interval, [&] { return done; })) {
            if (python_error || poll_failure) continue;  // cancelling: wait for the worker
            lock.unlock();
            {
                py::gil_scoped_acquire gil;
                if (PyErr_CheckSignals() != 0) {
                    python_error = true;
                } else {
                    try {
                        poll();
                    } catch (py::error_already_set& e) {
                        e.restore();
                        python_error = true;
                    } catch (...) {
                        poll_failure = std::current_exception();
                    }
                }
            }
            if (python_error || poll_failure) cancel.store(true);
            lock.lock();
        }
        lock.unlock();
        worker.join();
    }
    if (python_error) throw py::error_already_set();
    if (poll_failure) std::rethrow_exception(poll_failure);
    if (failure) std::rethrow_exception(failure);
    return std::move(*result);
}

template <class Work>
auto run_released(Work&& work)
{
    return run_released(std::forward<Work>(work), [] {});
}

// ---------------------------------------------------------------- numpy

inline py::array_t<double> vector_array(const double* data, py::ssize_t n)
{
    py::array_t<double> a(n);
    if (n > 0) std::memcpy(a.mutable_data(), data, static_cast<std::size_t>(n) * sizeof(double));
    return a;
}

inline py::array_t<double> vector_array(const std::vector<double>& v)
{
    return vector_array(v.data(), static_cast<py::ssize_t>(v.size()));
}

inline py::array_t<double> vector_array(const Eigen::VectorXd& v) { return vector_array(v.data(), v.size()); }

// (rows, cols) float64 from row-major data.
inline py::array_t<double> rows_array(const double* data, py::ssize_t rows, py::ssize_t cols)
{
    py::array_t<double> a({rows, cols});
    if (rows * cols > 0) std::memcpy(a.mutable_data(), data, static_cast<std::size_t>(rows * cols) * sizeof(double));
    return a;
}

// An Eigen matrix as a C-ordered numpy array (element by element: Eigen is column-major).
inline py::array_t<double> matrix_array(const Eigen::MatrixXd& m)
{
    py::array_t<double> a({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
    auto v = a.mutable_unchecked<2>();
    for (Eigen::Index i = 0; i < m.rows(); ++i)
        for (Eigen::Index j = 0; j < m.cols(); ++j) v(i, j) = m(i, j);
    return a;
}

// Rows of equal-length vectors, (n, cols); NaN where a vector is shorter (a failed job).
inline py::array_t<double> rows_array(const std::vector<Eigen::VectorXd>& v, py::ssize_t cols)
{
    py::array_t<double> a({static_cast<py::ssize_t>(v.size()), cols});
    auto av = a.mutable_unchecked<2>();
    for (std::size_t i = 0; i < v.size(); ++i)
        for (py::ssize_t c = 0; c < cols; ++c)
            av(static_cast<py::ssize_t>(i), c) = c < v[i].size() ? v[i][c] : std::nan("");
    return a;
}

template <class T, class Range, class Get>
py::array_t<T> column(const Range& items, Get&& get)
{
    py::array_t<T> a(static_cast<py::ssize_t>(items.size()));
    auto v = a.template mutable_unchecked<1>();
    py::ssize_t r = 0;
    for (const auto& it : items) v(r++) = static_cast<T>(get(it));
    return a;
}

template <class Range, class Get>
py::list string_list(const Range& items, Get&& get)
{
    py::list l;
    for (const auto& it : items) l.append(py::str(std::string(get(it))));
    return l;
}

template <class T>
py::array_t<std::int64_t> int_array(const std::vector<T>& v)
{
    return column<std::int64_t>(v, [](T x) { return x; });
}

// A state series as its times (n,) and states (n, dim).
inline py::tuple series_arrays(const state_series& s)
{
    return py::make_tuple(vector_array(s.times()),
                          rows_array(s.values().data(), static_cast<py::ssize_t>(s.size()), s.dim()));
}

inline void put_series(py::dict& d, const std::string& prefix, const state_series& s)
{
    d[py::str(prefix + "_t")] = vector_array(s.times());
    d[py::str(prefix)] = rows_array(s.values().data(), static_cast<py::ssize_t>(s.size()), s.dim());
}

// Impacts: times, surfaces, states before and after.
inline void put_impacts(py::dict& d, const std::string& prefix, const impact_series& s)
{
    d[py::str(prefix + "_t")] = vector_array(s.pre.times());
    d[py::str(prefix + "_surface")] = int_array(s.surface);
    d[py::str(prefix + "_pre")] = rows_array(s.pre.values().data(), static_cast<py::ssize_t>(s.size()), s.pre.dim());
    d[py::str(prefix + "_post")] =
        rows_array(s.post.values().data(), static_cast<py::ssize_t>(s.size()), s.post.dim());
}

// The impact statistics of one run by the library's names, excursion_by_surface a list.
inline py::dict statistics_dict(const impact_statistics& s)
{
    py::dict d;
    const auto values = impact_statistics_values(s);
    const auto& names = impact_statistics_names();
    for (std::size_t i = 0; i < names.size(); ++i) d[names[i]] = values[i];
    d["impacts_recorded"] = s.impacts;
    d["excursion_by_surface"] = py::cast(s.excursion_by_surface);
    return d;
}

// ---------------------------------------------------------------- options

// The keyword dict of one call, read key by key. Every key must be read: a key left over is
// a mistake in vimpact/_api.py, not the user's, and fails loudly (TypeError).
class options {
public:
    explicit options(py::dict d) : m_d(std::move(d)) {}

    [[nodiscard]] bool has(const char* key) const { return m_d.contains(key) && !m_d[key].is_none(); }

    template <class T>
    T get(const char* key, T fallback)
    {
        m_used.insert(key);
        if (!has(key)) return fallback;
        return cast<T>(key);
    }
    template <class T>
    T need(const char* key)
    {
        m_used.insert(key);
        if (!has(key)) throw py::type_error(std::string("internal: option '") + key + "' missing");
        return cast<T>(key);
    }
    py::object object(const char* key)
    {
        m_used.insert(key);
        return m_d.contains(key) ? py::object(m_d[key]) : py::object(py::none());
    }
    void finish() const
    {
        for (const auto& [k, v] : m_d) {
            const std::string key = py::str(k);
            if (!m_used.count(key)) throw py::type_error("internal: unknown option '" + key + "'");
        }
    }

private:
    template <class T>
    T cast(const char* key)
    {
        try {
            return m_d[key].cast<T>();
        } catch (const py::cast_error&) {
            if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>)
                if (py::isinstance<py::int_>(m_d[key]))
                    throw input_error(std::string(key) + " = " + std::string(py::str(m_d[key])) +
                                      " does not fit in a " + std::to_string(8 * sizeof(T)) + "-bit integer");
            throw py::type_error(std::string(key) + " has the wrong type (got " +
                                 std::string(py::str(py::type::of(m_d[key]).attr("__name__"))) + ")");
        }
    }

    py::dict m_d;
    std::set<std::string> m_used;
};

// The options an options struct declares (core/option.hpp), read by their keys from the
// keyword dict (a key not given keeps the default); the library checks their ranges.
struct declared_reader {
    options& kw;
    template <class T>
    void operator()(const option& o, T& v) const
    {
        v = kw.get<T>(std::string(o.key).c_str(), v);
    }
    // None: unset, the library's choice.
    template <class T>
    void operator()(const option& o, std::optional<T>& v) const
    {
        const std::string key(o.key);
        if (kw.has(key.c_str())) v = kw.get<T>(key.c_str(), T{});
        else (void)kw.object(key.c_str());
    }
    template <class E, std::size_t K>
    void operator()(const option& o, E& v, const std::array<E, K>& all) const
    {
        const std::string key(o.key);
        v = parse_name(kw.get<std::string>(key.c_str(), std::string(to_string(v))), all, key);
    }
};

template <class O>
void read_declared(options& kw, O& o)
{
    declared_reader r{kw};
    declare(r, o);
}

// The declarations of O for Python: per option its key, help, default (None for an option
// unset by default) and range ("" for any value, or the names of an enumeration's values).
struct declaration_lister {
    py::list out;
    template <class T>
    void operator()(const option& o, const T& v)
    {
        add(o, py::cast(v));
    }
    template <class T>
    void operator()(const option& o, const std::optional<T>& v)
    {
        add(o, v ? py::cast(*v) : py::none());
    }
    void add(const option& o, py::object v)
    {
        out.append(py::dict(py::arg("key") = std::string(o.key), py::arg("help") = std::string(o.help),
                            py::arg("default") = std::move(v),
                            py::arg("range") = o.range.bounded() ? o.range.text() : std::string()));
    }
    template <class E, std::size_t K>
    void operator()(const option& o, const E& v, const std::array<E, K>& all)
    {
        out.append(py::dict(py::arg("key") = std::string(o.key), py::arg("help") = std::string(o.help),
                            py::arg("default") = std::string(to_string(v)), py::arg("range") = name_list(all)));
    }
};

template <class O>
py::list declarations()
{
    declaration_lister l;
    const O o{};
    declare(l, o);
    return l.out;
}

// "maxima" (a section of the model), "impacts" (every surface) or "impacts:SURFACE".
inline section_choice section_of(const model& m, const std::string& name)
{
    if (const auto choice = section_choice_named(m, name)) return *choice;
    if (name.rfind("impacts:", 0) == 0)
        throw input_error("section '" + name + "': model " + m.name() + " has no surface '" + name.substr(8) +
                          "' (surfaces: " + m.info().surface_names() + ")");
    throw input_error("section '" + name + "' is not one of model " + m.name() + "'s: " + section_choice_names(m));
}

// rtol, atol, hold_band and method into the integration options of an analysis that runs
// without the protocol (grazing, response, the steppable systems), whose defaults are its own.
inline void read_integration(options& o, integrator_options& in, integration_method& method)
{
    in.rtol = o.get<double>("rtol", in.rtol);
    in.atol = o.get<double>("atol", in.atol);
    // None: the method's hold band.
    if (const double band = o.get<double>("hold_band", 0.0); o.has("hold_band")) in.hold_band = band;
    method = parse_name(o.get<std::string>("method", std::string(to_string(method))), all_integration_methods,
                        "method");
}

// A state given from Python: exactly dim numbers (empty: the library takes the model's).
inline Eigen::VectorXd state_of(const model& m, const py::object& a, const char* what)
{
    if (a.is_none()) return {};
    const auto arr = a.cast<input_array>();
    if (arr.ndim() != 1) throw input_error(std::string(what) + " must be a 1-D sequence of " + std::to_string(m.dim()) +
                                           " numbers (" + m.info().state_names() + ")");
    check_state_size(m, arr.shape(0), what);
    return Eigen::Map<const Eigen::VectorXd>(arr.data(), arr.shape(0));
}

// Where a single run starts: the state given from Python, or the model's own for None.
inline Eigen::VectorXd initial_state_of(const model& m, const py::object& ic)
{
    Eigen::VectorXd x0 = state_of(m, ic, "ic");
    return x0.size() ? x0 : m.initial_state();
}

// Values of a swept parameter or a grid axis: a 1-D sequence of numbers.
inline std::vector<double> values_of(const py::object& a, const std::string& what)
{
    const auto arr = a.cast<input_array>();
    if (arr.ndim() != 1) throw input_error(what + " must be a 1-D sequence of numbers");
    return {arr.data(), arr.data() + arr.shape(0)};
}

// param, values and ic of an analysis over one parameter's values (a sweep of any kind).
template <class SweepOptions>
void read_parameter_values(const model& m, options& o, SweepOptions& so)
{
    so.parameter = parameter_index(m, o.need<std::string>("param"), "param");
    so.values = values_of(o.object("values"), "values");
    so.initial_state = state_of(m, o.object("ic"), "ic");
}

// The protocol's options: the declared ones (analysis/protocol_declaration.hpp), the section
// and simulate's sample_dt.
inline protocol_options protocol_of(const model& m, options& o)
{
    protocol_options po;
    read_declared(o, po);
    po.section = section_of(m, o.need<std::string>("section"));
    po.sample_dt = o.get<double>("sample_dt", po.sample_dt);
    return po;
}


// ---------------------------------------------------------------- job options

// Progress of a job loop for a Python callback progress(done, total), called from the polling
// thread (which holds the GIL then), never from a worker.
class progress_reporter {
public:
    explicit progress_reporter(py::object callback) : m_callback(std::move(callback)) {}

    std::function<void(long, long)> sink()
    {
        return [this](long done, long total) {
            m_total.store(total, std::memory_order_relaxed);
            m_done.store(done, std::memory_order_relaxed);
        };
    }
    void poll()
    {
        if (m_callback.is_none()) return;
        const long d = m_done.load(std::memory_order_relaxed);
        const long t = m_total.load(std::memory_order_relaxed);
        if (t < 0 || d == m_reported) return;
        m_reported = d;
        m_callback(d, t);
    }

private:
    py::object m_callback;
    std::atomic<long> m_done{0};
    std::atomic<long> m_total{-1};
    long m_reported = -1;
};

// threads, shard (i, n), journal (a directory), resume; the stop flag and the progress sink are
// the caller's (run_jobs below).
inline job_options job_options_of(options& o)
{
    job_options j;
    j.threads = o.get<int>("threads", 0);
    j.batch = o.get<int>("batch", 0);
    if (o.has("shard")) {
        const auto s = o.need<std::pair<long, long>>("shard");
        j.shard = {s.first, s.second};
    }
    (void)o.object("shard");
    if (o.has("journal")) j.journal = std::filesystem::path(o.need<std::string>("journal"));
    (void)o.object("journal");
    j.resume = o.get<bool>("resume", false);
    return j;
}

inline py::dict report_dict(const job_report& r)
{
    py::dict d;
    d["jobs"] = r.jobs;
    d["owned"] = r.owned;
    d["resumed"] = r.resumed;
    d["computed"] = r.computed;
    d["done"] = r.done;
    d["stopped"] = r.stopped;
    d["written_elsewhere"] = r.written_elsewhere;
    d["complete"] = r.complete();
    d["threads"] = r.threads;
    d["batch"] = r.batch;
    return d;
}

// Runs analysis(job_options) with the GIL released: Ctrl-C and an exception from the progress
// callback set the stop flag, which ends the job loop and every running flow; the finished
// jobs are in the journal (if any) for a later resume.
template <class Analysis>
auto run_job_analysis(job_options j, const py::object& progress, Analysis&& analysis)
{
    progress_reporter reporter(progress);
    auto result = run_released(
        [&](const std::atomic<bool>& cancel) {
            job_options c = j;
            c.stop = &cancel;
            c.progress = reporter.sink();
            return analysis(static_cast<const job_options&>(c));
        },
        [&] { reporter.poll(); });
    reporter.poll();  // the last report, often after the last wake-up
    return result;
}

// After a complete run the journal has served its purpose (the caller holds the result).
inline void finish_journal(const job_options& j, const job_report& r, bool keep)
{
    if (j.journal && r.complete() && !keep) remove_journal(*j.journal);
}

// A many-job call once its analysis' keys are read: the job keys (threads, shard, journal,
// resume, keep_journal, progress), then analysis(job_options) run as run_job_analysis does.
// The dict holds the job report ("jobs") and, when the run is complete, what put(dict,
// result) adds.
template <class Analysis, class Put>
py::dict run_jobs(options& o, Analysis&& analysis, Put&& put)
{
    const job_options j = job_options_of(o);
    const bool keep = o.get<bool>("keep_journal", false);
    const py::object progress = o.object("progress");
    o.finish();
    const auto r = run_job_analysis(j, progress, std::forward<Analysis>(analysis));
    py::dict d;
    d["jobs"] = report_dict(r.jobs);
    if (!r.jobs.complete()) return d;
    finish_journal(j, r.jobs, keep);
    put(d, r);
    return d;
}

}  // namespace vimpact::python
