"""The Python module against the command line: the same inputs give the same numbers, bit for
bit (the command line prints shortest round-trip decimals, read back exactly), and bad input
gives the same message. The readers of the command line's directories (Sweep.load, ...) are
checked on the way: the Python result and the loaded one must agree field by field."""
import re

import numpy as np
import pytest

import vimpact
from vimpact.results import read_csv, read_table

# A short protocol keeps the whole comparison to a few seconds.
Q = dict(transient=80, record=40)
QA = ["--transient", "80", "--record", "40"]


def same(a, b):
    """Bit for bit (NaN where NaN)."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape, (a.shape, b.shape)
    if a.dtype.kind == "f" or b.dtype.kind == "f":
        np.testing.assert_array_equal(a.astype(float), b.astype(float))
    else:
        assert (a == b).all(), (a, b)


def same_stats(stats, js):
    d = stats.as_dict()
    if js["h_min"] is None:
        js = dict(js, h_min=float("inf"))
    assert d == js


def test_simulate(cli, tmp_path):
    out = tmp_path / "sim"
    p = cli("simulate", "--set", "Ur=21.5", *QA, "--dt", "0.05", "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    s = vimpact.simulate(vimpact.WakeImpact(Ur=21.5), sample_dt=0.05, **Q)
    loaded = vimpact.Simulation.load(out)
    for name in ("section_t", "section", "impact_t", "impact_pre", "series_t", "series"):
        same(getattr(s, name), getattr(loaded, name))
    same(s.impact_post[:, 1:], loaded.impact_post[:, 1:])
    same(s.final_state, loaded.final_state)
    assert s.t_record_start == loaded.t_record_start and s.outcome == loaded.outcome
    assert s.stats == loaded.stats and s.stats.impacts > Q["transient"]


def test_period_with_other_options(cli_json):
    args = ["--set", "Ur=19", "--set", "r=0.75", "--rtol", "1e-9", "--method", "dopri5", "--section", "minima"]
    j = cli_json("period", *args, *QA, "--tol", "1e-6")
    p = vimpact.period(vimpact.WakeImpact(Ur=19, r=0.75), tol=1e-6, rtol=1e-9, method="dopri5", section="minima",
                       **Q)
    assert (p.label, p.period, p.impacts, p.outcome) == (j["label"], j["period"], j["impacts"], j["outcome"])
    assert p.closure == j["closure"]
    same(p.section_y, j["section_y"])
    same_stats(p.stats, j["stats"])


def test_grazing(cli_json):
    j = cli_json("grazing", "--set", "Ur=25", "--set", "A=10", "--set", "eps=0.333")
    g = vimpact.grazing(vimpact.WakeImpact(Ur=25, A=10, eps=0.333))
    assert g.sigma_graze == j["sigma_graze"] and g.change == j["change"] and g.t_graze == j["t_graze"]
    assert (g.converged, g.minima, g.outcome) == (j["converged"], j["minima"], j["outcome"])
    same_stats(g.stats, j["stats"])


def test_sweep_fixed_with_grazing(cli, tmp_path):
    out = tmp_path / "s"
    p = cli("sweep", "--param", "Ur", "--range", "20:24:5", *QA, "--grazing", "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    s = vimpact.sweep(vimpact.WakeImpact(), "Ur", vimpact.grid(20, 24, 5), grazing=True, threads=2, **Q)
    c = vimpact.Sweep.load(out)
    for name in ("branch", "value", "label", "period", "impacts", "closure", "outcome", "sigma_graze", "points",
                 "point_value", "point_branch", "point_run"):
        same(getattr(s, name), getattr(c, name))
    assert np.isfinite(s.sigma_graze).all()


def test_sweep_follow_both_directions(cli, tmp_path):
    out = tmp_path / "s"
    p = cli("sweep", "--param", "Ur", "--range", "14.5:15.5:5", "--ic-mode", "follow", "--direction", "both", *QA,
            "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    s = vimpact.sweep(vimpact.WakeImpact(), "Ur", vimpact.grid(14.5, 15.5, 5), ic_mode="follow", direction="both",
                      **Q)
    c = vimpact.Sweep.load(out)
    for name in ("branch", "value", "label", "closure", "points", "point_run"):
        same(getattr(s, name), getattr(c, name))
    same(s.branch, [0, 1] * 5)


def test_sigma_sweep_following_a_rising_barrier(cli, tmp_path):
    # The barrier moves above the previous final state: the hand-over puts it on the barrier.
    out = tmp_path / "s"
    p = cli("sweep", "--param", "sigma", "--range=-0.16:0.02:4", "--ic-mode", "follow", *QA, "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    s = vimpact.sweep(vimpact.WakeImpact(), "sigma", vimpact.grid(-0.16, 0.02, 4), ic_mode="follow", **Q)
    c = vimpact.Sweep.load(out)
    same(s.label, c.label)
    same(s.points, c.points)


def test_map_with_grazing_line(cli, tmp_path):
    out = tmp_path / "m"
    p = cli("map", "--x", "Ur:16:25:4", "--y", "sigma:-0.16:-0.02:3", *QA, "--tol", "1e-5", "--grazing",
            "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    m = vimpact.map(vimpact.WakeImpact(), x=("Ur", vimpact.grid(16, 25, 4)), y=("sigma", vimpact.grid(-0.16, -0.02, 3)),
                    tol=1e-5, grazing=True, **Q)
    c = vimpact.Map.load(out)
    for name in ("x_values", "y_values", "label", "period", "impacts", "outcome", "grazing"):
        same(getattr(m, name), getattr(c, name))
    g = read_csv(out / "grazing.csv")
    same(m.grazing, np.column_stack([g["Ur"], g["sigma_graze"]]))


def test_basins(cli, cli_json, tmp_path):
    out = tmp_path / "b"
    args = ["--set", "Ur=14.9", "--x", "y:-0.2:0.25:4", "--y", "ydot:-0.2:0.2:3", "--transient", "300",
            "--record", "40"]
    j = cli_json("basins", *args, "--out", out, "--no-plot")
    b = vimpact.basins(vimpact.WakeImpact(Ur=14.9), x=("y", vimpact.grid(-0.2, 0.25, 4)),
                       y=("ydot", vimpact.grid(-0.2, 0.2, 3)), transient=300, record=40)
    c = vimpact.Basins.load(out)
    same(b.attractor, c.attractor)
    same(b.label, c.label)
    same(b.x_values, c.x_values)
    same(b.y_values, c.y_values)
    table = j["attractors"]["table"]
    assert [(a.id, a.label, a.cells) for a in b.attractors] == [(t["id"], t["label"], t["cells"]) for t in table]
    for a, t in zip(b.attractors, table):
        same(a.cycle.reshape(-1), np.array(t["section_points"], dtype=float).reshape(-1))
    assert b.inadmissible_cells == j["inadmissible_cells"] == 3


def test_response(cli, tmp_path):
    out = tmp_path / "r"
    p = cli("response", "--param", "Ur", "--range", "4:8:3", "--curves", "12:0.3,10:0.25", "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    r = vimpact.response(vimpact.WakeImpact(), "Ur", vimpact.grid(4, 8, 3), curves=[(12, 0.3), (10, 0.25)])
    c = vimpact.Response.load(out)
    for name in ("values", "curves", "amplitude", "y_max", "sigma_graze", "frequency_ratio", "structure_frequency",
                 "converged"):
        same(getattr(r, name), getattr(c, name))


def test_floquet(cli_json):
    j = cli_json("floquet", "--set", "Ur=16")
    f = vimpact.floquet(vimpact.WakeImpact(Ur=16))
    assert (f.label, f.status, f.section_returns, f.impacts_per_period) == (
        j["label"], j["outcome"], j["section_returns"], j["impacts_per_period"])
    assert f.period == j["period"] and f.closure == j["closure"] and f.stable == j["stable"]
    same(np.column_stack([f.multipliers.real, f.multipliers.imag]), j["multipliers"])
    same(f.orbit_point, j["orbit_point"])
    assert f.det_monodromy == j["det_monodromy"] and f.trivial_error == j["trivial_error"]
    same_stats(f.stats["protocol"], j["stats"]["protocol"])


def test_lyapunov(cli_json):
    j = cli_json("lyapunov", "--set", "Ur=24.4", "--impacts", "60", "--transient", "100")
    ly = vimpact.lyapunov(vimpact.WakeImpact(Ur=24.4), impacts=60, transient=100)
    same(ly.exponents, j["exponents"])
    assert ly.lle_standard_error == j["lle_standard_error"] and ly.sum_rule == j["sum_rule"]
    assert (ly.status, ly.impacts, ly.intervals, ly.time) == (j["outcome"], j["impacts"], j["intervals"], j["time"])


def test_dimension_of_a_runs_section_points(cli_json):
    j = cli_json("dimension", "--set", "Ur=18.426", "--transient", "100", "--record", "2000")
    s = vimpact.simulate(vimpact.WakeImpact(Ur=18.426), transient=100, record=2000)
    d = vimpact.dimension(s.section[:, [0, 2, 3]])
    assert d.dimension == j["dimension"] and d.r2 == j["r2"] and d.slope_error == j["slope_error"]
    same(d.fit_range, j["fit_range"])
    assert (d.fitted, d.total_pairs, d.points) == (j["fitted_radii"], j["total_pairs"], j["points"])
    c = cli_json("dimension", "--set", "Ur=18.426", "--transient", "100", "--record", "2000", "--estimator", "centres")
    e = vimpact.dimension(s.section[:, [0, 2, 3]], estimator="centres")
    assert e.dimension == c["dimension"] and e.centres.tolist() == c["centres"]


def test_grid_is_the_command_lines_range(cli_json):
    j = cli_json("map", "--x", "Ur:16.1:24.9:7", "--y", "sigma:-0.3:-0.29:2", "--transient", "1", "--record", "2")
    same(vimpact.grid(16.1, 24.9, 7), j["x_values"])
    same(vimpact.grid(-0.3, -0.29, 2), j["y_values"])


# ---------------------------------------------------------------- errors

def python_spelling(message):
    """The command line's option names as the Python arguments are spelled: --ic-mode -> ic_mode."""
    return re.sub(r"--([a-z][a-z-]*)", lambda m: m.group(1).replace("-", "_"), message)


