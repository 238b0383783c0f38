"""The command line end to end: the JSON contract, files written, exit codes, bad input."""
import json
import os
import subprocess
import time

import pytest

from conftest import check_png


def run(vimpact, *args, cwd=None):
    return subprocess.run([vimpact, *args], capture_output=True, text=True, cwd=cwd, timeout=600)


def run_json(vimpact, *args):
    p = run(vimpact, *args, "--json")
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


def assert_by_surface(j, total_key="impacts"):
    """impacts_by_surface: an object surface -> count summing to the total."""
    by = j["impacts_by_surface"]
    assert isinstance(by, dict) and by
    assert sum(by.values()) == j[total_key]


# The paper's labels (its Section 3 and Figure 2d-h): P2 at Ur = 16, P3 at 19, P4 at 21.5,
# P8 at 24.8, each with one impact per period; aperiodic at 24.4 below.
@pytest.mark.parametrize("ur,label", [("16", "P2"), ("19", "P3"), ("21.5", "P4"), ("24.8", "P8")])
def test_period_labels_match_the_paper(vimpact, ur, label):
    j = run_json(vimpact, "period", "--set", f"Ur={ur}")
    assert j["label"] == label
    assert j["impacts"] == 1
    assert j["impacts_by_surface"] == {"barrier": 1}
    assert j["outcome"] == "ok"
    assert len(j["section_y"]) == j["period"]
    assert len(j["cycle"]) == j["period"] and all(len(x) == 4 for x in j["cycle"])
    assert [x[0] for x in j["cycle"]] == j["section_y"]


def test_the_papers_aperiodic_example(vimpact):
    j = run_json(vimpact, "period", "--set", "Ur=24.4")
    assert j["label"] == "aperiodic" and j["period"] is None and j["outcome"] == "ok"


# The paper's Figure 5c-f at Ur = 25: P6 at sigma = -0.149, aperiodic at -0.146, P2 at -0.020
# and P4 at -0.021 (the paper gives no impact counts; these are ours).
@pytest.mark.parametrize("sigma,label", [("-0.149", "P6"), ("-0.146", "aperiodic"), ("-0.020", "P2"),
                                         ("-0.021", "P4")])
def test_period_labels_of_figure_5(vimpact, sigma, label):
    j = run_json(vimpact, "period", "--set", "Ur=25", "--set", f"sigma={sigma}")
    assert j["label"] == label and j["outcome"] == "ok"


def test_period_without_impacts_is_P0(vimpact):
    j = run_json(vimpact, "period", "--set", "sigma=-5")
    assert j["label"] == "P0"
    assert j["period"] == 0
    assert j["impacts_by_surface"] == {"barrier": 0}


def test_grazing_reproduces_the_published_value(vimpact):
    j = run_json(vimpact, "grazing", "--set", "Ur=25")
    assert j["converged"]
    assert abs(j["sigma_graze"] - (-0.150298)) < 5e-7
    [s] = j["surfaces"]
    assert s["name"] == "barrier" and s["parameter"] == "sigma" and s["converged"]
    assert s["parameter_value"] == j["sigma_graze"]
    # The margin is the orbit's clearance of the barrier at the configured sigma.
    assert abs(s["margin"] - (j["sigma_graze"] - (-0.150298))) < 1e-12


def test_grazing_of_a_named_parameter(vimpact):
    j = run_json(vimpact, "grazing", "--set", "Ur=25", "--param", "sigma")
    assert abs(j["sigma_graze"] - (-0.150298)) < 5e-7
    p = run(vimpact, "grazing", "--param", "Ur")
    assert p.returncode == 2 and "enters the vector field" in p.stderr


def test_simulate_json_contract(vimpact):
    j = run_json(vimpact, "simulate", "--transient", "20", "--record", "10")
    assert j["outcome"] == "ok"
    assert isinstance(j["impacts"], int) and j["impacts"] >= 20
    assert j["section_points"] == 10
    for key in ("steps", "rejected", "rhs_calls", "impacts", "t_final", "impacts_by_surface"):
        assert key in j["stats"]
    assert_by_surface(j)
    assert_by_surface(j["stats"])
    assert len(j["final_state"]) == 4


