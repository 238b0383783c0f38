// _HybridSystem, _SectionSystem, _TangentSystem: the library's steppable systems
// (include/vimpact/system/) as Python objects; vimpact/_systems.py documents them. A call that
// may run long (many steps, a time to reach) releases the GIL and stops on Ctrl-C: the system
// then has the outcome `interrupted` until reinit.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "bindings.hpp"
#include "common.hpp"
#include "records.hpp"
#include "vimpact/system/hybrid_system.hpp"
#include "vimpact/system/section_system.hpp"
#include "vimpact/system/tangent_system.hpp"

namespace vimpact::python {

namespace {

// A system with the flag its flow polls (flow_options::cancel), which outlives it.
template <class System>
struct held {
    std::unique_ptr<std::atomic<bool>> flag = std::make_unique<std::atomic<bool>>(false);
    std::optional<System> sys;
};

// f() with the GIL released; Ctrl-C (run_released's cancel) is relayed to the system's flag.
template <class System, class F>
auto released(held<System>& h, F&& f)
{
    h.flag->store(false);
    return run_released([&](const std::atomic<bool>& cancel) {
        std::mutex mutex;
        std::condition_variable wake;
        bool done = false;
        std::thread relay([&] {
            std::unique_lock lock(mutex);
            while (!wake.wait_for(lock, std::chrono::milliseconds(20), [&] { return done; }))
                if (cancel.load()) h.flag->store(true);
        });
        auto finish = [&] {
            {
                std::lock_guard lock(mutex);
                done = true;
            }
            wake.notify_all();
            relay.join();
        };
        try {
            auto r = f();
            finish();
            return r;
        } catch (...) {
            finish();
            throw;
        }
    });
}

flow_options flow_of(options& o, integration_method& method, std::atomic<bool>* flag)
{
    flow_options f;
    read_integration(o, f.integration, method);
    f.t_max = o.get<double>("t_max", f.t_max);
    f.max_steps = o.get<long>("max_steps", f.max_steps);
    f.cancel = flag;
    return f;
}

py::dict impacts_dict(const impact_series& s, const char* prefix = "impact")
{
    py::dict d;
    put_impacts(d, prefix, s);
    return d;
}

std::string status_of(outcome o) { return std::string(to_string(o)); }

Eigen::MatrixXd matrix_of(const py::object& a, const char* what)
{
    const auto arr = a.cast<input_array>();
    if (arr.ndim() != 2) throw input_error(std::string(what) + " must be a 2-D array (state dimension x deviations)");
    Eigen::MatrixXd w(arr.shape(0), arr.shape(1));
    for (py::ssize_t i = 0; i < arr.shape(0); ++i)
        for (py::ssize_t j = 0; j < arr.shape(1); ++j) w(i, j) = arr.at(i, j);
    return w;
}

using hybrid_held = held<hybrid_system>;
using section_held = held<section_system>;
using tangent_held = held<tangent_system>;

// What the three classes share: state, time, status, stats, parameters.
template <class Held>
void bind_common(py::class_<Held>& cls)
{
    cls.def_property_readonly("state", [](const Held& h) { return vector_array(h.sys->state()); })
        .def_property_readonly("time", [](const Held& h) { return h.sys->time(); })
        .def_property_readonly("status", [](const Held& h) { return status_of(h.sys->status()); })
        .def_property_readonly("stats", [](const Held& h) { return record_dict(h.sys->stats(), h.sys->system_model()); })
        .def_property_readonly("parameters", [](const Held& h) { return h.sys->parameters(); })
        .def("set_parameter", [](Held& h, int i, double v) { h.sys->set_parameter(i, v); });
}

}  // namespace

void bind_systems(py::module_& m)
{
    py::class_<hybrid_held> hybrid(m, "_HybridSystem", "Internal: see vimpact.HybridSystem.");
    bind_common(hybrid);
    hybrid.def(py::init([](const model& md, const py::object& ic, double t, const py::dict& kw) {
                 auto h = std::make_unique<hybrid_held>();
                 options o(kw);
                 hybrid_system_options so;
                 so.flow = flow_of(o, so.method, h->flag.get());
                 o.finish();
                 h->sys.emplace(md, initial_state_of(md, ic), t, so);
                 return h;
             }),
             py::arg("model"), py::arg("ic"), py::arg("t"), py::arg("options"))
        .def_property_readonly("impacts", [](const hybrid_held& h) { return impacts_dict(h.sys->impacts()); })
        .def_property_readonly("switchings",
                               [](const hybrid_held& h) { return impacts_dict(h.sys->switchings(), "switching"); })
        .def_property_readonly("in_contact", [](const hybrid_held& h) { return h.sys->in_contact(); })
        .def("step", [](hybrid_held& h) { return status_of(h.sys->step()); })
        .def("advance_to",
             [](hybrid_held& h, double t) { return status_of(released(h, [&] { return h.sys->advance_to(t); })); },
             py::arg("t"))
        .def("reinit", [](hybrid_held& h, const py::object& ic, double t) {
                 h.sys->reinit(state_of(h.sys->system_model(), ic, "ic"), t);
             }, py::arg("ic"), py::arg("t"));

    py::class_<section_held> section(m, "_SectionSystem", "Internal: see vimpact.SectionSystem.");
    bind_common(section);
    section.def(py::init([](const model& md, const py::object& ic, double t, const py::dict& kw) {
                 auto h = std::make_unique<section_held>();
                 options o(kw);
                 section_system_options so;
                 so.section = section_of(md, o.need<std::string>("section"));
                 so.max_return_time = o.get<double>("max_return_time", so.max_return_time);
                 so.flow = flow_of(o, so.method, h->flag.get());
                 o.finish();
                 h->sys.emplace(md, initial_state_of(md, ic), t, so);
                 return h;
             }),
             py::arg("model"), py::arg("ic"), py::arg("t"), py::arg("options"))
        .def_property_readonly("impacts", [](const section_held& h) { return impacts_dict(h.sys->impacts()); })
        .def_property_readonly("switchings",
                               [](const section_held& h) { return impacts_dict(h.sys->switchings(), "switching"); })
        .def("step",
             [](section_held& h, long n) {
                 if (n == 1) return status_of(h.sys->step());  // no thread for one return
                 return status_of(released(h, [&] { return h.sys->step(n); }));
             },
             py::arg("n"))
        .def("reinit", [](section_held& h, const py::object& ic, double t) {
                 h.sys->reinit(state_of(h.sys->system_model(), ic, "ic"), t);
             }, py::arg("ic"), py::arg("t"));

    py::class_<tangent_held> tangent(m, "_TangentSystem", "Internal: see vimpact.TangentSystem.");
    bind_common(tangent);
    tangent.def(py::init([](const model& md, const py::object& ic, double t, const py::dict& kw) {
                 auto h = std::make_unique<tangent_held>();
                 options o(kw);
                 tangent_system_options so;
                 if (o.has("section")) {
                     const section_choice s = section_of(md, o.need<std::string>("section"));
                     if (s.type != section_choice::kind::crossing)
                         throw input_error("section: a tangent system maps a model section (" +
                                           md.info().section_names() + "), not impacts");
                     so.section = s.index;
                 } else {
                     o.object("section");
                 }
                 so.deviations = o.get<int>("deviations", so.deviations);
                 so.max_return_time = o.get<double>("max_return_time", so.max_return_time);
                 integration_method method = integration_method::dop853;  // the tangent's, always
                 so.flow = flow_of(o, method, h->flag.get());
                 o.finish();
                 h->sys.emplace(md, initial_state_of(md, ic), t, so);
                 return h;
             }),
             py::arg("model"), py::arg("ic"), py::arg("t"), py::arg("options"))
        .def_property_readonly("deviations", [](const tangent_held& h) { return matrix_array(h.sys->deviations()); })
        .def_property_readonly("discrete", [](const tangent_held& h) { return h.sys->discrete(); })
        .def("step",
             [](tangent_held& h, long n) {
                 if (n == 1) return status_of(h.sys->step());
                 return status_of(released(h, [&] { return h.sys->step(n); }));
             },
             py::arg("n"))
        .def("advance_to",
             [](tangent_held& h, double t) { return status_of(released(h, [&] { return h.sys->advance_to(t); })); },
             py::arg("t"))
        .def("set_deviations", [](tangent_held& h, const py::object& w) { h.sys->set_deviations(matrix_of(w, "w")); },
             py::arg("w"))
        .def("reinit", [](tangent_held& h, const py::object& ic, double t, const py::object& w) {
                 const Eigen::VectorXd x = state_of(h.sys->system_model(), ic, "ic");
                 if (w.is_none()) h.sys->reinit(x, t);
                 else h.sys->reinit(x, t, matrix_of(w, "w"));
             }, py::arg("ic"), py::arg("t"), py::arg("w"));
}

}  // namespace vimpact::python
