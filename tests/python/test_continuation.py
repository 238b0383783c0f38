"""vimpact.continuation: the same numbers as the command line's `continue` (bit for bit: both
come from the library's one JSON form), Continuation.load of its directory field by field, any
model (a model file), the picture, and bad input."""
import numpy as np
import pytest

import vimpact
from conftest import TWO_SIDED_TOML

Q = dict(transient=200, record=20)
QA = ["--transient", "200", "--record", "20"]


def same(a, b):
    np.testing.assert_array_equal(np.asarray(a), np.asarray(b))


def assert_same_result(a, b):
    assert a.param == b.param and a.status == b.status and a.start_label == b.start_label
    assert len(a.branches) == len(b.branches) and len(a.bifurcations) == len(b.bifurcations)
    for x, y in zip(a.branches, b.branches):
        assert (x.returns, x.parent, x.origin, x.end, x.end_reason) == (y.returns, y.parent, y.origin, y.end,
                                                                        y.end_reason)
        for f in ("param", "stable", "period", "impacts", "closure", "arclength", "state", "sections", "multipliers"):
            same(getattr(x, f), getattr(y, f))
    for x, y in zip(a.bifurcations, b.bifurcations):
        assert (x.type, x.param, x.branch, x.surface, x.sequence_before) == (y.type, y.param, y.branch, y.surface,
                                                                           y.sequence_before)
        same(x.state, y.state)
        same(x.multipliers, y.multipliers)
    assert len(a.curves) == len(b.curves)
    for x, y in zip(a.curves, b.curves):
        for f in ("param", "param2", "state", "multipliers", "condition"):
            same(getattr(x, f), getattr(y, f))


def test_the_paper_p1_p2_story_and_the_command_line(cli, tmp_path):
    c = vimpact.continuation(vimpact.WakeImpact(), "Ur", (14.5, 15.3), switch=1, **Q)
    pd, g1 = c.bifurcations
    assert pd.type == "period_doubling" and abs(pd.param - 15.0181581267) < 1e-8
    # The P2 branch is unstable from the period doubling down to a grazing, then stable.
    p2 = c.branches[1]
    assert p2.returns == 2 and p2.sections.shape == (len(p2.param), 2, 4)
    assert not p2.stable[1] and p2.stable[-1]
    assert g1.type == "grazing" and g1.surface == "barrier" and g1.param < pd.param
    assert len(g1.sequence_before) == 2 and len(g1.sequence_after) == 1
    # Every multiplier array has the trivial one first.
    assert np.all(np.abs(p2.multipliers[:, 0] - 1) < 1e-6)
    out = tmp_path / "c"
    p = cli("continue", "--param", "Ur", "--range", "14.5:15.3", "--switch", "1", *QA, "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    assert_same_result(c, vimpact.Continuation.load(out))


def test_curves_against_the_command_line(cli, tmp_path):
    kw = dict(param2="sigma", range2=(-0.16, -0.14), ds_max=0.05)
    c = vimpact.continuation(vimpact.WakeImpact(), "Ur", (14.3, 15.1), **kw, **Q)
    assert len(c.curves) == 1 and c.curves[0].type == "period_doubling"
    out = tmp_path / "c2"
    p = cli("continue", "--param", "Ur", "--range", "14.3:15.1", "--param2", "sigma", "--range2", "-0.16:-0.14",
            "--ds-max", "0.05", "--map", "2,2", *QA, "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    loaded = vimpact.Continuation.load(out)
    assert_same_result(c, loaded)
    assert loaded.map["label"].shape == (2, 2)


def test_a_branch_says_why_it_ended(cli, tmp_path):
    # The two-sided oscillator's P1 down from w = 1 goes on where its strobe point meets an
    # impact (w = 0.789) and ends at the grazing of both stops at once (w = 0.5276).
    c = vimpact.continuation(vimpact.TwoSidedImpactOscillator(), "w", (1.0, 0.4), section="strobe", **Q)
    b = c.branches[0]
    assert b.param.min() < 0.6 and b.end == "grazing" and b.end_reason == f"grazing at w = {b.param[-1]!r}"
    assert sorted(g.surface for g in c.bifurcations if g.type == "grazing") == ["left", "right"]
    assert "ends grazing at w = " in repr(b)
    out = tmp_path / "e"
    p = cli("continue", "--model", "two_sided_impact_oscillator", "--section", "strobe", "--param", "w", "--range",
            "1:0.4", *QA, "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    assert_same_result(c, vimpact.Continuation.load(out))


def test_a_model_file_and_its_picture(tmp_path):
    m = vimpact.Model.from_file(TWO_SIDED_TOML)
    c = vimpact.continuation(m, "w", (1.2, 1.0), section="strobe", **Q)
    assert c.status == "ok" and len(c.branches[0].param) >= 5
    assert c.branches[0].impacts_by_surface["left"][0] == 1
    fig = vimpact.plot.continuation(c, str(tmp_path / "c.png"))
    assert (tmp_path / "c.png").stat().st_size > 1000 and fig is not None


def test_aperiodic_start_is_a_status_not_an_error():
    c = vimpact.continuation(vimpact.WakeImpact(), "Ur", (22.5, 23.0), **Q)
    assert c.status == "aperiodic" and c.branches == [] and c.start_label == "aperiodic"


@pytest.mark.parametrize("kw, message", [
    (dict(param="Uq", range=(12, 13)), "param"),
    (dict(param="Ur", range=(12, 12)), "empty"),
    (dict(param="Ur", range=(12, 13), switch=9), "switch"),
    (dict(param="Ur", range=(12, 13), param2="sigma", range2=(0, 0.1)), "outside its range"),
])
def test_bad_input(kw, message):
    with pytest.raises(vimpact.InputError, match=message):
        vimpact.continuation(vimpact.WakeImpact(), **kw)
