// The many-job analyses: sweep, map, basins, response. Each reads its options into the
// library's, runs the library function with the GIL released (threads, shard, journal and
// resume as given; Ctrl-C or an exception from the progress callback stops it) and returns a
// dict of numpy arrays in job order, or only the job report when the run is not complete (a
// shard whose partners have not finished). vimpact/_api.py shapes it into a result object.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "common.hpp"
#include "records.hpp"
#include "vimpact/analysis/basins.hpp"
#include "vimpact/analysis/clearance.hpp"
#include "vimpact/analysis/map.hpp"
#include "vimpact/analysis/response.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/physical/si_units.hpp"

namespace vimpact::python {
namespace {

// Rows of `width` values (per surface, per switch), NaN where a row has fewer.
py::array_t<double> padded_rows(const std::vector<std::vector<double>>& v, int width)
{
    py::array_t<double> a({static_cast<py::ssize_t>(v.size()), static_cast<py::ssize_t>(width)});
    auto av = a.mutable_unchecked<2>();
    for (std::size_t i = 0; i < v.size(); ++i)
        for (int s = 0; s < width; ++s)
            av(static_cast<py::ssize_t>(i), s) =
                static_cast<std::size_t>(s) < v[i].size() ? v[i][static_cast<std::size_t>(s)] : std::nan("");
    return a;
}

// ---------------------------------------------------------------- sweep

py::dict sweep_run(const model& m, const py::dict& kw)
{
    options o(kw);
    sweep_options so;
    read_parameter_values(m, o, so);
    read_declared(o, so);
    so.protocol = protocol_of(m, o);
    if (o.has("grazing")) so.grazing_parameter = parameter_index(m, o.need<std::string>("grazing"), "grazing");
    (void)o.object("grazing");
    const auto analysis = [&](const job_options& c) { return sweep(m, so, c); };
    return run_jobs(o, analysis, [&](py::dict& d, const sweep_result& r) {
        d["records"] = record_arrays(r.points, m);
    });
}

// ---------------------------------------------------------------- map

py::dict map_run(const model& m, const py::dict& kw)
{
    options o(kw);
    map_options mo;
    mo.x.parameter = parameter_index(m, o.need<std::string>("x"), "x");
    mo.x.values = values_of(o.object("x_values"), "x values");
    mo.y.parameter = parameter_index(m, o.need<std::string>("y"), "y");
    mo.y.values = values_of(o.object("y_values"), "y values");
    mo.initial_state = state_of(m, o.object("ic"), "ic");
    mo.protocol = protocol_of(m, o);
    read_declared(o, mo);
    const auto analysis = [&](const job_options& c) { return map2d(m, mo, c); };
    return run_jobs(o, analysis, [&](py::dict& d, const map_result& r) {
        d["records"] = record_arrays(r.cells, m);
        d["grazing_axis"] = r.grazing_axis;
        d["grazing_other"] = vector_array(r.grazing_other);
        d["grazing"] = padded_rows(r.grazing_values, m.surface_count());
        d["switch_grazing"] = padded_rows(r.grazing_switch_values, static_cast<int>(m.info().switches.size()));
    });
}

// ---------------------------------------------------------------- basins

py::dict basins_run(const model& m, const py::dict& kw)
{
    options o(kw);
    basins_options bo;
    bo.x_state = state_index(m, o.need<std::string>("x"), "x");
    bo.x_values = values_of(o.object("x_values"), "x values");
    bo.y_state = state_index(m, o.need<std::string>("y"), "y");
    bo.y_values = values_of(o.object("y_values"), "y values");
    bo.initial_state = state_of(m, o.object("ic"), "ic");
    bo.protocol = protocol_of(m, o);
    read_declared(o, bo);
    const auto analysis = [&](const job_options& c) { return basins(m, bo, c); };
    return run_jobs(o, analysis, [&](py::dict& d, const basins_result& r) {
        d["records"] = record_arrays(r.cells, m);
        py::list table;
        for (std::size_t i = 0; i < r.attractors.size(); ++i) {
            const auto& e = r.attractors[i];
            const auto& s = e.signature;
            py::dict a;
            a["id"] = static_cast<long>(i);
            a["label"] = s.label;
            a["cells"] = e.members;
            a["cycle"] = rows_array(s.cycle, s.lo.size());
            if (s.lo.size()) {
                a["box"] = rows_array(std::vector<Eigen::VectorXd>{s.lo, s.hi}, s.lo.size());
            } else {
                a["box"] = py::none();
            }
            table.append(a);
        }
        d["attractors"] = table;
    });
}

// ---------------------------------------------------------------- response

py::dict response_run(const model& m, const py::dict& kw)
{
    options o(kw);
    response_options ro;
    ro.parameter = parameter_index(m, o.need<std::string>("param"), "param");
    ro.values = values_of(o.object("values"), "values");
    for (const auto& curve : o.object("curves")) {
        std::vector<std::pair<int, double>> c;
        for (const auto& [k, v] : curve.cast<py::dict>()) {
            const std::string name = py::str(k);
            c.emplace_back(parameter_index(m, name, "curves"), v.cast<double>());
        }
        ro.curves.push_back(std::move(c));
    }
    ro.variable = state_index(m, o.need<std::string>("variable"), "variable");
    ro.initial_state = state_of(m, o.object("ic"), "ic");
    grazing_options& go = ro.grazing;
    read_integration(o, go.integration, go.method);
    read_declared(o, ro);
    if (o.has("grazing")) go.parameter = parameter_index(m, o.need<std::string>("grazing"), "grazing");
    (void)o.object("grazing");
    const auto analysis = [&](const job_options& c) { return response(m, ro, c); };
    return run_jobs(o, analysis, [&](py::dict& d, const response_result& r) {
        d["records"] = record_arrays(r.points, m);
    });
}

// ---------------------------------------------------------------- clearance

py::dict clearance_run(const model& m, const py::dict& kw)
{
    options o(kw);
    clearance_options co;
    co.parameter = parameter_index(m, o.need<std::string>("param"), "param");
    co.values = values_of(o.object("values"), "values");
    if (o.has("gap_param")) co.gap_parameter = parameter_index(m, o.need<std::string>("gap_param"), "gap_param");
    (void)o.object("gap_param");
    // With units, gaps and results in SI (the library converts both ways).
    std::optional<si_input> units;
    if (o.has("units")) units = o.object("units").cast<si_input>();
    (void)o.object("units");
    if (o.has("gaps")) {
        const auto gaps = values_of(o.object("gaps"), "gaps");
        co.gaps = units ? gaps_in_model_units(*units, gaps) : gaps;
    }
    (void)o.object("gaps");
    if (o.has("fractions")) co.fractions = values_of(o.object("fractions"), "fractions");
    (void)o.object("fractions");
    co.initial_state = state_of(m, o.object("ic"), "ic");
    co.protocol = protocol_of(m, o);
    read_declared(o, co);
    co.grazing = job_grazing_options(co.protocol.flow.integration, co.grazing.transient_time);
    co.grazing.method = co.protocol.method;
    const auto analysis = [&](const job_options& c) { return clearance(m, co, c); };
    // The values' records and the chart cells', value after value, with the index of their value.
    const auto put = [&](py::dict& d, const clearance_result& r) {
        std::vector<clearance_cell> cells;
        std::vector<long> point;
        for (std::size_t k = 0; k < r.points.size(); ++k)
            for (const auto& c : r.points[k].cells) {
                cells.push_back(c);
                point.push_back(static_cast<long>(k));
            }
        d["records"] = record_arrays(r.points, m);
        d["cells"] = record_arrays(cells, m);
        d["cell_point"] = int_array(point);
    };
    return run_jobs(o, analysis, [&](py::dict& d, const clearance_result& r) {
        d["gap_param"] = m.info().parameters[static_cast<std::size_t>(r.gap_parameter)].name;
        if (r.surface >= 0) d["surface"] = m.info().surfaces[static_cast<std::size_t>(r.surface)].name;
        else d["switch"] = m.info().switches[static_cast<std::size_t>(r.switch_index)].name;
        put(d, r);
        if (!units) return;
        py::dict si;
        put(si, in_si(r, *units, m, co.parameter));
        d["si"] = si;
    });
}

}  // namespace

void bind_jobs(py::module_& m)
{
    using namespace pybind11::literals;
    m.def("_sweep", &sweep_run, "model"_a, "options"_a, "Internal: see vimpact.sweep.");
    m.def("_map", &map_run, "model"_a, "options"_a, "Internal: see vimpact.map.");
    m.def("_basins", &basins_run, "model"_a, "options"_a, "Internal: see vimpact.basins.");
    m.def("_response", &response_run, "model"_a, "options"_a, "Internal: see vimpact.response.");
    m.def("_clearance", &clearance_run, "model"_a, "options"_a, "Internal: see vimpact.clearance.");
}

}  // namespace vimpact::python