def test_hold_band_reaches_the_integrator(vimpact, tmp_path):
    # A held step keeps its size: a different sequence of steps, the same impacts.
    a = run_json(vimpact, "simulate", "--transient", "20", "--record", "10")
    b = run_json(vimpact, "simulate", "--transient", "20", "--record", "10", "--hold-band", "0.1")
    assert a["stats"]["impacts"] == b["stats"]["impacts"]
    assert a["stats"]["steps"] != b["stats"]["steps"]
    # From a config file too, and written to the run's config.toml.
    cfg = tmp_path / "c.toml"
    cfg.write_text("hold_band = 0.1\n")
    c = run_json(vimpact, "simulate", "--transient", "20", "--record", "10", "--config", str(cfg))
    assert c["stats"] == b["stats"]
    out = tmp_path / "out"
    assert run(vimpact, "simulate", "--transient", "20", "--record", "10", "--hold-band", "0.1", "--no-plot",
               "--out", str(out)).returncode == 0
    assert "hold_band = 0.1" in (out / "config.toml").read_text()


def test_each_method_has_its_default_hold_band(vimpact):
    # Without --hold-band, DOPRI5 holds from 0.1 and DOP853 not at all (docs/performance.md).
    q = ("simulate", "--transient", "20", "--record", "10")
    for method, band, other in (("dopri5", "0.1", "0"), ("dop853", "0", "0.1")):
        d = run_json(vimpact, *q, "--method", method)
        assert d["stats"] == run_json(vimpact, *q, "--method", method, "--hold-band", band)["stats"]
        assert d["stats"]["steps"] != run_json(vimpact, *q, "--method", method, "--hold-band", other)["stats"]["steps"]


# The protocol's options are the library's declaration (analysis/protocol_declaration.hpp): the
# library refuses a value out of its range and the message names the option as typed, with the
# range the library enforced before (rtol (0, 1) and >= 1e-15 as one range).
@pytest.mark.parametrize("args,message", [
    (["--rtol", "2"], "--rtol = 2 is outside its valid range [1e-15, 1)"),
    (["--rtol", "1e-16"], "--rtol = 1e-16 is outside its valid range [1e-15, 1)"),
    (["--atol", "1"], "--atol = 1 is outside its valid range [1e-300, 1)"),
    (["--hold-band", "1"], "--hold-band = 1 is outside its valid range [0, 1)"),
    (["--hold-band=-0.5"], "--hold-band = -0.5 is outside its valid range [0, 1)"),
    (["--max-step", "0"], "--max-step = 0 is outside its valid range (0, inf]"),
    (["--transient=-1"], "--transient = -1 is outside its valid range [0, 1e+09]"),
])
def test_a_protocol_option_out_of_range_exits_2_naming_it(vimpact, tmp_path, args, message):
    out = tmp_path / "out"
    for command in (["period"], ["sweep", "--param", "Ur", "--range", "15:16:2"]):
        p = run(vimpact, *command, *args, "--out", str(out))
        assert p.returncode == 2, p.stderr
        assert p.stderr.strip() == "vimpact: error: " + message
        assert not out.exists()


