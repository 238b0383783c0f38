"""Any model: `vimpact models`, model files (checked, compiled), every command on a model other
than the paper's, the built-in and its model file giving the same results, per-surface impact
counts."""
import csv
import json
import os
import subprocess

import pytest

from conftest import TWO_SIDED_TOML
from test_cli import run, run_json

TWO = "two_sided_impact_oscillator"


def models_json(vimpact, *args):
    p = run(vimpact, "models", *args, "--json")
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)["models"]


def test_models_lists_the_builtins_with_everything_a_user_needs(vimpact):
    p = run(vimpact, "models")
    assert p.returncode == 0, p.stderr
    for text in ("wake_impact (built-in)", "forced_impact_oscillator (built-in)", f"{TWO} (built-in)",
                 "reduced velocity", "Ur", "16, > 0", "r", "[0, 1]", "barrier", "sticks", "maxima", "strobe",
                 "paper", "facchinetti", "a phase"):
        assert text in p.stdout, text
    models = {m["name"]: m for m in models_json(vimpact)}
    assert sorted(models) == sorted(["wake_impact", "forced_impact_oscillator", TWO])
    w = models["wake_impact"]
    assert [s["name"] for s in w["state"]] == ["y", "ydot", "x", "xdot"]
    ur = w["parameters"][0]
    assert ur["name"] == "Ur" and ur["default"] == 16 and ur["meaning"] == "reduced velocity U/(f_n D)"
    assert ur["range"]["lower"] == 0 and ur["range"]["upper"] is None and not ur["range"]["lower_inclusive"]
    sigma = w["parameters"][1]
    assert sigma["unit"] == "D" and sigma["range"]["text"] == "any finite number"
    assert w["surfaces"] == [{"name": "barrier", "meaning": "rigid barrier at y = sigma", "sticks": True}]
    assert [s["name"] for s in w["sections"]] == ["maxima", "minima"]
    assert [p["name"] for p in w["presets"]] == ["paper", "facchinetti"]
    assert w["presets"][1]["values"] == {"CL0": 0.3}
    t = models[TWO]
    assert [s["name"] for s in t["surfaces"]] == ["right", "left"]
    assert not any(s["sticks"] for s in t["surfaces"])
    assert t["state"][2]["period"] == pytest.approx(6.283185307179586)
    assert t["sections"] == [{"name": "strobe", "direction": "up",
                              "meaning": "once per forcing period: sin(phi) = 0, increasing (phi = 0 mod 2 pi)"}]


def test_models_of_a_file_compiles_it_and_describes_the_same_model(vimpact):
    p = run(vimpact, "models", TWO_SIDED_TOML)
    assert p.returncode == 0, p.stderr
    assert TWO_SIDED_TOML in p.stdout
    [f] = models_json(vimpact, TWO_SIDED_TOML)
    [b] = [m for m in models_json(vimpact) if m["name"] == TWO]
    assert f["source"] == TWO_SIDED_TOML and b["source"] == "built-in"
    for key in ("name", "state", "parameters", "surfaces", "sections", "initial_state", "presets"):
        assert f[key] == b[key], key


BAD_FILES = [
    ("syntax.toml", 'name = "m"\nstate = [\n', "syntax.toml"),
    ("unknown.toml", None, "bogus_key"),
    ("symbol.toml", None, "nosuchsymbol"),
    ("missing.toml", "", "does not exist"),
]


def bad_model(tmp_path, name, content):
    path = tmp_path / name
    if name == "unknown.toml":
        content = open(TWO_SIDED_TOML).read() + '\nbogus_key = 1\n'
    elif name == "symbol.toml":
        content = open(TWO_SIDED_TOML).read().replace('v = "-2*zeta*v - x + a*cos(phi)"',
                                                     'v = "-2*zeta*v - x + nosuchsymbol"')
    if content:
        path.write_text(content)
    return path


@pytest.mark.parametrize("name,content,needle", BAD_FILES, ids=[b[0] for b in BAD_FILES])
@pytest.mark.parametrize("command", [["models"], ["period", "--model"]], ids=["models", "period"])
def test_bad_model_files_exit_2_with_one_line(vimpact, tmp_path, name, content, needle, command):
    path = bad_model(tmp_path, name, content)
    p = run(vimpact, *command, str(path))
    assert p.returncode == 2, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1, p.stderr
    assert lines[0].startswith("vimpact: error: ")
    assert needle in lines[0], lines[0]
    assert p.stdout == ""


