"""The plotting helpers draw Python results of any model and the command line's directories
with the same functions; `python3 -m vimpact.plot KIND DIR` draws every kind."""
import json
import os
import subprocess
import sys

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

import vimpact  # noqa: E402
import vimpact.plot as plot  # noqa: E402

Q = dict(transient=60, record=30)
W = vimpact.WakeImpact()
T = vimpact.TwoSidedImpactOscillator()

KINDS = {"simulate", "period", "sweep", "map", "basins", "response", "floquet", "lyapunov", "floquet_sweep",
         "lyapunov_sweep", "dimension", "continuation", "clearance"}


def png(path):
    with open(path, "rb") as f:
        return f.read(8) == b"\x89PNG\r\n\x1a\n"


PICTURES = [
    (plot.phase, lambda m: vimpact.simulate(m, sample_dt=0.1, **Q)),
    (plot.sections, lambda m: vimpact.period(m, **Q)),
    (plot.bifurcation, lambda m: vimpact.sweep(m, m.parameter_names[0] if m is W else "w",
                                               [16, 17] if m is W else [1.1, 1.2], grazing=True, **Q)),
    (plot.map, lambda m: vimpact.map(m, x=("Ur", [16, 20]), y=("sigma", [-0.16, -0.1]), grazing=True, **Q) if m is W
     else vimpact.map(m, x=("w", [1.1, 1.3]), y=("d", [0.9, 1.5]), grazing=True, **Q)),
    (plot.basins, lambda m: vimpact.basins(m, x=(m.state_names[0], [-0.2, 0.1]), y=(m.state_names[1], [0, 0.1]), **Q)),
    (plot.response, lambda m: vimpact.response(m, "Ur" if m is W else "w", [5, 6] if m is W else [1.1, 1.2],
                                               transient_time=200)),
    (plot.floquet, lambda m: vimpact.floquet(m, sample_dt=0.1, **Q)),
    (plot.lyapunov, lambda m: vimpact.lyapunov(m, impacts=30, transient=60)),
    (plot.floquet_sweep, lambda m: vimpact.floquet_sweep(m, "Ur" if m is W else "w", [16, 17] if m is W else [1.1, 1.2],
                                                         **Q)),
    (plot.lyapunov_sweep, lambda m: vimpact.lyapunov_sweep(m, "Ur" if m is W else "w",
                                                           [16, 17] if m is W else [1.1, 1.2], impacts=20,
                                                           transient=40, record=5)),
]


@pytest.mark.parametrize("model", [W, T], ids=["wake_impact", "two_sided"])
@pytest.mark.parametrize("draw,make", PICTURES, ids=[d.__name__ for d, _ in PICTURES])
def test_each_picture_of_a_python_result(tmp_path, model, draw, make):
    path = tmp_path / "p.png"
    fig = draw(make(model), str(path))
    assert isinstance(fig, matplotlib.figure.Figure)
    assert png(path)


def test_into_given_axes_and_from_a_plain_object():
    import matplotlib.pyplot as plt
    from types import SimpleNamespace
    s = SimpleNamespace(param="Ur", ic_mode="fixed", points=np.array([[0.1, 0, 0, 0], [0.2, 0, 0, 0]]),
                        point_value=np.array([16.0, 17.0]), point_branch=np.array([0, 0]),
                        value=np.array([16.0, 17.0]), grazing=np.full((2, 1), np.nan), parameters={},
                        state_names=("y", "ydot", "x", "xdot"), plot_variable="y")
    fig, ax = plt.subplots()
    assert plot.bifurcation(s, ax=ax) is fig
    plt.close(fig)


def test_results_do_not_import_plots():
    code = "import sys, vimpact.results; assert not any(m.startswith('vimpact.plot') for m in sys.modules)"
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert set(plot._kinds()) == KINDS


def write_simulation_directory(directory, s, model):
    """A directory as the command line writes it (cli/output.cpp): run.json with the model's
    state names, plot variable and surfaces, sections.csv, timeseries.csv and impacts.csv with
    NAME_before / NAME_after for the variables a reset changes and the surface by name."""
    os.makedirs(directory)
    names = model.state_names
    record = {"command": "simulate", "model": {"name": model.name, "parameters": model.parameters,
                                               "state_names": list(names), "surfaces": list(model.surfaces)},
              "state_names": list(names), "plot_variable": names[0], "config": {"section": "strobe"},
              "result": {"outcome": s.outcome, "t_record_start": s.t_record_start,
                         "final_state": s.final_state.tolist(), "stats": {"impacts": s.stats.impacts}}}
    with open(os.path.join(directory, "run.json"), "w") as f:
        json.dump(record, f)
    for file, t, x in (("sections.csv", s.section_t, s.section), ("timeseries.csv", s.series_t, s.series)):
        with open(os.path.join(directory, file), "w") as f:
            f.write(",".join(("t",) + names) + "\n")
            for ti, xi in zip(t, x):
                f.write(",".join(repr(float(v)) for v in (ti, *xi)) + "\n")
    with open(os.path.join(directory, "impacts.csv"), "w") as f:
        f.write("t,x,v_before,v_after,phi,surface\n")
        for ti, pre, post, k in zip(s.impact_t, s.impact_pre, s.impact_post, s.impact_surface):
            f.write(f"{ti!r},{pre[0]!r},{pre[1]!r},{post[1]!r},{pre[2]!r},{model.surfaces[k]}\n")


def test_a_directory_in_the_command_lines_format_loads_and_draws(tmp_path):
    s = vimpact.simulate(T, sample_dt=0.1, **Q)
    d = tmp_path / "sim"
    write_simulation_directory(str(d), s, T)
    loaded = vimpact.Simulation.load(d)
    assert loaded.state_names == ("x", "v", "phi") and loaded.surfaces == ("right", "left")
    for name in ("section", "section_t", "series", "impact_t", "impact_surface", "impact_pre", "impact_post"):
        np.testing.assert_array_equal(getattr(loaded, name), getattr(s, name), err_msg=name)
    p = subprocess.run([sys.executable, "-m", "vimpact.plot", "simulate", str(d)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert png(d / "plot.png")


def test_the_command_lines_plot_kinds_draw_its_directories(cli, tmp_path):
    runs = {
        "simulate": ["simulate", "--dt", "0.1"],
        "period": ["period"],
        "sweep": ["sweep", "--param", "Ur", "--range", "16:17:2", "--grazing"],
        "map": ["map", "--x", "Ur:16:20:2", "--y", "sigma:-0.16:-0.1:2", "--grazing"],
        "basins": ["basins", "--set", "Ur=14.9", "--x", "y:-0.2:0.1:2", "--y", "ydot:0:0.1:2"],
        "response": ["response", "--param", "Ur", "--range", "5:6:2"],
        "floquet": ["floquet"],
        "lyapunov": ["lyapunov", "--impacts", "30"],
    }
    for kind, args in runs.items():
        out = tmp_path / kind
        p = cli(*args, "--transient", "60", *(["--record", "30"] if kind not in ("lyapunov", "response") else []),
                "--out", out)
        assert p.returncode == 0, (kind, p.stderr)
        assert png(out / "plot.png"), kind
    loaded = vimpact.Sweep.load(tmp_path / "sweep")
    assert loaded.label.tolist() == vimpact.sweep(W, "Ur", [16, 17], **Q).label.tolist()