def test_a_protocol_option_in_a_config_file_names_the_file(vimpact, tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text("hold_band = 1\n")
    p = run(vimpact, "period", "--config", str(cfg))
    assert p.returncode == 2
    assert p.stderr.strip() == f"vimpact: error: config {cfg}: hold_band = 1 is outside its valid range [0, 1)"
    # The command line wins over the file, the file over the defaults.
    cfg.write_text("rtol = 1e-8\nmax_step = 0.5\n")

    def config(*args):
        out = tmp_path / f"out{len(os.listdir(tmp_path))}"
        p = run(vimpact, "simulate", "--transient", "20", "--record", "10", *args, "--no-plot", "--out", str(out))
        assert p.returncode == 0, p.stderr
        return json.loads((out / "run.json").read_text())["config"]

    assert config("--config", str(cfg))["rtol"] == 1e-8
    assert config("--config", str(cfg), "--rtol", "1e-9")["rtol"] == 1e-9
    assert config("--config", str(cfg))["max_step"] == 0.5
    assert "max_step" not in config()  # none


def test_the_help_gives_the_declared_defaults_and_ranges(vimpact):
    p = run(vimpact, "period", "--help")
    text = " ".join(p.stdout.split())
    for needle in ("--transient", "(default 500; [0, 1e+09])", "--record", "(default 200; [1, 1e+07])",
                   "--hold-band", "(default none; [0, 1))", "--max-step", "(default inf; (0, inf])",
                   "--method", "(default dop853; one of dop853, dopri5)"):
        assert needle in text, needle
    # dimension keeps its own default record.
    assert "(default 20000; [1, 1e+07])" in " ".join(run(vimpact, "dimension", "--help").stdout.split())


def test_results_are_deterministic(vimpact):
    a = run(vimpact, "period", "--json", "--set", "Ur=21.5")
    b = run(vimpact, "period", "--json", "--set", "Ur=21.5")
    assert a.stdout == b.stdout


def test_config_file_equals_set_options(vimpact, tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text('Ur = 19.0\nsigma = -0.150298\nic = [0.0, 0.0, 0.0, 0.1]\nrtol = 1e-10\n')
    a = run_json(vimpact, "period", "--config", str(cfg))
    b = run_json(vimpact, "period", "--set", "Ur=19")
    assert a["label"] == b["label"] == "P3"
    assert a["section_y"] == b["section_y"]


def test_config_file_names_the_model_and_section(vimpact, tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text('model = "two_sided_impact_oscillator"\nsection = "strobe"\nd = 1.5\nic = [0.1, 0.0, 0.0]\n')
    a = run_json(vimpact, "period", "--config", str(cfg), "--transient", "50", "--record", "20")
    b = run_json(vimpact, "period", "--model", "two_sided_impact_oscillator", "--set", "d=1.5", "--ic", "0.1,0,0",
                 "--transient", "50", "--record", "20")
    assert a == b


def test_out_directory_has_csv_record_and_png(vimpact, tmp_path):
    out = tmp_path / "run"
    p = run(vimpact, "simulate", "--transient", "30", "--record", "20", "--out", str(out))
    assert p.returncode == 0, p.stderr
    assert str(out) in p.stdout
    for name, header in (("timeseries.csv", "t,y,ydot,x,xdot"), ("sections.csv", "t,y,ydot,x,xdot"),
                         ("impacts.csv", "t,y,ydot_before,ydot_after,x,xdot,surface,normal_velocity,rebound_velocity,energy")):
        lines = (out / name).read_text().splitlines()
        assert lines[0] == header
        assert len(lines) > 1
    impact = (out / "impacts.csv").read_text().splitlines()[1].split(",")
    assert impact[-4] == "barrier"
    assert float(impact[1]) == -0.150298  # y at the barrier
    assert abs(float(impact[3]) + 0.8 * float(impact[2])) < 1e-15  # ydot after = -r ydot before
    record = json.loads((out / "run.json").read_text())
    assert record["version"] and record["git_hash"]
    assert record["config"]["parameters"]["Ur"] == 16
    assert record["config"]["model"] == "wake_impact"
    assert record["model"]["name"] == "wake_impact"
    assert record["model"]["source"] == "built-in"
    assert record["model"]["identity"]
    assert record["model"]["parameters"]["sigma"] == -0.150298
    assert record["model"]["state_names"] == ["y", "ydot", "x", "xdot"]
    assert record["state_names"] == ["y", "ydot", "x", "xdot"]
    assert record["plot_variable"] == "y"
    assert record["result"]["outcome"] == "ok"
    check_png(out / "plot.png")
    assert not [f for f in os.listdir(tmp_path) if f.startswith(".vimpact-staging")]


BAD_INPUTS = [
    (["period", "--set", "nope=1"], "nope"),
    (["period", "--set", "Ur=abc"], "abc"),
    (["period", "--set", "r=1.5"], "r = 1.5"),
    (["period", "--set", "mu=0"], "mu"),
    (["period", "--set", "Ur=16", "--set", "Ur=19"], "Ur"),
    (["period", "--set", "Ur=16", "--set", "Ur=16"], "twice"),
    (["period", "--ic", "-0.5,0,0,0.1"], "beyond surface barrier"),
    (["period", "--ic", "0,0,0"], "--ic needs 4 numbers (y, ydot, x, xdot), got 3"),
    (["period", "--config", "/nonexistent/file.toml"], "config"),
    (["period", "--rtol", "2"], "rtol"),
    (["period", "--hold-band", "1"], "--hold-band = 1 is outside its valid range [0, 1)"),
    (["period", "--record", "0"], "record"),
    (["period", "--tol", "0"], "--tol = 0 is outside its valid range > 0"),
    (["dimension", "--tol", "-1"], "--tol = -1 is outside its valid range > 0"),
    (["period", "--method", "euler"], "method"),
    (["period", "--section", "sideways"], "maxima, minima, impacts, impacts:barrier"),
    (["period", "--preset", "nope"], "paper, facchinetti"),
    (["period", "--model", "nope"], "two_sided_impact_oscillator"),
    (["period", "--model", "/nonexistent/model.toml"], "/nonexistent/model.toml"),
    (["period", "--model", "two_sided_impact_oscillator", "--set", "Ur=16"], "zeta, a, w, d, r"),
    (["period", "--model", "two_sided_impact_oscillator", "--ic", "0,0,0,0.1"], "(x, v, phi), got 4"),
    (["period", "--model", "two_sided_impact_oscillator", "--preset", "paper"], "no presets"),
    (["grazing", "--param", "nope"], "nope"),
    (["frobnicate"], "frobnicate"),
]


@pytest.mark.parametrize("args,needle", BAD_INPUTS)
def test_bad_input_exits_2_with_one_line_and_writes_nothing(vimpact, tmp_path, args, needle):
    out = tmp_path / "out"
    p = run(vimpact, *args, "--out", str(out)) if args[0] != "frobnicate" else run(vimpact, *args)
    assert p.returncode == 2, (p.returncode, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1, p.stderr
    assert lines[0].startswith("vimpact: error: ")
    assert needle in lines[0]
    assert p.stdout == ""
    assert not out.exists()
    assert not [f for f in os.listdir(tmp_path) if f.startswith(".vimpact-staging")]


@pytest.mark.parametrize("content,needle", [
    ("Ur = 16\nbogus = 3\n", "bogus"),
    ("Ur = [1, 2\n", "config"),
    ("Ur = 'fast'\n", "Ur"),
    ("ic = [0, 0, 0]\n", "(y, ydot, x, xdot)"),
    ('model = "nope"\n', "nope"),
])
def test_bad_config_exits_2(vimpact, tmp_path, content, needle):
    cfg = tmp_path / "bad.toml"
    cfg.write_text(content)
    p = run(vimpact, "period", "--config", str(cfg))
    assert p.returncode == 2
    assert len(p.stderr.strip().splitlines()) == 1
    assert needle in p.stderr


def test_config_that_is_a_directory_exits_2(vimpact, tmp_path):
    p = run(vimpact, "period", "--config", str(tmp_path))
    assert p.returncode == 2 and "directory" in p.stderr
    assert len(p.stderr.strip().splitlines()) == 1


# --out is checked before anything is computed: a long run (Ur = 25 with 1e6 section points
# would take minutes) is refused at once, and nothing is left behind.
OUT_COMMANDS = [
    ["simulate", "--set", "Ur=25", "--record", "1000000"],
    ["sweep", "--param", "Ur", "--range", "12:25:1000"],
    ["map", "--x", "Ur:12:25:100", "--y", "sigma:-0.2:0:100"],
    ["dimension", "--set", "Ur=25"],
    ["floquet", "--param", "Ur", "--range", "12:25:100"],
    ["grazing"],
]


@pytest.mark.parametrize("args", OUT_COMMANDS, ids=[a[0] for a in OUT_COMMANDS])
def test_out_that_is_a_file_exits_2_before_computing(vimpact, tmp_path, args):
    target = tmp_path / "taken"
    target.write_text("not a directory\n")
    before = sorted(os.listdir(tmp_path))
    start = time.monotonic()
    p = run(vimpact, *args, "--out", str(target))
    elapsed = time.monotonic() - start
    assert p.returncode == 2, p.stderr
    assert elapsed < 1.0, elapsed
    assert len(p.stderr.strip().splitlines()) == 1 and "not a directory" in p.stderr
    assert sorted(os.listdir(tmp_path)) == before
    assert target.read_text() == "not a directory\n"


def test_out_below_a_file_exits_2(vimpact, tmp_path):
    (tmp_path / "file").write_text("x")
    p = run(vimpact, "simulate", "--out", str(tmp_path / "file" / "sub" / "dir"))
    assert p.returncode == 2 and "is not a directory" in p.stderr
    assert sorted(os.listdir(tmp_path)) == ["file"]


def test_out_in_an_unwritable_place_exits_2(vimpact, tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        if os.access(locked, os.W_OK):
            pytest.skip("running as a user who can write anywhere")
        p = run(vimpact, "simulate", "--out", str(locked / "run"))
        assert p.returncode == 2 and "cannot write" in p.stderr
        assert os.listdir(locked) == []
    finally:
        locked.chmod(0o700)
