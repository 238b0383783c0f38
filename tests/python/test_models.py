"""vimpact.Model: built-ins, model files, TOML text and dicts as one class; parameters as
attributes, presets, copies, value semantics, pickling; bad models and values."""
import math
import os
import pickle
import tomllib

import numpy as np
import pytest

import vimpact
from conftest import TWO_SIDED_TOML


def test_builtins_by_name_and_the_constructors():
    assert set(vimpact.Model.builtin_names()) == {"wake_impact", "forced_impact_oscillator",
                                                  "two_sided_impact_oscillator"}
    m = vimpact.Model("wake_impact", Ur=16)
    assert m == vimpact.Model.builtin("wake_impact", Ur=16) == vimpact.WakeImpact(Ur=16)
    assert vimpact.Model() == vimpact.WakeImpact()
    assert isinstance(vimpact.TwoSidedImpactOscillator(), vimpact.Model)
    assert vimpact.ForcedImpactOscillator(omega=1.2).omega == 1.2
    assert "Ur : float, default 16" in vimpact.WakeImpact.__doc__
    assert vimpact.WakeImpact.parameter_names[:2] == ("Ur", "sigma")
    with pytest.raises(vimpact.InputError, match="unknown model 'nope'.*wake_impact"):
        vimpact.Model("nope")


def test_what_a_model_says_about_itself():
    m = vimpact.WakeImpact(Ur=16)
    assert m.name == "wake_impact" and m.dim == 4
    assert m.state_names == ("y", "ydot", "x", "xdot")
    assert m.surfaces == ("barrier",) and m.sections == ("maxima", "minima")
    assert m.presets == ("paper", "facchinetti")
    assert list(m.parameters) == list(m.parameter_names) and m.parameters["Ur"] == m.Ur == 16.0
    assert m.default_ic.tolist() == [0, 0, 0, 0.1] and m.default_ic.dtype == np.float64
    p = m.info["parameters"][m.parameter_names.index("r")]
    assert p["range"]["text"] == "[0, 1]" and p["meaning"] == "coefficient of restitution"
    assert m.info["surfaces"][0]["sticks"] is True
    assert m.gap_parameters("barrier") == ("sigma",)
    t = vimpact.TwoSidedImpactOscillator()
    assert t.surfaces == ("right", "left") and t.sections == ("strobe",)
    assert t.gap_parameters(0) == t.gap_parameters("left") == ("d",)
    assert t.info["state"][2]["period"] == pytest.approx(2 * math.pi)


def test_with_preset_and_immutability():
    m = vimpact.WakeImpact(Ur=16, sigma=-0.1377)
    m2 = m.with_(r=0.7)
    assert m2.r == 0.7 and m.r == 0.8, "with_ returns a copy"
    assert m2.with_(r=m.r) == m and hash(m2.with_(r=m.r)) == hash(m)
    f = vimpact.WakeImpact.preset("facchinetti", Ur=25)
    assert f.CL0 == 0.3 and f.Ur == 25.0 and f == m.preset("facchinetti", Ur=25)
    assert f != vimpact.WakeImpact(Ur=25)
    assert m != "not a model" and m != vimpact.ForcedImpactOscillator()
    with pytest.raises(AttributeError, match="immutable"):
        m.Ur = 3
    with pytest.raises(AttributeError):
        m.nonsense
    with pytest.raises(vimpact.InputError, match="unknown preset 'nope'.*paper, facchinetti"):
        m.preset("nope")
    assert m.with_parameters(list(m.parameters.values())) == m


def test_repr_shows_every_parameter_exactly():
    m = vimpact.WakeImpact(Ur=17.25)
    text = repr(m)
    assert text.startswith("Model('wake_impact', Ur=17.25, ")
    for name, value in m.parameters.items():
        assert f"{name}={value!r}" in text, (name, text)


def test_pickle_round_trip(two_sided_file):
    for m in (vimpact.WakeImpact(Ur=21.5, r=0.6), vimpact.ForcedImpactOscillator(omega=1.3),
              two_sided_file.with_(d=0.8), vimpact.Model.from_toml(open(TWO_SIDED_TOML).read(), a=2.0)):
        back = pickle.loads(pickle.dumps(m))
        assert back == m and back.parameters == m.parameters and back.source == m.source


def test_bad_parameters_are_value_errors():
    with pytest.raises(vimpact.InputError, match="unknown parameter 'foo' of model wake_impact"):
        vimpact.WakeImpact(foo=1)
    with pytest.raises(ValueError, match=r"parameter St = 0 is outside its valid range > 0"):
        vimpact.WakeImpact().with_(St=0)
    with pytest.raises(TypeError, match="must be a number"):
        vimpact.WakeImpact(Ur="fast")
    assert issubclass(vimpact.InputError, ValueError)


