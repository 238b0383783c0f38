// The correlation dimension of a point set (include/vimpact/analysis/correlation_dimension.hpp).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <thread>

#include "bindings.hpp"
#include "common.hpp"
#include "vimpact/analysis/correlation_dimension.hpp"
#include "vimpact/analysis/dimension_points.hpp"
#include "vimpact/model/model.hpp"
#include "vimpact/jobs/job_options.hpp"

namespace vimpact::python {
namespace {

py::dict dimension(const input_array& points, const py::dict& declared, const std::array<double, 3>& radii,
                   const std::optional<std::array<double, 2>>& fit_range, int threads)
{
    if (points.ndim() != 2) throw input_error("points must be a 2-D array (one point per row)");
    point_set ps(static_cast<int>(points.shape(1)));
    ps.reserve(static_cast<std::size_t>(points.shape(0)));
    for (py::ssize_t i = 0; i < points.shape(0); ++i) ps.push_back(points.data(i, 0));

    dimension_options o;
    options kw(declared);
    read_declared(kw, o);
    kw.finish();
    o.centre.r_min = radii[0];
    o.centre.r_max = radii[1];
    o.centre.r_step = radii[2];
    o.correlation.threads = resolve_threads(threads);
    o.scaling.fit_range = fit_range;

    // No cancel flag in the dimension code: Ctrl-C is honoured when it returns.
    const auto r = run_released([&](const std::atomic<bool>&) { return correlation_dimension(ps, o); });
    const auto& f = r.fit;
    py::dict d;
    d["estimator"] = std::string(to_string(r.estimator));
    d["points"] = r.points;
    d["embedding"] = r.embedding;
    d["dimension"] = f.dimension;
    d["found"] = f.found;
    d["automatic"] = f.automatic;
    d["intercept"] = f.intercept;
    d["r2"] = f.r2;
    d["slope_error"] = f.slope_error;
    d["slope_spread"] = f.slope_spread;
    d["fit_range"] = py::make_tuple(f.r_min, f.r_max);
    d["fitted"] = f.fitted;
    d["fit_first"] = f.first;
    d["fit_last"] = f.last;
    d["r"] = vector_array(r.curve.r);
    d["pairs"] = column<std::int64_t>(r.curve.pairs, [](std::uint64_t p) { return p; });
    d["total_pairs"] = r.curve.total_pairs;
    d["local_slope"] = vector_array(f.local_slope);
    d["centres"] = column<std::int64_t>(r.centres, [](std::size_t c) { return c; });
    d["r_cap"] = r.r_cap;
    d["all_pairs"] = r.all_pairs;
    return d;
}

}  // namespace

void bind_dimension(py::module_& m)
{
    using namespace pybind11::literals;
    // The points of recorded states as the command line takes them (state_point_table): every
    // state variable, a phase as its (cos, sin) pair.
    m.def(
        "_state_points",
        [](const model& mo, const input_array& states) {
            if (states.ndim() != 2 || states.shape(1) != mo.dim())
                throw input_error("states must have one row per point and " + std::to_string(mo.dim()) + " columns");
            state_series series(mo.dim());
            for (py::ssize_t i = 0; i < states.shape(0); ++i) series.push_back(0.0, states.data(i, 0));
            const point_table t = state_point_table(mo.info(), series);
            py::array_t<double> a({static_cast<py::ssize_t>(series.size()), static_cast<py::ssize_t>(t.header.size())});
            auto v = a.mutable_unchecked<2>();
            for (std::size_t c = 0; c < t.columns.size(); ++c)
                for (std::size_t i = 0; i < t.columns[c].size(); ++i)
                    v(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(c)) = t.columns[c][i];
            return py::make_tuple(t.header, a);
        },
        "model"_a, "states"_a, "Internal: see vimpact.dimension.");

    m.def("_dimension", &dimension, "points"_a, "declared"_a, "radii"_a, "fit_range"_a, "threads"_a,
          "Internal: see vimpact.dimension.");
}

}  // namespace vimpact::python
