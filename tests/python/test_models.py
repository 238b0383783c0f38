"""The model classes: parameters as attributes, presets, copies, validation."""
import math
import pickle

import numpy as np
import pytest

import vimpact


def test_defaults_are_the_paper_preset_and_derived_values_follow():
    m = vimpact.WakeImpact()
    p = m.parameters
    assert list(p) == list(vimpact.WakeImpact.parameter_names)
    assert m.Ur == p["Ur"] and m.sigma == p["sigma"]
    assert m.delta == pytest.approx(1.0 / (m.St * m.Ur), rel=1e-15)
    assert m.alpha == pytest.approx(2 * m.xi * m.delta + m.gamma / m.mu, rel=1e-15)
    assert m.M == pytest.approx(m.CL0 / (16 * math.pi ** 2 * m.St ** 2 * m.mu), rel=1e-15)
    # The paper preset is defined by M = 0.05 / mu.
    assert m.M == pytest.approx(0.05 / m.mu, rel=1e-12)


def test_keywords_with_and_preset():
    m = vimpact.WakeImpact(Ur=16, sigma=-0.1377)
    assert (m.Ur, m.sigma) == (16.0, -0.1377)
    m2 = m.with_(r=0.7)
    assert m2.r == 0.7 and m.r != 0.7, "with_ returns a copy"
    assert m2.with_(r=m.r) == m and hash(m2.with_(r=m.r)) == hash(m)
    f = vimpact.WakeImpact.preset("facchinetti", Ur=25)
    assert f.CL0 == 0.3 and f.Ur == 25.0
    assert f != vimpact.WakeImpact(Ur=25)
    assert m != "not a model" and m != vimpact.ForcedImpactOscillator()
    with pytest.raises(AttributeError):
        m.Ur = 3


def test_repr_shows_every_parameter_exactly_and_the_derived_ones():
    m = vimpact.WakeImpact(Ur=17.25)
    text = repr(m)
    for name, value in m.parameters.items():
        assert f"{name}={value!r}" in text or f"{name}={value:g}" in text, (name, text)
    for derived in ("delta=", "alpha=", "M="):
        assert derived in text
    assert "zeta=" in repr(vimpact.ForcedImpactOscillator())


def test_pickle_round_trip():
    for m in (vimpact.WakeImpact(Ur=21.5, r=0.6), vimpact.ForcedImpactOscillator(omega=1.3)):
        assert pickle.loads(pickle.dumps(m)) == m


def test_bad_parameters_are_value_errors():
    with pytest.raises(vimpact.InputError, match="unknown parameter 'foo'"):
        vimpact.WakeImpact(foo=1)
    with pytest.raises(ValueError, match="parameter St = 0 is outside its valid range > 0"):
        vimpact.WakeImpact().with_(St=0)
    with pytest.raises(TypeError, match="must be a number"):
        vimpact.WakeImpact(Ur="fast")
    assert issubclass(vimpact.InputError, ValueError)


def test_rhs_and_jacobian():
    m = vimpact.WakeImpact(Ur=19)
    x = np.array([0.01, -0.02, 0.3, 0.1])
    f = m.rhs(x)
    assert f.shape == (4,) and f.dtype == np.float64
    a = -m.delta ** 2 * x[0] - m.alpha * x[1] + m.M * x[2]
    assert f[1] == pytest.approx(a, rel=1e-14)
    J = m.jacobian(x)
    assert J.shape == (4, 4)
    h = 1e-6
    for j in range(4):
        e = np.zeros(4)
        e[j] = h
        np.testing.assert_allclose(J[:, j], (m.rhs(x + e) - m.rhs(x - e)) / (2 * h), rtol=1e-6, atol=1e-9)
    with pytest.raises(ValueError, match="must hold 4 numbers"):
        m.rhs([1.0, 2.0])


def test_forced_oscillator_model():
    f = vimpact.ForcedImpactOscillator(omega=1.2)
    assert f.dim == 3 and f.state_names == ("y", "ydot", "theta")
    assert f.default_ic.shape == (3,)
    assert f.with_(F=2).F == 2
