"""The Python module against the command line: the same inputs give the same numbers, bit for
bit (the command line prints shortest round-trip decimals, read back exactly), for the paper's
model and for a model file, and the readers of the command line's directories (Sweep.load,
...) agree with the Python results field by field. Skipped where the program is not built."""
import os

import numpy as np
import pytest

import vimpact
from conftest import TWO_SIDED_TOML
from vimpact.results import read_csv

# A short protocol keeps the whole comparison to a few seconds.
Q = dict(transient=80, record=40)
QA = ["--transient", "80", "--record", "40"]
COMPLIANT_STOP = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "examples",
                              "models", "compliant_stop.toml")


def same(a, b):
    """Bit for bit (NaN where NaN)."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape, (a.shape, b.shape)
    if a.dtype.kind == "c" or b.dtype.kind == "c":
        np.testing.assert_array_equal(a, b)
    elif a.dtype.kind == "f" or b.dtype.kind == "f":
        np.testing.assert_array_equal(a.astype(float), b.astype(float))
    else:
        assert (a == b).all(), (a, b)


def same_records(api, loaded):
    """Every field of the record that the directory holds (all but the counters and final
    states, which are not columns), by the library's description, as the module gives it."""
    assert loaded.records and set(loaded.records) <= set(api.records)
    for name, column in loaded.records.items():
        if isinstance(column, dict):  # a group
            assert set(column) == set(api.records[name])
            for k in column:
                same(api.records[name][k], column[k])
        else:
            same(api.records[name], column)


