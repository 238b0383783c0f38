"""vimpact dimension end to end: the JSON contract, point files, files written, bad input."""
import json
import math
import os
import subprocess

import pytest

from conftest import check_png


def run(vimpact, *args):
    return subprocess.run([vimpact, *args], capture_output=True, text=True, timeout=600)


def run_json(vimpact, *args):
    p = run(vimpact, "dimension", *args, "--json")
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


def henon_csv(path, n=5000, extra=True):
    """The Henon map (a = 1.4, b = 0.3) after 1000 discarded iterates: columns t, x, y[, z]."""
    x, y = 0.1, 0.1
    rows = []
    for i in range(n + 1000):
        x, y = 1.0 - 1.4 * x * x + y, 0.3 * x
        if i >= 1000:
            rows.append((i - 1000, x, y))
    with open(path, "w") as f:
        f.write("t,x,y,z\n" if extra else "t,x,y\n")
        for t, a, b in rows:
            f.write(f"{t},{a!r},{b!r},{7.0!r}\n" if extra else f"{t},{a!r},{b!r}\n")
    return path


def test_json_contract_of_a_model_run(vimpact):
    # The aperiodic band between P2 and P3 (docs/reproduction-fig6.md); a short record.
    j = run_json(vimpact, "--set", "Ur=18.455", "--transient", "300", "--record", "2000")
    for key in ("dimension", "fit_range", "points", "r2", "estimator", "total_pairs", "scaling_region",
                "slope_error", "fitted_radii", "source"):
        assert key in j, key
    assert j["points"] == 2000
    assert j["estimator"] == "correlation_sum"
    assert j["total_pairs"] == 2000 * 1999 // 2
    r_min, r_max = j["fit_range"]
    assert 0 < r_min < r_max
    assert 0 < j["r2"] <= 1
    assert j["source"]["kind"] == "model"
    assert j["source"]["columns"] == ["y", "ydot", "x", "xdot"]
    assert j["coordinates"] == 4
    assert j["source"]["outcome"] == "ok"
    assert 0.5 < j["dimension"] < 3.0


def test_without_record_the_run_keeps_20000_points(vimpact):
    j = run_json(vimpact, "--set", "Ur=16", "--transient", "50")
    assert j["points"] == 20000
    assert j["source"]["label"] == "P2"
    assert abs(j["dimension"]) < 0.02  # a finite set of points


def test_points_file_and_column_selection(vimpact, tmp_path):
    f = henon_csv(tmp_path / "henon.csv")
    j = run_json(vimpact, "--points", str(f), "--columns", "x,y")
    assert j["points"] == 5000
    assert j["coordinates"] == 2
    assert j["source"] == {"kind": "file", "file": str(f), "columns": ["x", "y"], "rows": 5000}
    assert abs(j["dimension"] - 1.21) < 0.05  # Grassberger & Procaccia (1983): 1.21 +- 0.01
    # Default columns: all but t. A constant column adds nothing to any distance.
    k = run_json(vimpact, "--points", str(f))
    assert k["source"]["columns"] == ["x", "y", "z"]
    assert k["dimension"] == j["dimension"]


def test_search_methods_and_threads_give_the_same_numbers(vimpact, tmp_path):
    f = henon_csv(tmp_path / "henon.csv", n=3000, extra=False)
    results = [run_json(vimpact, "--points", str(f), "--search", s, "--threads", t)
               for s, t in (("grid", "1"), ("kd_tree", "1"), ("brute_force", "1"), ("grid", "3"))]
    for r in results[1:]:
        assert r["dimension"] == results[0]["dimension"]
        assert r["fit_range"] == results[0]["fit_range"]


def test_centres_estimator_and_user_fit_range(vimpact, tmp_path):
    f = henon_csv(tmp_path / "henon.csv", extra=False)
    j = run_json(vimpact, "--points", str(f), "--estimator", "centres")
    assert j["estimator"] == "centres"
    assert len(j["centres"]) == 15
    assert j["radii"] == 600  # the paper's 1e-4 .. 0.06 in steps of 1e-4
    assert j["total_pairs"] == 15 * 4999
    k = run_json(vimpact, "--points", str(f), "--fit-range", "0.001:0.05")
    assert k["scaling_region"] == "user"
    assert 0.001 <= k["fit_range"][0] < k["fit_range"][1] <= 0.05


def test_theiler_window_reduces_the_pairs(vimpact, tmp_path):
    f = henon_csv(tmp_path / "henon.csv", n=1000, extra=False)
    j = run_json(vimpact, "--points", str(f), "--theiler", "10")
    assert j["total_pairs"] == (1000 - 11) * (1000 - 10) // 2
    assert j["theiler_window"] == 10


def test_the_constant_column_changes_nothing(vimpact):
    # ydot is 0 on the section of maxima: every state column and (y, x, xdot) count the same pairs.
    a = run_json(vimpact, "--set", "Ur=18.455", "--transient", "300", "--record", "2000")
    b = run_json(vimpact, "--set", "Ur=18.455", "--transient", "300", "--record", "2000", "--columns", "y,x,xdot")
    assert b["source"]["columns"] == ["y", "x", "xdot"]
    assert a["dimension"] == b["dimension"] and a["fit_range"] == b["fit_range"]


def test_phases_are_cos_sin_pairs(vimpact):
    j = run_json(vimpact, "--model", "two_sided_impact_oscillator", "--transient", "20", "--record", "300")
    assert j["source"]["columns"] == ["x", "v", "phi_cos", "phi_sin"]
    assert j["coordinates"] == 4
    assert j["source"]["section"] == "strobe"
    k = run_json(vimpact, "--model", "two_sided_impact_oscillator", "--transient", "20", "--record", "300",
                 "--columns", "x,v")
    assert k["source"]["columns"] == ["x", "v"]