def test_a_model_directory_is_refused(vimpact, tmp_path):
    (tmp_path / "m.toml").mkdir()
    p = run(vimpact, "models", str(tmp_path / "m.toml"))
    assert p.returncode == 2 and "directory" in p.stderr
    assert len(p.stderr.strip().splitlines()) == 1


# ---- every command on the two-stop oscillator, built in and from its model file -------------

TWO_COMMANDS = {
    "simulate": ["simulate", "--transient", "50", "--record", "20"],
    "period": ["period"],
    "grazing": ["grazing"],
    "sweep": ["sweep", "--param", "w", "--range", "1.1:1.3:3", "--grazing", "--transient", "200", "--record", "40"],
    "map": ["map", "--x", "w:1.0:1.4:3", "--y", "d:0.8:1.2:2", "--grazing", "--transient", "200", "--record", "40"],
    "basins": ["basins", "--x", "x:-0.5:0.5:3", "--y", "v:-0.5:0.5:2", "--transient", "200", "--record", "40"],
    "response": ["response", "--param", "w", "--range", "0.8:1.4:3", "--curves", "a=1;a=0.5"],
    "floquet": ["floquet"],
    "floquet-sweep": ["floquet", "--param", "w", "--range", "1.15:1.25:2"],
    "lyapunov": ["lyapunov", "--impacts", "200"],
    "lyapunov-sweep": ["lyapunov", "--param", "w", "--range", "1.15:1.25:2", "--impacts", "100", "--record", "20"],
    "dimension": ["dimension", "--transient", "50", "--record", "400"],
}


# What may differ between the two builds of the model, which evaluate the same expressions in a
# different order: step counts, the block of minima at which a grazing run is found to have
# converged (its time and unwrapped phase; the values agree), and the fit of a dimension of the
# P1 orbit's points, which lie within 1e-12 of each other (rounding noise).
# "batch": both run their jobs in SIMD lanes (each job's bits those of its run alone, tested in
# tests/lanes_test.cpp).
IGNORED = {"out", "batch", "stats", "t", "minima", "state", "change", "fit_range", "r2", "slope_error", "slope_spread",
           "dimension", "scaling_region", "scaling_region_found", "fitted_radii", "pairs_at_fit_range",
           "c_at_fit_range", "r_cap", "all_pairs", "pairs_below_cap", "radii", "t_final"}


