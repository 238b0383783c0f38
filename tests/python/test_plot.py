"""The plotting helpers draw Python results and the command line's directories with the same
functions."""
import os

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

import vimpact  # noqa: E402
import vimpact.plot as plot  # noqa: E402

Q = dict(transient=60, record=30)
W = vimpact.WakeImpact()


def png(path):
    with open(path, "rb") as f:
        return f.read(8) == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("draw,make", [
    (plot.phase, lambda: vimpact.simulate(vimpact.WakeImpact(Ur=21.5), sample_dt=0.1, **Q)),
    (plot.sections, lambda: vimpact.period(vimpact.WakeImpact(Ur=19), **Q)),
    (plot.bifurcation, lambda: vimpact.sweep(W, "Ur", vimpact.grid(16, 19, 4), grazing=True, **Q)),
    (plot.map, lambda: vimpact.map(W, x=("Ur", [16, 20]), y=("sigma", [-0.16, -0.1]), grazing=True, **Q)),
    (plot.basins, lambda: vimpact.basins(vimpact.WakeImpact(Ur=14.9), x=("y", [-0.2, 0.1]), y=("ydot", [0, 0.1]), **Q)),
    (plot.response, lambda: vimpact.response(W, "Ur", [5, 6], transient_time=200)),
])
def test_each_picture_of_a_python_result(tmp_path, draw, make):
    path = tmp_path / "p.png"
    fig = draw(make(), str(path))
    assert isinstance(fig, matplotlib.figure.Figure)
    assert png(path)


def test_into_given_axes_and_from_a_plain_object(tmp_path):
    import matplotlib.pyplot as plt
    from types import SimpleNamespace
    s = SimpleNamespace(param="Ur", ic_mode="fixed", points=np.array([[0.1, 0, 0, 0], [0.2, 0, 0, 0]]),
                        point_value=np.array([16.0, 17.0]), point_branch=np.array([0, 0]),
                        value=np.array([16.0, 17.0]), sigma_graze=np.array([np.nan, np.nan]), parameters={})
    fig, ax = plt.subplots()
    assert plot.bifurcation(s, ax=ax) is fig
    plt.close(fig)


def test_the_command_lines_plot_kinds_use_the_same_readers(cli, tmp_path):
    out = tmp_path / "s"
    p = cli("sweep", "--param", "Ur", "--range", "16:17:2", "--transient", "60", "--record", "30", "--out", out)
    assert p.returncode == 0, p.stderr
    assert png(out / "plot.png")
    assert vimpact.Sweep.load(out).label.tolist() == vimpact.sweep(W, "Ur", [16, 17], **Q).label.tolist()
    assert set(plot._kinds()) >= {"simulate", "period", "sweep", "map", "basins", "response", "dimension"}