def test_rhs_and_jacobian_of_any_model(two_sided_file):
    m = vimpact.WakeImpact(Ur=19)
    x = np.array([0.01, -0.02, 0.3, 0.1])
    f = m.rhs(x)
    assert f.shape == (4,) and f.dtype == np.float64
    delta = 1 / (m.St * m.Ur)
    alpha = 2 * m.xi * delta + m.gamma / m.mu
    M = m.CL0 / (16 * math.pi ** 2 * m.St ** 2 * m.mu)
    assert f[1] == pytest.approx(-delta ** 2 * x[0] - alpha * x[1] + M * x[2], rel=1e-14)
    for model, point in ((m, x), (two_sided_file, np.array([0.3, -0.2, 1.1]))):
        J = model.jacobian(point)
        assert J.shape == (model.dim, model.dim)
        h = 1e-6
        for j in range(model.dim):
            e = np.zeros(model.dim)
            e[j] = h
            np.testing.assert_allclose(J[:, j], (model.rhs(point + e) - model.rhs(point - e)) / (2 * h), rtol=1e-6,
                                       atol=1e-9)
    np.testing.assert_array_equal(two_sided_file.gaps([0.3, 0, 0]), [0.7, 1.3])
    with pytest.raises(ValueError, match=r"x needs 4 numbers \(y, ydot, x, xdot\), got 2"):
        m.rhs([1.0, 2.0])


def test_a_model_file_is_the_builtin_system(two_sided_file):
    b = vimpact.TwoSidedImpactOscillator()
    f = two_sided_file
    assert f.name == b.name and f.parameters == b.parameters
    assert f.state_names == b.state_names and f.surfaces == b.surfaces and f.sections == b.sections
    assert f.source == TWO_SIDED_TOML and b.source == "built-in"
    assert f != b, "different code: a file's identity is its content, a built-in's its name"
    x = np.array([0.3, -0.4, 0.7])
    np.testing.assert_allclose(f.rhs(x), b.rhs(x), rtol=1e-15)
    # The same text as TOML, from another path, or written out elsewhere: the same model.
    text = open(TWO_SIDED_TOML).read()
    assert vimpact.Model.from_toml(text) == f
    assert vimpact.Model(TWO_SIDED_TOML) == f and vimpact.Model.from_file(os.path.relpath(TWO_SIDED_TOML)) == f


def test_a_model_from_a_dict_equals_the_file(two_sided_file):
    with open(TWO_SIDED_TOML, "rb") as f:
        description = tomllib.load(f)  # dicts keep the file's key order: the parameters' order
    m = vimpact.Model(description)
    assert m == two_sided_file and m.identity == two_sided_file.identity
    assert m.source == "<dict>" and m.parameter_names == ("zeta", "a", "w", "d", "r")
    m2 = vimpact.Model(description, d=0.5)
    assert m2.d == 0.5 and m2 == two_sided_file.with_(d=0.5)
    # numpy numbers are numbers
    description["initial_state"] = np.zeros(3)
    assert vimpact.Model(description).default_ic.tolist() == [0, 0, 0]


# A ball on a shaken floor (three state variables: the dimensions every build has, 3 and 4).
MINIMAL = {"name": "bouncer", "state": ["h", "v", "phi"],
           "parameters": {"g": 9.81, "a": 0.5, "r": {"default": 0.5, "min": 0, "max": 1}},
           "derivatives": {"h": "v", "v": "-g + a*cos(phi)", "phi": "1"},
           "surfaces": [{"name": "floor", "gap": "h", "reset": {"v": "-r*v"}}],
           "sections": [{"name": "apex", "when": "v", "direction": "down"}], "initial_state": [1.0, 0.0, 0.0]}


@pytest.mark.parametrize("change,message", [
    (lambda d: d.pop("derivatives"), "model file <dict>: missing key 'derivatives'"),
    (lambda d: d["surfaces"][0].update(resett={}), "unknown key 'surfaces[0].resett'"),
    (lambda d: d["derivatives"].update(v="-gg"), "derivatives.v: unknown symbol 'gg'"),
    (lambda d: d["sections"][0].update(direction="sideways"), "sections[0].direction: 'sideways' is not a direction"),
    (lambda d: d["parameters"].update(r={"default": 2, "min": 0, "max": 1}), "parameters.r: the default 2"),
    (lambda d: d["derivatives"].pop("h"), "derivatives: no equation for state variable 'h'"),
    (lambda d: d["surfaces"][0]["reset"].update(q="1"), "surfaces[0].reset.q: 'q' is not a state variable"),
])
def test_bad_models_raise_value_errors_naming_the_key(change, message):
    import copy
    d = copy.deepcopy(MINIMAL)
    change(d)
    with pytest.raises(ValueError) as e:
        vimpact.Model(d)
    assert isinstance(e.value, vimpact.InputError)
    assert message in str(e.value), str(e.value)


def test_bad_model_files_and_sources(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "x"\nstate = ["a", "b", "c"]\n[parameters]\n[derivatives]\na = "b"\nb = "q"\nc = "1"\n')
    with pytest.raises(vimpact.InputError, match=r"bad\.toml: derivatives\.b: unknown symbol 'q'"):
        vimpact.Model.from_file(bad)
    with pytest.raises(vimpact.InputError, match="does not exist"):
        vimpact.Model.from_file(tmp_path / "missing.toml")
    with pytest.raises(vimpact.InputError, match="set"):
        vimpact.Model({"name": "x", "state": {"a", "b"}})
    with pytest.raises(TypeError, match="a name, a file or a dict"):
        vimpact.Model(3)


def test_a_small_model_from_a_dict_runs():
    m = vimpact.Model(MINIMAL)
    s = vimpact.simulate(m, transient=5, record=4)
    assert s.outcome == "ok" and s.section.shape == (4, 3) and s.state_names == ("h", "v", "phi")
    np.testing.assert_array_equal(s.section[:, 1], 0.0)