def same(a, b, path="", rel=1e-6):
    """Equal labels and structure; numbers equal to rel (rounding differences of the two builds
    grow a little over a transient)."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and sorted(a) == sorted(b), (path, sorted(a), sorted(b))
        for k in a:
            if k not in IGNORED:
                same(a[k], b[k], f"{path}.{k}", rel)
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{path}[{i}]", rel)
    elif isinstance(a, bool) or a is None or isinstance(a, str):
        assert a == b, (path, a, b)
    else:
        assert b == pytest.approx(a, rel=rel, abs=1e-8), (path, a, b)


@pytest.mark.parametrize("name", sorted(TWO_COMMANDS))
def test_every_command_runs_on_the_two_stop_model_built_in_and_from_its_file(vimpact, name):
    args = TWO_COMMANDS[name]
    a = run_json(vimpact, *args, "--model", TWO)
    b = run_json(vimpact, *args, "--model", TWO_SIDED_TOML)
    same(a, b)


def test_two_stop_results_name_both_surfaces(vimpact, tmp_path):
    j = run_json(vimpact, "period", "--model", TWO)
    assert j["label"] == "P1"
    assert j["impacts_by_surface"] == {"right": 1, "left": 1}
    assert sum(j["impacts_by_surface"].values()) == j["impacts"]
    assert sum(j["stats"]["impacts_by_surface"].values()) == j["stats"]["impacts"]
    g = run_json(vimpact, "grazing", "--model", TWO)
    assert [s["name"] for s in g["surfaces"]] == ["right", "left"]
    assert all(s["parameter"] == "d" for s in g["surfaces"])
    assert g["d_graze"] == g["surfaces"][0]["parameter_value"]
    # The free response of the linear oscillator has amplitude a / sqrt((1 - w^2)^2 + (2 zeta w)^2).
    X = 1.0 / ((1 - 1.44) ** 2 + (0.12) ** 2) ** 0.5
    for s in g["surfaces"]:
        assert abs(s["parameter_value"] - X) < 1e-8
    f = run_json(vimpact, "floquet", "--model", TWO)
    assert f["outcome"] == "ok" and f["label"] == "P1"
    assert sum(f["impacts_by_surface"].values()) == f["impacts_per_period"] == 2
    ly = run_json(vimpact, "lyapunov", "--model", TWO, "--impacts", "200")
    assert len(ly["exponents"]) == 3
    assert sum(ly["impacts_by_surface"].values()) == ly["impacts"]
    out = tmp_path / "s"
    p = run(vimpact, "simulate", "--model", TWO, "--transient", "20", "--record", "10", "--no-plot", "--out", str(out))
    assert p.returncode == 0, p.stderr
    assert (out / "impacts.csv").read_text().splitlines()[0] == \
        "t,x,v_before,v_after,phi,surface,normal_velocity,rebound_velocity,energy"
    assert {line.split(",")[5] for line in (out / "impacts.csv").read_text().splitlines()[1:]} == {"left", "right"}
    assert (out / "sections.csv").read_text().splitlines()[0] == "t,x,v,phi"
    record = json.loads((out / "run.json").read_text())
    assert record["state_names"] == ["x", "v", "phi"] and record["plot_variable"] == "x"
    assert record["config"]["section"] == "strobe"
    assert record["model"]["parameters"] == {"zeta": 0.05, "a": 1.0, "w": 1.2, "d": 1.0, "r": 0.8}


def test_sweep_and_map_files_of_two_surfaces(vimpact, tmp_path):
    out = tmp_path / "s"
    p = run(vimpact, *TWO_COMMANDS["sweep"], "--model", TWO, "--no-plot", "--out", str(out))
    assert p.returncode == 0, p.stderr
    lines = (out / "labels.csv").read_text().splitlines()
    header = lines[0].split(",")
    assert header[:12] == ["branch", "w", "label", "period", "impacts", "closure", "settled", "impacts_right",
                           "impacts_left", "outcome", "d_graze_right", "d_graze_left"]
    assert header[12:15] == ["impacts_recorded", "duration", "impact_rate"]
    for line in lines[1:]:
        row = dict(zip(header, line.split(",")))
        assert int(row["impacts_right"]) + int(row["impacts_left"]) == int(row["impacts"])
    assert (out / "points.csv").read_text().splitlines()[0] == "branch,w,x,v,phi"
    m = tmp_path / "m"
    p = run(vimpact, *TWO_COMMANDS["map"], "--model", TWO, "--no-plot", "--out", str(m), "--json")
    assert p.returncode == 0, p.stderr
    j = json.loads(p.stdout)
    assert j["grazing_param"] == "d" and j["grazing_surfaces"] == ["right", "left"]
    assert all(len(e) == 3 for e in j["grazing"])
    assert (m / "grazing.csv").read_text().splitlines()[0] == "w,d_graze_right,d_graze_left"


def test_response_of_another_variable(vimpact):
    j = run_json(vimpact, "response", "--model", TWO, "--param", "w", "--range", "0.8:1.4:3", "--variable", "v")
    assert j["variable"] == "v"
    [c] = j["curves"]
    assert c["parameters"] == {}
    assert set(c) >= {"d_graze_right", "d_graze_left", "amplitude", "frequency"}
    # The linear oscillator responds at the forcing frequency.
    for w, f in zip(c["values"], c["frequency"]):
        assert abs(f - w) < 1e-6


def test_config_names_a_model_file_relative_to_itself(vimpact, tmp_path):
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "two.toml").write_text(open(TWO_SIDED_TOML).read())
    cfg = tmp_path / "c.toml"
    cfg.write_text('model = "models/two.toml"\nd = 1.5\n')
    a = run_json(vimpact, "period", "--config", str(cfg))
    b = run_json(vimpact, "period", "--model", TWO, "--set", "d=1.5")
    same(a, b)


def test_points_after_the_impacts_of_one_surface(vimpact):
    # The paper's P3 at Ur = 19 has one impact per period: on the impacts it is a fixed point.
    j = run_json(vimpact, "period", "--set", "Ur=19", "--section", "impacts:barrier")
    assert j["label"] == "P1"
    k = run_json(vimpact, "period", "--model", TWO, "--section", "impacts:left")
    assert k["label"] == "P1" and k["impacts_by_surface"] == {"right": 1, "left": 1}


def test_a_nul_in_a_string_is_refused(vimpact, tmp_path):
    # It ended the C string that holds it in the generated code: the meaning was cut short.
    path = tmp_path / "nul.toml"
    path.write_text(open(TWO_SIDED_TOML).read().replace('meaning = "displacement"', 'meaning = "dis\\u0000placement"'))
    p = run(vimpact, "models", str(path))
    assert p.returncode == 2
    assert p.stderr == f"vimpact: error: model file {path}: state[0].meaning: the string contains a NUL character (\\u0000)\n"


def test_a_model_without_parameters_says_so(vimpact, tmp_path):
    path = tmp_path / "e.toml"
    path.write_text('name = "e"\nstate = ["x", "v"]\n[parameters]\n[derivatives]\nx = "v"\nv = "-1"\n'
                    '[[surfaces]]\nname = "floor"\ngap = "x"\nreset = { v = "-0.5*v" }\n')
    p = run(vimpact, "simulate", "--model", str(path), "--set", "q=1")
    assert p.returncode == 2
    assert p.stderr == "vimpact: error: unknown parameter 'q' in --set (model e has no parameters)\n"


COMPLIANT_TOML = os.path.join(os.path.dirname(TWO_SIDED_TOML), "compliant_stop.toml")


def test_a_model_with_a_switch_lists_it_and_records_its_crossings(vimpact, tmp_path):
    """examples/models/compliant_stop.toml: a switch (the stop's surface y = d, no reset) and no
    impact surface. `models` lists the switch; `simulate` records each crossing in
    switchings.csv, on the surface (y = d) with the state unchanged, entering (v > 0) and
    leaving (v < 0) in turn."""
    p = run(vimpact, "models", COMPLIANT_TOML)
    assert p.returncode == 0, p.stderr
    assert "switches" in p.stdout and "contact" in p.stdout and "surfaces: none" in p.stdout
    [m] = models_json(vimpact, COMPLIANT_TOML)
    assert m["surfaces"] == [] and [s["name"] for s in m["switches"]] == ["contact"]
    out = tmp_path / "run"
    j = run_json(vimpact, "simulate", "--model", COMPLIANT_TOML, "--out", str(out), "--no-plot")
    assert j["outcome"] == "ok" and j["impacts"] == 0
    assert j["stats"]["switchings"] >= j["switchings_recorded"] > 10
    with open(out / "switchings.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == j["switchings_recorded"]
    d = 1.0  # the file's default
    for r in rows:
        assert r["switch"] == "contact"
        assert abs(float(r["y"]) - d) < 1e-9
        assert all(r[name] == r[name + "_after"] for name in ("y", "v", "phi"))
    signs = [float(r["v"]) > 0 for r in rows]
    assert all(a != b for a, b in zip(signs, signs[1:]))
    assert "switchings.csv" in json.load(open(out / "run.json"))["files"]


def test_grazing_of_a_switch_is_the_switch_free_orbits_distance(vimpact):
    """Below the compliant stop the switch-free orbit is the linear forced oscillator's, of
    amplitude X = F/sqrt((1 - w^2)^2 + (2 zeta w)^2): the stop's position d grazes at d = X,
    the margin is d - X. The model has no impact surface: the switch alone is reported."""
    j = run_json(vimpact, "grazing", "--model", COMPLIANT_TOML, "--set", "d=5")
    X = 1.0 / ((1 - 0.8 ** 2) ** 2 + (2 * 0.05 * 0.8) ** 2) ** 0.5
    assert j["surfaces"] == [] and j["converged"] and j["outcome"] == "ok"
    [s] = j["switches"]
    assert s["name"] == "contact" and s["parameter"] == "d" and s["converged"]
    assert abs(s["parameter_value"] - X) < 1e-9 and abs(s["margin"] - (5 - X)) < 1e-9
    assert abs(j["d_graze"] - X) < 1e-9
    p = run(vimpact, "grazing", "--model", COMPLIANT_TOML, "--param", "kc")
    assert p.returncode == 2 and "kc moves no surface or switch" in p.stderr, p.stderr


def test_continuation_labels_the_grazing_of_a_switch(vimpact, tmp_path):
    """The compliant stop's P1 branch from d = 5 to 2: one grazing, of the switch `contact`, at
    the free orbit's amplitude X (closed form), in the JSON and bifurcations.csv."""
    out = tmp_path / "c"
    j = run_json(vimpact, "continue", "--model", COMPLIANT_TOML, "--param", "d", "--range", "5:2", "--out", str(out),
                 "--no-plot")
    X = 1.0 / ((1 - 0.8 ** 2) ** 2 + (2 * 0.05 * 0.8) ** 2) ** 0.5
    [g] = [b for b in j["bifurcations"] if b["type"] == "grazing"]
    assert g["switch"] == "contact" and g["surface"] is None and abs(g["param"] - X) < 1e-8
    with open(out / "bifurcations.csv") as f:
        rows = [r for r in csv.DictReader(f) if r["type"] == "grazing"]
    assert [r["switch"] for r in rows] == ["contact"] and rows[0]["surface"] == ""
