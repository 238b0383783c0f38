"""Every analysis on any model: the two-stop oscillator built in and as a model file
(examples/models/two_sided_impact_oscillator.toml, compiled into the run's cache) give the same
results, and the results name the model's state variables and surfaces.

"The same": labels, periods, impact counts, outcomes, shapes and every other integer or text
exactly; numbers to 1e-9. Not bit for bit: the built-in's C++ and the file's generated C are
compiled separately (the compiler may fuse a multiply and an add in one and not the other),
so the last bits of a step can differ; the step counts may differ by a few (not compared)."""
import numpy as np
import pytest

import vimpact

Q = dict(transient=40, record=24)


# Not compared: counters of steps and jobs; where a run stopped (the step it ended on); the time
# and state of a grazing minimum (among equal minima one period apart, which one is smallest
# by a last bit decides; its value is compared).
SKIP = ("model", "options", "stats", "protocol_stats", "tangent_stats", "transient_stats", "steps", "jobs",
        "final_state", "t", "x")


def same(a, b, path="result"):
    """Equal field by field: arrays bit for bit (NaN where NaN), dicts and lists item by item."""
    if isinstance(a, dict):  # a result's records too: the same fields are skipped there
        assert a.keys() == b.keys(), path
        for k in a:
            if k not in SKIP:
                same(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, (list, tuple)) and not isinstance(a, str):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{path}[{i}]")
    elif isinstance(a, (np.ndarray, float)) or hasattr(a, "__array__"):
        a, b = np.asarray(a), np.asarray(b)
        assert a.shape == b.shape, (path, a.shape, b.shape)
        if a.dtype.kind in "fc":
            np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9, err_msg=path)
        else:
            np.testing.assert_array_equal(a, b, err_msg=path)
    elif hasattr(a, "__dataclass_fields__"):
        for k in a.__dataclass_fields__:
            if k not in SKIP:
                same(getattr(a, k), getattr(b, k), f"{path}.{k}")
    else:
        assert a == b, (path, a, b)


@pytest.fixture(scope="module")
def pair(two_sided_file):
    return vimpact.TwoSidedImpactOscillator(), two_sided_file


RUNS = {
    "simulate": lambda m: vimpact.simulate(m, sample_dt=0.1, **Q),
    "simulate impacts:left": lambda m: vimpact.simulate(m, section="impacts:left", **Q),
    "period": lambda m: vimpact.period(m, **Q),
    "grazing": lambda m: vimpact.grazing(m, variable="x"),
    "sweep": lambda m: vimpact.sweep(m, "w", vimpact.grid(1.0, 1.4, 5), grazing=True, threads=2, **Q),
    "sweep follow both": lambda m: vimpact.sweep(m, "d", vimpact.grid(0.9, 1.1, 3), ic_mode="follow",
                                                 direction="both", **Q),
    "map": lambda m: vimpact.map(m, x=("w", [1.1, 1.3]), y=("d", [0.9, 1.5]), grazing=True, **Q),
    "basins": lambda m: vimpact.basins(m, x=("x", [-0.5, 0.0, 0.5]), y=("v", [-0.5, 0.5]), **Q),
    "response": lambda m: vimpact.response(m, "w", [1.1, 1.3], curves=[{"a": 1.0}, {"a": 0.5, "zeta": 0.1}]),
    "floquet": lambda m: vimpact.floquet(m, sample_dt=0.2, **Q),
    "lyapunov": lambda m: vimpact.lyapunov(m, impacts=30, transient=40, record=5),
    "floquet_sweep": lambda m: vimpact.floquet_sweep(m, "w", [1.1, 1.2], **Q),
    "lyapunov_sweep": lambda m: vimpact.lyapunov_sweep(m, "w", [1.1, 1.2], impacts=20, transient=40),
}


@pytest.mark.parametrize("name", RUNS)
def test_the_builtin_and_the_model_file_agree(pair, name):
    builtin, file = pair
    a, b = RUNS[name](builtin), RUNS[name](file)
    same(a, b, name)
    assert a.state_names == ("x", "v", "phi") and a.surfaces == ("right", "left")


def test_the_results_name_the_surfaces(pair):
    m = pair[0]
    s = vimpact.simulate(m, **Q)
    assert set(s.stats.impacts_by_surface) == {"right", "left"}
    assert sum(s.stats.impacts_by_surface.values()) == s.stats.impacts > 0
    assert set(np.unique(s.impact_surface)) <= {0, 1}
    # The right stop is at x = d, the left at -d, and a reset keeps x.
    np.testing.assert_allclose(s.impact_pre[s.impact_surface == 0, 0], m.d, atol=1e-12)
    np.testing.assert_allclose(s.impact_pre[s.impact_surface == 1, 0], -m.d, atol=1e-12)
    np.testing.assert_array_equal(s.impact_post[:, 1], -m.r * s.impact_pre[:, 1])
    p = vimpact.period(m, **Q)
    assert set(p.impacts_by_surface) == {"right", "left"} and sum(p.impacts_by_surface.values()) == p.impacts
    g = vimpact.grazing(m, variable="x")
    assert g.param == ("d", "d") and set(g.by_surface) == {"right", "left"}
    # The closed form (tests/analysis_test.cpp): both stops grazed at the amplitude X.
    X = m.a / np.sqrt((1 - m.w ** 2) ** 2 + (2 * m.zeta * m.w) ** 2)
    np.testing.assert_allclose(g.value, [X, X], atol=1e-9)
    assert g.response_max == pytest.approx(X, abs=1e-9) and g.response_omega == pytest.approx(m.w, abs=1e-9)
    only = vimpact.simulate(m, section="impacts:right", **Q)
    np.testing.assert_allclose(only.section[:, 0], m.d, atol=1e-12)
    sw = vimpact.sweep(m, "w", [1.1, 1.2], grazing="d", **Q)
    assert sw.grazing.shape == (2, 2) and sw.grazing_param == "d"
    r = vimpact.response(m, "w", [1.1, 1.2], grazing=False)
    assert r.grazing.shape == (1, 2, 2) and r.grazing_param is None
    np.testing.assert_allclose(r.grazing[0, :, 0], m.d - r.maximum[0], atol=1e-9)  # margins of the right stop


def test_section_names_and_errors(pair):
    m = pair[0]
    with pytest.raises(vimpact.InputError, match="section 'maxima' is not one of model two_sided_impact_oscillator's: "
                                                 "strobe, impacts, impacts:right, impacts:left"):
        vimpact.simulate(m, section="maxima")
    with pytest.raises(vimpact.InputError, match="no surface 'top'"):
        vimpact.simulate(m, section="impacts:top")
    with pytest.raises(vimpact.InputError, match="unknown parameter 'Ur' for param"):
        vimpact.sweep(m, "Ur", [1, 2])
    with pytest.raises(vimpact.InputError, match="x: 'y' is not one of x, v, phi"):
        vimpact.basins(m, x=("y", [0, 1]), y=("v", [0, 1]))
    with pytest.raises(vimpact.InputError, match="does not enter the vector field"):
        vimpact.response(m, "d", [1, 2])
    with pytest.raises(ValueError, match=r"ic needs 3 numbers \(x, v, phi\), got 4"):
        vimpact.simulate(m, ic=[0, 0, 0, 0])
