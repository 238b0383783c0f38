// SI units: the engineer's inputs (physical/si_units.hpp) as _SIUnits, and the cylinder's
// conversion at one flow speed. vimpact/_units.py builds vimpact.PhysicalUnits on it.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "common.hpp"
#include "vimpact/physical/si_units.hpp"

namespace vimpact::python {
namespace {

py::dict named(const std::vector<named_value>& values)
{
    py::dict d;
    for (const auto& [name, value] : values) d[name] = value;
    return d;
}

// A dict of impact statistics (statistics_dict's names) back to the library's value.
impact_statistics statistics_of(const py::dict& d)
{
    std::vector<double> v;
    for (const char* name : impact_statistics_names()) {
        if (!d.contains(name)) throw input_error(std::string("statistics: no '") + name + "'");
        v.push_back(d[name].cast<double>());
    }
    impact_statistics s = impact_statistics_from_values(v);
    if (d.contains("excursion_by_surface")) s.excursion_by_surface = d["excursion_by_surface"].cast<std::vector<double>>();
    return s;
}

}  // namespace

void bind_units(py::module_& m)
{
    using namespace pybind11::literals;
    py::class_<si_input>(m, "_SIUnits", "Internal: see vimpact.PhysicalUnits.")
        .def(py::init([](const std::vector<std::pair<std::string, double>>& pairs) { return si_from_pairs(pairs); }),
             "pairs"_a)
        .def_property_readonly("inputs", [](const si_input& in) { return named(si_inputs(in)); })
        .def_property_readonly("cylinder", [](const si_input& in) { return in.cylinder.has_value(); })
        .def("apply", [](const si_input& in, const model& mm) { return apply_si(mm, in); }, "model"_a)
        .def(
            "parameters",
            [](const si_input& in, const model& mm) {
                py::dict d;
                for (const auto& [i, v] : si_parameters(mm, in)) d[py::str(mm.info().parameters[static_cast<std::size_t>(i)].name)] = v;
                return d;
            },
            "model"_a)
        .def(
            "parameter",
            [](const si_input& in, const model& mm, const std::string& quantity, double value) {
                const int p = si_parameter(in, mm, quantity);
                if (p < 0) throw input_error("'" + quantity + "' is not an SI quantity (U, gap)");
                return py::make_tuple(mm.info().parameters[static_cast<std::size_t>(p)].name,
                                      si_parameter_value(in, mm, quantity, value));
            },
            "model"_a, "quantity"_a, "value"_a)
        .def("values", [](const si_input& in, const model& mm) { return named(si_values(in, mm)); }, "model"_a)
        .def("flow_speed", &flow_speed_of, "model"_a)
        .def("gap", &gap_of, "model"_a)
        .def("length_scale", &length_scale)
        .def(
            "at",
            [](const si_input& in, double U) {
                if (!in.cylinder) throw input_error("units: a flow speed needs a cylinder (D, m or mstar, fn or k, zeta, rho)");
                return named(units_at(*in.cylinder, U));
            },
            "U"_a)
        .def("warnings", [](const si_input& in, const model& mm) { return validity_warnings(in, mm); }, "model"_a)
        .def(
            "statistics",
            [](const si_input& in, const model& mm, const py::dict& s) {
                return statistics_dict(in_si(statistics_of(s), scales_at(in, mm)));
            },
            "model"_a, "statistics"_a);
    m.def("_impact_statistics_names", [] {
        std::vector<std::string> out;
        for (const char* n : impact_statistics_names()) out.emplace_back(n);
        return out;
    });
}

}  // namespace vimpact::python
