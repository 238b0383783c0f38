#pragma once
// What every binding shares: running library work with the GIL released and Ctrl-C honoured,
// numpy conversions, and the protocol options built from keyword arguments.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "vimpact/analysis/job_points.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/hybrid/run_stats.hpp"

namespace vimpact::python {

namespace py = pybind11;

// Any array-like of numbers, read as contiguous float64.
using input_array = py::array_t<double, py::array::c_style | py::array::forcecast>;

inline constexpr input_spelling spelling = input_spelling::python;

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

inline py::array_t<double> new_array(py::ssize_t n) { return py::array_t<double>(n); }
inline py::array_t<double> new_array(py::ssize_t rows, py::ssize_t cols)
{
    return py::array_t<double>({rows, cols});
}

template <int N>
py::array_t<double> vector_array(const vec<N>& x)
{
    auto a = new_array(N);
    auto v = a.mutable_unchecked<1>();
    for (int i = 0; i < N; ++i) v(i) = x[i];
    return a;
}

// Rows of states, (n, N), and their times, (n,).
template <int N, class Range, class Get>
py::array_t<double> state_rows(const Range& items, Get&& get)
{
    auto a = new_array(static_cast<py::ssize_t>(items.size()), N);
    auto v = a.template mutable_unchecked<2>();
    py::ssize_t r = 0;
    for (const auto& it : items) {
        const vec<N>& x = get(it);
        for (int i = 0; i < N; ++i) v(r, i) = x[i];
        ++r;
    }
    return a;
}

template <class Range, class Get>
py::array_t<double> scalar_rows(const Range& items, Get&& get)
{
    auto a = new_array(static_cast<py::ssize_t>(items.size()));
    auto v = a.template mutable_unchecked<1>();
    py::ssize_t r = 0;
    for (const auto& it : items) v(r++) = get(it);
    return a;
}

template <class T, class Range, class Get>
py::array_t<T> typed_rows(const Range& items, Get&& get)
{
    py::array_t<T> a(static_cast<py::ssize_t>(items.size()));
    auto v = a.template mutable_unchecked<1>();
    py::ssize_t r = 0;
    for (const auto& it : items) v(r++) = static_cast<T>(get(it));
    return a;
}

// A state given from Python: exactly Model::dim numbers.
template <class Model>
vec<Model::dim> state_of(const Model& m, const input_array& a, const char* what)
{
    if (a.ndim() != 1 || a.shape(0) != Model::dim) {
        std::string names;
        for (const auto& n : state_axis_names(m)) names += (names.empty() ? "" : ", ") + std::string(n);
        std::string shape = "(";
        for (py::ssize_t i = 0; i < a.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(a.shape(i));
        shape += a.ndim() == 1 ? ",)" : ")";
        throw input_error(std::string(what) + " must hold " + std::to_string(Model::dim) + " numbers (" + names +
                          "), got shape " + shape);
    }
    vec<Model::dim> x;
    for (int i = 0; i < Model::dim; ++i) x[i] = a.at(i);
    return x;
}

// Values of a swept parameter or a grid axis: a non-empty 1-D sequence of finite numbers.
inline std::vector<double> values_of(const input_array& a, const std::string& what)
{
    if (a.ndim() != 1) throw input_error(what + " must be a 1-D sequence of numbers");
    if (a.shape(0) < 1) throw input_error(what + " must hold at least one value");
    std::vector<double> v(a.data(), a.data() + a.shape(0));
    for (std::size_t i = 0; i < v.size(); ++i)
        if (!std::isfinite(v[i]))
            throw input_error(what + " must be finite (got " + format_double(v[i]) + " at index " +
                              std::to_string(i) + ")");
    return v;
}

inline py::dict stats_dict(const run_stats& s)
{
    py::dict d;
    d["steps"] = s.steps;
    d["rejected"] = s.rejected;
    d["rhs_calls"] = s.rhs_calls;
    d["impacts"] = s.impacts;
    d["sections"] = s.sections;
    d["sticking_phases"] = s.sticking_phases;
    d["sticking_time"] = s.sticking_time;
    d["h_min"] = s.h_min;
    d["h_max"] = s.h_max;
    d["t_final"] = s.t_final;
    return d;
}

// ---------------------------------------------------------------- options

// The protocol's options from keyword arguments; validated by the library (same messages as
// the command line).
inline protocol_options protocol_of(long transient, long record, double rtol, double atol, const std::string& section,
                                    double sample_dt, double quiet_time, double t_max)
{
    protocol_options po;
    po.transient_impacts = transient;
    po.record_points = record;
    po.section = parse_section_choice(section, spelling);
    po.sample_dt = sample_dt;
    po.quiet_time = quiet_time;
    po.flow.integration.rtol = rtol;
    po.flow.integration.atol = atol;
    if (!(t_max > 0.0)) throw input_error("t_max must be > 0 (got " + format_double(t_max) + ")");
    po.flow.t_max = t_max;
    validate(po);
    return po;
}

// Integration tolerances alone, checked by the protocol's rule.
inline integrator_options tolerances_of(double rtol, double atol)
{
    protocol_options probe;
    probe.flow.integration.rtol = rtol;
    probe.flow.integration.atol = atol;
    validate(probe);
    return probe.flow.integration;
}

// Progress of a job loop for a Python callback progress(done, total), called from the polling
// thread (which holds the GIL then), never from a worker.
class progress_reporter {
public:
    progress_reporter(py::object callback, long total) : m_callback(std::move(callback)), m_total(total) {}

    std::function<void(long, long)> sink()
    {
        return [this](long done, long) { m_done.store(done, std::memory_order_relaxed); };
    }
    void poll()
    {
        if (m_callback.is_none()) return;
        const long d = m_done.load(std::memory_order_relaxed);
        if (d == m_reported) return;
        m_reported = d;
        m_callback(d, m_total);
    }
    void finish()
    {
        m_done.store(m_total);
        poll();
    }

private:
    py::object m_callback;
    long m_total;
    std::atomic<long> m_done{0};
    long m_reported = -1;
};

}  // namespace vimpact::python