W = vimpact.WakeImpact()
G2 = vimpact.grid(10, 12, 3)


@pytest.mark.parametrize("call,args", [
    (lambda: vimpact.WakeImpact(r=1.5), ["period", "--set", "r=1.5"]),
    (lambda: vimpact.WakeImpact(eps=-1), ["period", "--set", "eps=-1"]),
    (lambda: vimpact.WakeImpact.preset("nope"), ["period", "--preset", "nope"]),
    (lambda: vimpact.simulate(W, rtol=0), ["simulate", "--rtol", "0"]),
    (lambda: vimpact.simulate(W, rtol=2e-16), ["simulate", "--rtol", "2e-16"]),
    (lambda: vimpact.simulate(W, record=0), ["simulate", "--record", "0"]),
    (lambda: vimpact.simulate(W, transient=-1), ["simulate", "--transient=-1"]),
    (lambda: vimpact.period(W, method="rk4"), ["period", "--method", "rk4"]),
    (lambda: vimpact.period(W, section="zeros"), ["period", "--section", "zeros"]),
    (lambda: vimpact.sweep(W, "Q", G2), ["sweep", "--param", "Q", "--range", "10:12:3"]),
    (lambda: vimpact.sweep(W, "Ur", G2, tol=0), ["sweep", "--param", "Ur", "--range", "10:12:3", "--tol", "0"]),
    (lambda: vimpact.sweep(W, "Ur", G2, direction="both"),
     ["sweep", "--param", "Ur", "--range", "10:12:3", "--direction", "both"]),
    (lambda: vimpact.sweep(W, "Ur", G2, ic_mode="x"), ["sweep", "--param", "Ur", "--range", "10:12:3", "--ic-mode", "x"]),
    (lambda: vimpact.sweep(W, "Ur", G2, direction="sideways"),
     ["sweep", "--param", "Ur", "--range", "10:12:3", "--direction", "sideways"]),
    (lambda: vimpact.sweep(W, "sigma", vimpact.grid(-0.1, 0.1, 3)), ["sweep", "--param", "sigma", "--range=-0.1:0.1:3"]),
    (lambda: vimpact.sweep(W, "sigma", vimpact.grid(0.1, -0.1, 3), ic_mode="follow"),
     ["sweep", "--param", "sigma", "--range=0.1:-0.1:3", "--ic-mode", "follow"]),
    (lambda: vimpact.sweep(W, "Ur", G2, threads=-1), ["sweep", "--param", "Ur", "--range", "10:12:3", "--threads=-1"]),
    (lambda: vimpact.map(W, x=("Ur", [10, 12]), y=("Ur", [1, 2])), ["map", "--x", "Ur:10:12:2", "--y", "Ur:1:2:2"]),
    (lambda: vimpact.map(W, x=("Ur", [10, 12]), y=("r", [0.5, 0.8]), grazing=True),
     ["map", "--x", "Ur:10:12:2", "--y", "r:0.5:0.8:2", "--grazing"]),
    (lambda: vimpact.map(W, x=("Ur", [10, 12]), y=("sigma", [-0.1, 0.1])),
     ["map", "--x", "Ur:10:12:2", "--y", "sigma:-0.1:0.1:2"]),
    (lambda: vimpact.map(W, x=("Q", [10, 12]), y=("sigma", [-0.1, 0.1])),
     ["map", "--x", "Q:10:12:2", "--y", "sigma:-0.1:0.1:2"]),
    (lambda: vimpact.basins(W, x=("z", [0, 1]), y=("ydot", [0, 1])), ["basins", "--x", "z:0:1:2", "--y", "ydot:0:1:2"]),
    (lambda: vimpact.basins(W, x=("y", [0, 1]), y=("y", [0, 1])), ["basins", "--x", "y:0:1:2", "--y", "y:0:1:2"]),
    (lambda: vimpact.basins(W, x=("y", [0, 1]), y=("ydot", [0, 1]), match_tol=0),
     ["basins", "--x", "y:0:1:2", "--y", "ydot:0:1:2", "--match-tol", "0"]),
    (lambda: vimpact.response(W, "sigma", [0, 1]), ["response", "--param", "sigma", "--range", "0:1:2"]),
    (lambda: vimpact.response(W, "Ur", [4, 5], transient_time=-1),
     ["response", "--param", "Ur", "--range", "4:5:2", "--transient-time=-1"]),
    (lambda: vimpact.response(W, "Ur", [4, 5], curves=[(12, -1)]),
     ["response", "--param", "Ur", "--range", "4:5:2", "--curves", "12:-1"]),
    (lambda: vimpact.floquet(W, impact_map="none"), ["floquet", "--impact-map", "none"]),
    (lambda: vimpact.lyapunov(W, tdm="exact"), ["lyapunov", "--tdm", "exact"]),
    (lambda: vimpact.lyapunov(W, r0=2), ["lyapunov", "--r0", "2"]),
    (lambda: vimpact.dimension(np.zeros((5, 2)), estimator="boxes"), ["dimension", "--estimator", "boxes"]),
])
def test_bad_input_is_a_value_error_with_the_command_lines_message(cli, tmp_path, call, args):
    p = cli(*args, cwd=tmp_path)
    assert p.returncode == 2, p.stderr
    assert p.stderr.startswith("vimpact: error: ")
    expected = python_spelling(p.stderr[len("vimpact: error: "):].strip())
    with pytest.raises(ValueError) as e:
        call()
    assert isinstance(e.value, vimpact.InputError)
    assert str(e.value) == expected


def test_inadmissible_initial_state_names_it():
    # The command line says this in its own words (cli/common_options.cpp); Python gets the
    # library's message.
    with pytest.raises(ValueError, match=r"initial state is not admissible: y = -0\.2 .*sigma = -0\.150298"):
        vimpact.simulate(W, ic=[-0.2, 0, 0, 0.1])
