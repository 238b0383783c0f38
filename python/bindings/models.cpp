// The library's model handle as _Model: how it is made (built-in, file, TOML text, JSON
// description), what it says about itself, copies with other parameters, and its vector
// field. vimpact/_model.py builds the user's vimpact.Model on it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "common.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/io/model_info_json.hpp"
#include "vimpact/model/model_file.hpp"

namespace vimpact::python {
namespace {

Eigen::VectorXd point_of(const model& m, const input_array& x)
{
    if (x.ndim() != 1)
        throw input_error("x must be a 1-D sequence of " + std::to_string(m.dim()) + " numbers (" +
                          m.info().state_names() + ")");
    check_state_size(m, x.shape(0), "x");
    return Eigen::Map<const Eigen::VectorXd>(x.data(), x.shape(0));
}

}  // namespace

void bind_models(py::module_& m)
{
    py::class_<model> cls(m, "_Model", "Internal: the library's model handle; see vimpact.Model.");
    cls.def_static("builtin", &model::builtin, py::arg("name"));
    cls.def_static("builtin_names", &model::builtin_names);
    cls.def_static(
        "from_file",
        [](const std::string& path) {
            // Ctrl-C stops a compilation at once (KeyboardInterrupt, nothing left in the cache).
            return run_released(
                [&](const std::atomic<bool>& cancel) { return model::with_defaults(load_model_code(path, &cancel)); });
        },
        py::arg("path"));
    cls.def_static(
        "from_toml",
        [](const std::string& text, const std::string& source) {
            return run_released([&](const std::atomic<bool>& cancel) {
                return model::with_defaults(compile_model_text(text, source, &cancel));
            });
        },
        py::arg("text"), py::arg("source"));
    // The description as JSON text (Python's json.dumps keeps the dict's key order, which is
    // the order of the parameters).
    cls.def_static(
        "from_json",
        [](const std::string& text, const std::string& source) {
            nlohmann::ordered_json tree;
            try {
                tree = nlohmann::ordered_json::parse(text);
            } catch (const nlohmann::json::exception& e) {
                throw input_error("model description " + source + ": " + e.what());
            }
            return run_released([&](const std::atomic<bool>& cancel) {
                return model::with_defaults(compile_model_json(tree, source, &cancel));
            });
        },
        py::arg("text"), py::arg("source"));
    // As JSON text (io/model_info_json.hpp): vimpact/_model.py reads it with json.loads.
    cls.def_property_readonly("info", [](const model& x) { return model_info_json(x.info()).dump(); });
    cls.def_property_readonly("identity", [](const model& x) { return x.info().identity; });
    cls.def_property_readonly("parameters", [](const model& x) { return x.parameters(); });
    cls.def("with_parameters",
            [](const model& x, const std::vector<double>& values) { return x.with_parameters(values); });
    cls.def("with_preset", &model::with_preset);
    cls.def(
        "rhs", [](const model& x, const input_array& p) {
            const Eigen::VectorXd s = point_of(x, p);
            Eigen::VectorXd f(x.dim());
            x.table().rhs(x.context(), s.data(), f.data());
            return vector_array(f);
        });
    cls.def(
        "jacobian", [](const model& x, const input_array& p) {
            const Eigen::VectorXd s = point_of(x, p);
            Eigen::MatrixXd J(x.dim(), x.dim());  // column-major, as the table writes it
            x.table().jacobian(x.context(), s.data(), J.data());
            return matrix_array(J);
        });
    cls.def(
        "gaps", [](const model& x, const input_array& p) {
            const Eigen::VectorXd s = point_of(x, p);
            std::vector<double> g;
            for (int i = 0; i < x.surface_count(); ++i) g.push_back(x.table().gap(x.context(), i, s.data()));
            return vector_array(g);
        });
    cls.def("gap_parameters", [](const model& x, int surface) { return gap_parameters(x, surface); });
    cls.def("first_gap_parameter", [](const model& x) { return first_gap_parameter(x); });
    cls.def("first_grazing_parameter", [](const model& x) { return first_grazing_parameter(x); });
    cls.def("default_section", [](const model& x) { return section_choice_name(x, default_section(x)); });
    cls.def("parameter_enters_field", [](const model& x, int p) { return parameter_enters_field(x, p); });
    cls.def("__eq__", [](const model& a, const model& b) { return a == b; }, py::is_operator());
}

}  // namespace vimpact::python