def test_simulate(cli, tmp_path):
    out = tmp_path / "sim"
    p = cli("simulate", "--set", "Ur=21.5", *QA, "--dt", "0.05", "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    s = vimpact.simulate(vimpact.WakeImpact(Ur=21.5), sample_dt=0.05, **Q)
    loaded = vimpact.Simulation.load(out)
    assert loaded.state_names == s.state_names and loaded.plot_variable == "y"
    for name in ("section_t", "section", "impact_t", "impact_surface", "impact_pre", "impact_post", "series_t",
                 "series"):
        same(getattr(s, name), getattr(loaded, name))
    same(s.final_state, loaded.final_state)
    assert s.t_record_start == loaded.t_record_start and s.outcome == loaded.outcome


def test_simulate_a_model_file(cli, tmp_path, two_sided_file):
    out = tmp_path / "sim"
    p = cli("simulate", "--model", TWO_SIDED_TOML, "--set", "w=1.3", *QA, "--dt", "0.1", "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    s = vimpact.simulate(two_sided_file.with_(w=1.3), sample_dt=0.1, **Q)
    loaded = vimpact.Simulation.load(out)
    assert loaded.state_names == ("x", "v", "phi") and loaded.surfaces == ("right", "left")
    for name in ("section", "impact_t", "impact_surface", "impact_pre", "impact_post", "series"):
        same(getattr(s, name), getattr(loaded, name))


def test_simulate_a_model_with_a_switch(cli, tmp_path):
    """The crossings of a switch: the module's arrays and switchings.csv, read back, bit for bit."""
    stop = os.path.join(os.path.dirname(TWO_SIDED_TOML), "compliant_stop.toml")
    out = tmp_path / "sim"
    p = cli("simulate", "--model", stop, *QA, "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    s = vimpact.simulate(vimpact.Model(stop), **Q)
    loaded = vimpact.Simulation.load(out)
    assert loaded.switches == s.switches == ("contact",) and len(s.switching_t) > 10
    for name in ("section", "switching_t", "switching_surface", "switching_pre", "switching_post"):
        same(getattr(s, name), getattr(loaded, name))


def test_period_with_other_options(cli_json):
    args = ["--set", "Ur=19", "--set", "r=0.75", "--rtol", "1e-9", "--method", "dopri5", "--section", "minima"]
    j = cli_json("period", *args, *QA, "--tol", "1e-6")
    p = vimpact.period(vimpact.WakeImpact(Ur=19, r=0.75), tol=1e-6, rtol=1e-9, method="dopri5", section="minima",
                       **Q)
    assert (p.label, p.period, p.impacts, p.outcome) == (j["label"], j["period"], j["impacts"], j["outcome"])
    assert p.closure == j["closure"]


def test_sweep_fixed_with_grazing(cli, tmp_path):
    out = tmp_path / "s"
    p = cli("sweep", "--param", "Ur", "--range", "20:24:5", *QA, "--grazing", "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    s = vimpact.sweep(vimpact.WakeImpact(), "Ur", vimpact.grid(20, 24, 5), grazing=True, threads=2, **Q)
    c = vimpact.Sweep.load(out)
    for name in ("branch", "value", "label", "period", "impacts", "impacts_by_surface", "closure", "settled",
                 "outcome", "grazing", "points", "point_value", "point_branch", "point_run"):
        same(getattr(s, name), getattr(c, name))
    assert set(s.statistics) == set(c.statistics)
    for name in s.statistics:
        same(s.statistics[name], c.statistics[name])
    same_records(s, c)
    assert np.isfinite(s.grazing).all()


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


def test_map_with_grazing_line(cli, tmp_path):
    out = tmp_path / "m"
    p = cli("map", "--x", "Ur:16:25:4", "--y", "sigma:-0.16:-0.02:3", *QA, "--tol", "1e-5", "--grazing",
            "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    m = vimpact.map(vimpact.WakeImpact(), x=("Ur", vimpact.grid(16, 25, 4)),
                    y=("sigma", vimpact.grid(-0.16, -0.02, 3)), tol=1e-5, grazing=True, **Q)
    c = vimpact.Map.load(out)
    for name in ("x_values", "y_values", "label", "period", "impacts", "outcome", "grazing_other", "grazing"):
        same(getattr(m, name), getattr(c, name))
    assert c.grazing_param == "sigma"


def test_basins(cli, tmp_path):
    out = tmp_path / "b"
    p = cli("basins", "--set", "Ur=14.9", "--x", "y:-0.2:0.25:4", "--y", "ydot:-0.2:0.2:3", "--transient", "300",
            "--record", "40", "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    b = vimpact.basins(vimpact.WakeImpact(Ur=14.9), x=("y", vimpact.grid(-0.2, 0.25, 4)),
                       y=("ydot", vimpact.grid(-0.2, 0.2, 3)), transient=300, record=40)
    c = vimpact.Basins.load(out)
    for name in ("attractor", "label", "period", "settled", "outcome", "x_values", "y_values"):
        same(getattr(b, name), getattr(c, name))
    same_records(b, c)
    assert [(a.id, a.label, a.cells) for a in b.attractors] == [(a.id, a.label, a.cells) for a in c.attractors]
    for a, ca in zip(b.attractors, c.attractors):
        same(a.cycle, ca.cycle)
        same(a.box, ca.box)


def test_basins_aperiodic_attractor_loads_its_shapes(cli, tmp_path):
    """An aperiodic attractor (Ur = 21) has no cycle: (0, k) with k the signature's width, as
    the API gives it, and its box."""
    out = tmp_path / "b"
    p = cli("basins", "--set", "Ur=21", "--x", "y:-0.2:0.25:2", "--y", "ydot:-0.2:0.2:2", "--transient", "300",
            "--record", "40", "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    b = vimpact.basins(vimpact.WakeImpact(Ur=21), x=("y", vimpact.grid(-0.2, 0.25, 2)),
                       y=("ydot", vimpact.grid(-0.2, 0.2, 2)), transient=300, record=40)
    c = vimpact.Basins.load(out)
    assert "aperiodic" in [a.label for a in b.attractors]
    for a, ca in zip(b.attractors, c.attractors):
        assert ca.cycle.shape == a.cycle.shape and a.cycle.shape[1] == a.box.shape[1] > 0
        same(a.box, ca.box)


def test_response(cli, tmp_path):
    out = tmp_path / "r"
    p = cli("response", "--param", "Ur", "--range", "4:8:3", "--curves", "A=12,eps=0.3;A=10,eps=0.25", "--out", out,
            "--no-plot")
    assert p.returncode == 0, p.stderr
    r = vimpact.response(vimpact.WakeImpact(), "Ur", vimpact.grid(4, 8, 3),
                         curves=[{"A": 12, "eps": 0.3}, {"A": 10, "eps": 0.25}])
    c = vimpact.Response.load(out)
    for name in ("values", "amplitude", "maximum", "minimum", "frequency", "grazing", "margin", "converged",
                 "outcome"):
        same(getattr(r, name), getattr(c, name))
    assert c.curves == r.curves and c.grazing_param == "sigma" and c.variable == r.variable
    same_records(r, c)


def test_floquet_sweep(cli, tmp_path):
    # Ur = 18.426 is the paper's chaotic point: no multipliers there (NaN rows, stable None).
    out = tmp_path / "f"
    p = cli("floquet", "--param", "Ur", "--range", "16:18.426:2", *QA, "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    s = vimpact.floquet_sweep(vimpact.WakeImpact(), "Ur", vimpact.grid(16, 18.426, 2), **Q)
    c = vimpact.FloquetSweep.load(out)
    assert (c.param, s.param) == ("Ur", "Ur") and s.label.tolist() == ["P2", "aperiodic"]
    for name in ("value", "label", "multipliers", "trivial", "stable", "points", "point_run", "point_value"):
        same(getattr(s, name), getattr(c, name))
    same_records(s, c)
    for name in ("label", "period", "closure", "stable"):
        same([getattr(r, name) for r in s.results], [getattr(r, name) for r in c.results])


def test_lyapunov_sweep(cli, tmp_path):
    out = tmp_path / "l"
    p = cli("lyapunov", "--param", "Ur", "--range", "16:17:2", "--impacts", "30", "--transient", "60", "--record",
            "5", "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    s = vimpact.lyapunov_sweep(vimpact.WakeImpact(), "Ur", vimpact.grid(16, 17, 2), impacts=30, transient=60,
                               record=5)
    c = vimpact.LyapunovSweep.load(out)
    assert (c.param, c.tdm) == (s.param, s.tdm)
    for name in ("value", "exponents", "lle", "lle_standard_error", "positive_exponent", "settled", "status",
                 "points", "point_run"):
        same(getattr(s, name), getattr(c, name))
    same_records(s, c)


def test_floquet(cli_json):
    j = cli_json("floquet", "--set", "Ur=16")
    f = vimpact.floquet(vimpact.WakeImpact(Ur=16))
    assert (f.label, f.status, f.impacts_per_period) == (j["label"], j["outcome"], j["impacts_per_period"])
    assert f.period == j["period"] and f.closure == j["closure"]
    same(np.column_stack([f.multipliers.real, f.multipliers.imag]), j["multipliers"])


def test_lyapunov(cli_json):
    j = cli_json("lyapunov", "--set", "Ur=24.4", "--impacts", "60", "--transient", "100")
    ly = vimpact.lyapunov(vimpact.WakeImpact(Ur=24.4), impacts=60, transient=100)
    same(ly.exponents, j["exponents"])
    assert ly.lle_standard_error == j["lle_standard_error"]
    assert (ly.status, ly.impacts) == (j["outcome"], j["impacts"])


def test_dimension_of_a_runs_section_points(cli_json):
    j = cli_json("dimension", "--set", "Ur=18.426", "--transient", "100", "--record", "2000")
    s = vimpact.simulate(vimpact.WakeImpact(Ur=18.426), transient=100, record=2000)
    d = vimpact.dimension(s)
    assert d.columns == ("y", "ydot", "x", "xdot") == tuple(j["source"]["columns"])
    assert d.dimension == j["dimension"] and d.r2 == j["r2"]
    assert (d.total_pairs, d.points) == (j["total_pairs"], j["points"])


def test_grid_is_the_command_lines_range(cli_json):
    j = cli_json("map", "--x", "Ur:16.1:24.9:7", "--y", "sigma:-0.3:-0.29:2", "--transient", "1", "--record", "2")
    same(vimpact.grid(16.1, 24.9, 7), j["x_values"])
    same(vimpact.grid(-0.3, -0.29, 2), j["y_values"])


def tabular(fields, group=None):
    """(group, name) of every field of a description (vimpact._vimpact.described) that a table
    holds, a group's fields under its name."""
    for f in fields:
        if f["tabular"] and f["type"] == "group":
            yield from tabular(f["fields"], f["name"])
        elif f["tabular"]:
            yield group, f["name"], f


@pytest.mark.parametrize("record,args", [
    ("sweep", ["sweep", "--param", "Ur", "--range", "20:21:2", "--grazing"]),
    ("map", ["map", "--x", "Ur:16:20:2", "--y", "sigma:-0.16:-0.1:2"]),
    ("basins", ["basins", "--set", "Ur=14.9", "--x", "y:-0.2:0.1:2", "--y", "ydot:0:0.1:2"]),
    ("response", ["response", "--param", "Ur", "--range", "5:6:2"]),
    ("floquet_sweep", ["floquet", "--param", "Ur", "--range", "16:17:2"]),
    ("lyapunov_sweep", ["lyapunov", "--param", "Ur", "--range", "16:17:2", "--impacts", "20"]),
    ("sweep", ["sweep", "--model", COMPLIANT_STOP, "--param", "F", "--range", "0.5:1:2", "--set", "d=3", "--grazing"]),
    ("response", ["response", "--model", COMPLIANT_STOP, "--param", "omega", "--range", "0.6:1.2:2", "--set", "d=3"])])
def test_the_described_records_are_the_tables_the_program_writes(cli, tmp_path, record, args):
    # The description the Python results document themselves from is the schema of the
    # program's tables: the same fields, meanings, units and types; a field with a value per
    # surface (switch) has columns where the model has surfaces (switches).
    out = tmp_path / "o"
    p = cli(*args, *(QA if record != "response" else []), "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    run = vimpact.results.read_record(out)
    columns = [c for t in run["tables"].values() for c in t["columns"] if "field" in c]
    has = {"per_surface": bool(run["model"]["surfaces"]), "per_switch": bool(run["model"].get("switches"))}
    described = {(g, n): f for g, n, f in tabular(vimpact._vimpact.described[record]) if has.get(f["span"], True)}
    assert {(c.get("group"), c["field"]) for c in columns} == set(described)
    for c in columns:
        f = described[c.get("group"), c["field"]]
        if "meaning" in c:
            assert (c["meaning"], c["unit"], c["type"]) == (f["meaning"], f["unit"], f["type"]), c["name"]


def test_the_described_sweep_point_is_the_arrays_of_a_sweep():
    s = vimpact.sweep(vimpact.WakeImpact(), "Ur", [20, 21], **Q)
    fields = vimpact._vimpact.described["sweep"]
    assert set(s.records) == {f["name"] for f in fields} | {"points_run"}
    for f in fields:
        if f["type"] == "group":
            assert set(s.records[f["name"]]) == {g["name"] for g in f["fields"]}
        if f["name"] != "stats":  # the run's counters in all
            assert getattr(s, f["name"]) is s.records[f["name"]]


# ---------------------------------------------------------------- errors the library checks
# (the command line checks some options, --tol and --threads among them, in its own words first)

W = vimpact.WakeImpact()


def test_hold_band_gives_the_command_lines_numbers(cli, tmp_path):
    # The step-size controller's hold band reaches the integrator from Python as from the
    # command line (section points bit for bit), and changes the steps taken.
    out = tmp_path / "sim"
    p = cli("simulate", "--set", "Ur=21.5", *QA, "--hold-band", "0.1", "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    s = vimpact.simulate(vimpact.WakeImpact(Ur=21.5), hold_band=0.1, **Q)
    same(s.section, vimpact.Simulation.load(out).section)
    assert s.stats.steps != vimpact.simulate(vimpact.WakeImpact(Ur=21.5), **Q).stats.steps


@pytest.mark.parametrize("call,args", [
    (lambda: vimpact.WakeImpact(r=1.5), ["period", "--set", "r=1.5"]),
    (lambda: vimpact.simulate(W, rtol=0), ["simulate", "--rtol", "0"]),
    (lambda: vimpact.simulate(W, rtol=2e-16), ["simulate", "--rtol", "2e-16"]),
    (lambda: vimpact.simulate(W, record=0), ["simulate", "--record", "0"]),
    (lambda: vimpact.simulate(W, transient=-1), ["simulate", "--transient=-1"]),
    (lambda: vimpact.simulate(W, hold_band=1.0), ["simulate", "--hold-band", "1"]),
])
def test_bad_input_gives_the_command_lines_message(cli, tmp_path, call, args):
    p = cli(*args, cwd=tmp_path)
    assert p.returncode == 2, p.stderr
    assert p.stderr.startswith("vimpact: error: ")
    with pytest.raises(ValueError) as e:
        call()
    assert isinstance(e.value, vimpact.InputError)
    # An option's message names it as each front end spells it: hold_band, --hold-band.
    key, sep, rest = str(e.value).partition(" = ")
    option = args[1].split("=")[0]
    expected = option + sep + rest if sep and option == "--" + key.replace("_", "-") else str(e.value)
    assert expected in p.stderr


def test_grazing_line_file_format(cli, tmp_path):
    out = tmp_path / "m"
    p = cli("map", "--x", "Ur:16:20:2", "--y", "sigma:-0.16:-0.1:2", "--grazing", *QA, "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    g = read_csv(out / "grazing.csv")
    assert "Ur" in g
