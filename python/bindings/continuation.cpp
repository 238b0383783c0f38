// Continuation of periodic orbits and curves of bifurcation points
// (include/vimpact/analysis/continuation.hpp, bifurcation_curve.hpp). The result crosses as
// the library's JSON form (io/continuation_json.hpp), the same the command line writes, so
// vimpact.Continuation reads both alike.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "bindings.hpp"
#include "common.hpp"
#include "vimpact/analysis/bifurcation_curve.hpp"
#include "vimpact/analysis/continuation.hpp"
#include "vimpact/integrate/tangent_integration.hpp"
#include "vimpact/io/continuation_json.hpp"

namespace vimpact::python {
namespace {

std::string continuation_run(const model& m, const py::list& starts, const py::dict& kw)
{
    options o(kw);
    continuation_options co;
    co.parameter = parameter_index(m, o.need<std::string>("param"), "param");
    co.start = o.need<double>("start");
    co.end = o.need<double>("end");
    co.protocol = protocol_of(m, o);
    read_declared(o, co);
    co.from_attractor = co.returns == 0;
    co.arclength.integration = tangent_integration(co.protocol.flow.integration);
    const int threads = o.get<int>("threads", 0);
    const bool two = o.has("param2");
    curve_options cv;
    if (two) {
        cv.parameter2 = parameter_index(m, o.need<std::string>("param2"), "param2");
        cv.lo2 = o.need<double>("lo2");
        cv.hi2 = o.need<double>("hi2");
        cv.types.clear();
        for (const auto& t : o.need<std::vector<std::string>>("curves"))
            cv.types.push_back(parse_name(t, std::array{bifurcation_type::fold, bifurcation_type::period_doubling,
                                                        bifurcation_type::grazing},
                                          "curves"));
        cv.arclength = co.arclength;
    } else {
        (void)o.object("param2");
        (void)o.object("lo2");
        (void)o.object("hi2");
        (void)o.object("curves");
    }
    o.finish();
    std::vector<Eigen::VectorXd> xs;
    for (const auto& s : starts) xs.push_back(initial_state_of(m, py::reinterpret_borrow<py::object>(s)));
    if (xs.empty()) xs.push_back(m.initial_state());
    if (two) validate(m, co, cv);
    else validate(m, co);
    const auto j = run_released([&](const std::atomic<bool>& cancel) {
        continuation_options c = co;
        c.cancel = &cancel;
        const continuation_result r = continuation(m, xs, c, threads);
        if (!two) return continuation_json(m, c, r);
        const auto curves = r.status == outcome::ok ? continue_bifurcations(m, r, c, cv, threads)
                                                    : std::vector<bifurcation_curve>{};
        return continuation_json(m, c, r, cv, curves);
    });
    return j.dump();
}

}  // namespace

void bind_continuation(py::module_& m)
{
    using namespace pybind11::literals;
    m.def("_continuation", &continuation_run, "model"_a, "starts"_a, "options"_a,
          "Internal: see vimpact.continuation (returns the result's JSON text).");
}

}  // namespace vimpact::python