def test_results_are_deterministic(vimpact):
    a = run(vimpact, "dimension", "--set", "Ur=20.85", "--transient", "200", "--record", "1500", "--json")
    b = run(vimpact, "dimension", "--set", "Ur=20.85", "--transient", "200", "--record", "1500", "--json")
    assert a.returncode == 0
    assert a.stdout == b.stdout


def test_out_directory(vimpact, tmp_path):
    out = tmp_path / "dim"
    p = run(vimpact, "dimension", "--set", "Ur=18.455", "--transient", "200", "--record", "1500", "--out", str(out))
    assert p.returncode == 0, p.stderr
    assert "correlation dimension" in p.stdout
    for name in ("points.csv", "correlation.csv", "sections.csv", "run.json"):
        assert (out / name).exists(), name
    assert (out / "points.csv").read_text().splitlines()[0] == "y,ydot,x,xdot"
    assert (out / "sections.csv").read_text().splitlines()[0] == "t,y,ydot,x,xdot"
    curve = (out / "correlation.csv").read_text().splitlines()
    assert curve[0] == "r,C,pairs,local_slope,in_fit"
    record = json.loads((out / "run.json").read_text())
    assert record["command"] == "dimension"
    assert record["config"]["parameters"]["Ur"] == 18.455
    assert record["result"]["points"] == 1500
    assert record["model"]["name"] == "wake_impact"
    fitted = [line for line in curve[1:] if line.endswith(",1")]
    assert len(fitted) == record["result"]["fitted_radii"]
    check_png(out / "plot.png")
    assert not [f for f in os.listdir(tmp_path) if f.startswith(".vimpact-staging")]


def write(tmp_path, name, text):
    f = tmp_path / name
    f.write_text(text)
    return str(f)


BAD = [
    # (arguments, text the one-line message must contain)
    (["--points", "/nonexistent/points.csv"], "/nonexistent/points.csv"),
    (["--points", "HENON", "--columns", "x,speed"], "no column 'speed'"),
    (["--points", "HENON", "--columns", "x,speed"], "columns: t, x, y"),
    (["--points", "HENON", "--fit-range", "0.1:0.01"], "--fit-range 0.1:0.01"),
    (["--points", "HENON", "--fit-range", "0.1:0.01"], "0 < r_min < r_max"),
    (["--points", "HENON", "--fit-range", "0.01"], "r_min:r_max"),
    (["--points", "HENON", "--fit-range", "50:60"], "span"),
    (["--points", "BADNUM"], "line 3, column 'y'"),
    (["--points", "SHORT"], "line 2"),
    (["--points", "HENON", "--set", "Ur=18"], "--set"),
    (["--points", "HENON", "--estimator", "boxes"], "correlation_sum, centres"),
    (["--points", "HENON", "--theiler", "-1"], "--theiler"),
    (["--points", "HENON", "--theiler", "4999"], "Theiler window"),
    (["--points", "HENON", "--radii", "0:0.06:1e-4"], "--radii"),
    (["--points", "HENON", "--centres", "0"], "--centres"),
    (["--points", "HENON", "--estimator", "centres", "--centres", "9999"], "centres must be in [1, 5000]"),
    (["--points", "HENON", "--search", "octree"], "grid, kd_tree, brute_force"),
    (["--points", "HENON", "--bins-per-octave", "12"], "power of two"),
    (["--points", "HENON", "--slope-tolerance", "0"], "--slope-tolerance = 0 is outside its valid range > 0"),
    (["--points", "HENON", "--max-correlation", "2"], "--max-correlation = 2 is outside its valid range (0, 1]"),
    (["--points", "HENON", "--max-pairs", "1.5"], "--max-pairs = 1.5 is not a whole number"),
    (["--points", "HENON", "--min-pairs", "-3"], "--min-pairs = -3 is not a whole number in its valid range >= 1"),
    (["--set", "Ur=16", "--columns", "y,v"], "no column 'v'"),
    (["--points", "HENON", "--model", "two_sided_impact_oscillator"], "--model"),
    (["--set", "Ur=16", "--record", "0"], "record"),
]


@pytest.mark.parametrize("args,needle", BAD)
def test_bad_input_exits_2_with_one_line_and_writes_nothing(vimpact, tmp_path, args, needle):
    files = {
        "HENON": str(henon_csv(tmp_path / "henon.csv", extra=False)),
        "BADNUM": write(tmp_path, "badnum.csv", "x,y\n1,2\n3,abc\n"),
        "SHORT": write(tmp_path, "short.csv", "x,y\n1\n"),
    }
    args = [files.get(a, a) for a in args]
    out = tmp_path / "out"
    p = run(vimpact, "dimension", *args, "--out", str(out))
    assert p.returncode == 2, (p.returncode, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1, p.stderr
    assert lines[0].startswith("vimpact: error: ")
    assert needle in lines[0], lines[0]
    assert p.stdout == ""
    assert not out.exists()
    assert not [f for f in os.listdir(tmp_path) if f.startswith(".vimpact-staging")]


def test_paper_variant_reports_its_centres_on_the_picture_data(vimpact, tmp_path):
    f = henon_csv(tmp_path / "henon.csv", n=2000, extra=False)
    out = tmp_path / "c"
    p = run(vimpact, "dimension", "--points", str(f), "--estimator", "centres", "--centres", "6", "--out", str(out))
    assert p.returncode == 0, p.stderr
    record = json.loads((out / "run.json").read_text())
    # Evenly spaced along the record: floor((2k + 1) N / (2K)).
    assert record["result"]["centres"] == [math.floor((2 * k + 1) * 2000 / 12) for k in range(6)]
