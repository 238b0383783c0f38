// The models as Python classes: immutable values with their parameters as attributes.
#include <pybind11/pybind11.h>

#include <cmath>
#include <functional>
#include <string>

#include "bindings.hpp"
#include "common.hpp"

namespace vimpact::python {
namespace {

template <class Model>
const auto& table_of()
{
    if constexpr (std::is_same_v<Model, wake_impact>) return wake_impact_parameter_table();
    else return forced_impact_parameter_table();
}

template <class Model>
Model make_model(typename Model::parameters p, const py::dict& kwargs)
{
    for (const auto& [key, value] : kwargs) {
        const std::string name = py::str(key);
        double v = 0.0;
        try {
            v = value.template cast<double>();
        } catch (const py::cast_error&) {
            throw py::type_error("parameter " + name + " must be a number (got " +
                                 std::string(py::str(py::type::of(value).attr("__name__"))) + ")");
        }
        set_parameter(p, table_of<Model>(), name, v);
    }
    return Model(p);
}

template <class Model>
py::dict parameters_dict(const Model& m)
{
    py::dict d;
    for (const auto& info : table_of<Model>()) d[py::str(std::string(info.name))] = m.params().*(info.member);
    return d;
}

template <class Model>
std::string parameters_text(const Model& m)
{
    std::string s;
    for (const auto& info : table_of<Model>())
        s += (s.empty() ? "" : ", ") + std::string(info.name) + "=" + format_double(m.params().*(info.member));
    return s;
}

// "name : float, default D\n    meaning; valid range R." for every parameter.
template <class Model>
std::string parameters_doc()
{
    const typename Model::parameters defaults{};
    std::string s;
    for (const auto& info : table_of<Model>())
        s += std::string(info.name) + " : float, default " + format_double(defaults.*(info.member)) + "\n    " +
             std::string(info.meaning) + "; valid range " + info.range_text() + ".\n";
    return s;
}

template <class Model>
std::size_t parameters_hash(const Model& m)
{
    std::size_t h = 0;
    for (const auto& info : table_of<Model>())
        h = h * 1000003u ^ std::hash<double>{}(m.params().*(info.member));
    return h;
}

template <class Model, class Class>
void bind_common(Class& cls)
{
    for (const auto& info : table_of<Model>()) {
        const auto member = info.member;
        const std::string doc = std::string(info.meaning) + " (valid range " + info.range_text() + ")";
        cls.def_property_readonly(
            std::string(info.name).c_str(), [member](const Model& m) { return m.params().*member; }, doc.c_str());
    }
    py::tuple names(table_of<Model>().size());
    std::size_t k = 0;
    for (const auto& info : table_of<Model>()) names[k++] = py::str(std::string(info.name));
    cls.attr("parameter_names") = names;
    const auto axes = state_axis_names(Model{});
    py::tuple states(axes.size());
    for (std::size_t i = 0; i < axes.size(); ++i) states[i] = py::str(std::string(axes[i]));
    cls.attr("state_names") = states;
    cls.attr("dim") = Model::dim;

    cls.def(
        "with_", [](const Model& m, const py::kwargs& kw) { return make_model<Model>(m.params(), kw); },
        "A copy with the given parameters changed, e.g. ``m.with_(r=0.7, sigma=-0.1)``.\n\n"
        "Raises ValueError (vimpact.InputError) for an unknown name or a value outside its range.");
    cls.def_property_readonly("parameters", &parameters_dict<Model>,
                              "All parameters as a dict, in the library's order.");
    cls.def_property_readonly(
        "default_ic", [](const Model& m) { return vector_array(default_initial_state(m)); },
        "The initial state used when none is given (numpy float64, shape (dim,)).");
    cls.def(
        "rhs", [](const Model& m, const input_array& x) { return vector_array<Model::dim>(m.rhs(state_of(m, x, "x"))); },
        py::arg("x"), "The vector field F(x) between impacts (numpy float64, shape (dim,)).");
    cls.def(
        "jacobian",
        [](const Model& m, const input_array& x) {
            const mat<Model::dim> J = m.jacobian(state_of(m, x, "x"));
            auto a = new_array(Model::dim, Model::dim);
            auto v = a.template mutable_unchecked<2>();
            for (int i = 0; i < Model::dim; ++i)
                for (int j = 0; j < Model::dim; ++j) v(i, j) = J(i, j);
            return a;
        },
        py::arg("x"), "The Jacobian DF(x) (numpy float64, shape (dim, dim)), analytic.");
    cls.def(
        "__eq__",
        [](const Model& a, const Model& b) {
            for (const auto& info : table_of<Model>())
                if (!(a.params().*(info.member) == b.params().*(info.member))) return false;
            return true;
        },
        py::is_operator());
    cls.def("__hash__", &parameters_hash<Model>);
    cls.def(py::pickle([](const Model& m) { return parameters_dict(m); },
                       [](const py::dict& d) { return make_model<Model>(typename Model::parameters{}, d); }));
}

}  // namespace

void bind_models(py::module_& m)
{
    const std::string wake_doc = R"(The paper's wake-induced vibro-impacting oscillator.

A damped linear structure y coupled by acceleration coupling to a Van der Pol wake
oscillator x (Facchinetti et al. 2004), with a rigid barrier at y = sigma::

    y' = v,  v' = a(X) = -delta^2 y - alpha v + M x
    x' = w,  w' = -x - eps (x^2 - 1) w + A a(X)
    delta = 1/(St Ur),  alpha = 2 xi delta + gamma/mu,  M = CL0 / (16 pi^2 St^2 mu)

An impact happens when y decreases through sigma; the reset is
(y, v, x, w) -> (sigma, -r v, x, w). State order: (y, ydot, x, xdot).

Parameters
----------
Keyword arguments; those not given take the ``paper`` preset's values.

)" + parameters_doc<wake_impact>() +
                                 R"(
Attributes
----------
Each parameter above (read-only: use ``with_`` for a changed copy), and the derived
``delta``, ``alpha`` and ``M``.

Examples
--------
>>> m = vimpact.WakeImpact(Ur=16, sigma=-0.1377)
>>> m.with_(r=0.7).r
0.7
>>> vimpact.WakeImpact.preset("facchinetti").CL0
0.3
)";
    py::class_<wake_impact> wake(m, "WakeImpact", wake_doc.c_str());
    wake.def(py::init([](const py::kwargs& kw) { return make_model<wake_impact>(wake_impact_preset("paper"), kw); }));
    bind_common<wake_impact>(wake);
    wake.def_static(
        "preset",
        [](const std::string& name, const py::kwargs& kw) { return make_model<wake_impact>(wake_impact_preset(name), kw); },
        py::arg("name"),
        ("The model of a named preset, with keyword overrides: ``WakeImpact.preset(\"facchinetti\", Ur=25)``.\n\n"
         "Presets: " + wake_impact_preset_names() +
         ". ``paper`` (the default) has M = 0.05/mu at St = 0.2, with which the paper's grazing "
         "values are reproduced; ``facchinetti`` has CL0 = 0.3 (amplitudes about 8 % smaller).")
            .c_str());
    wake.def_property_readonly("delta", &wake_impact::delta, "delta = 1/(St Ur), the structure's natural frequency.");
    wake.def_property_readonly("alpha", &wake_impact::alpha, "alpha = 2 xi delta + gamma/mu, the damping.");
    wake.def_property_readonly("M", &wake_impact::coupling_M, "M = CL0 / (16 pi^2 St^2 mu), the wake forcing.");
    wake.def("__repr__", [](const wake_impact& w) {
        return "WakeImpact(" + parameters_text(w) + ") with delta=" + format_double(w.delta()) +
               ", alpha=" + format_double(w.alpha()) + ", M=" + format_double(w.coupling_M());
    });

    const std::string forced_doc = R"(The classic harmonically forced linear impact oscillator.

In autonomous form with a phase::

    y' = v,  v' = -y - 2 zeta v + F cos(theta),  theta' = omega

with the same barrier law as WakeImpact: impact when y decreases through sigma, reset
(y, v, theta) -> (sigma, -r v, theta). Between impacts the flow is known in closed form,
which makes it the model to check numerics against. State order: (y, ydot, theta).

Parameters
----------
Keyword arguments; those not given take the defaults below.

)" + parameters_doc<forced_impact_oscillator>();
    py::class_<forced_impact_oscillator> forced(m, "ForcedImpactOscillator", forced_doc.c_str());
    forced.def(py::init([](const py::kwargs& kw) {
        return make_model<forced_impact_oscillator>(forced_impact_parameters{}, kw);
    }));
    bind_common<forced_impact_oscillator>(forced);
    forced.def("__repr__", [](const forced_impact_oscillator& f) {
        return "ForcedImpactOscillator(" + parameters_text(f) + ")";
    });
}

}  // namespace vimpact::python
