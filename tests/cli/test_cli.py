"""The command line end to end: the JSON contract, files written, exit codes, bad input."""
import json
import os
import subprocess

import pytest


def run(vimpact, *args, cwd=None):
    return subprocess.run([vimpact, *args], capture_output=True, text=True, cwd=cwd, timeout=600)


def run_json(vimpact, *args):
    p = run(vimpact, *args, "--json")
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


# Published values (the paper, Section 3, as read in SPEC §2): P2 at Ur = 16, P3 at 19.
@pytest.mark.parametrize("ur,label", [("16", "P2"), ("19", "P3")])
def test_period_labels_match_the_paper(vimpact, ur, label):
    j = run_json(vimpact, "period", "--set", f"Ur={ur}")
    assert j["label"] == label
    assert j["impacts"] == 1
    assert j["outcome"] == "ok"
    assert len(j["section_y"]) == j["period"]


def test_period_without_impacts_is_P0(vimpact):
    j = run_json(vimpact, "period", "--set", "sigma=-5")
    assert j["label"] == "P0"
    assert j["period"] == 0


def test_grazing_reproduces_the_published_value(vimpact):
    j = run_json(vimpact, "grazing", "--set", "Ur=25")
    assert j["converged"]
    assert abs(j["sigma_graze"] - (-0.150298)) < 5e-7


def test_simulate_json_contract(vimpact):
    j = run_json(vimpact, "simulate", "--transient", "20", "--record", "10")
    assert j["outcome"] == "ok"
    assert isinstance(j["impacts"], int) and j["impacts"] >= 20
    assert j["section_points"] == 10
    for key in ("steps", "rejected", "rhs_calls", "impacts", "t_final"):
        assert key in j["stats"]


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


def test_out_directory_has_csv_record_and_png(vimpact, tmp_path):
    out = tmp_path / "run"
    p = run(vimpact, "simulate", "--transient", "30", "--record", "20", "--out", str(out))
    assert p.returncode == 0, p.stderr
    assert str(out) in p.stdout
    for name, header in (("timeseries.csv", "t,y,ydot,x,xdot"), ("sections.csv", "t,y,ydot,x,xdot"),
                         ("impacts.csv", "t,y,ydot_before,ydot_after,x,xdot")):
        lines = (out / name).read_text().splitlines()
        assert lines[0] == header
        assert len(lines) > 1
    record = json.loads((out / "run.json").read_text())
    assert record["version"] and record["git_hash"]
    assert record["config"]["parameters"]["Ur"] == 16
    assert record["result"]["outcome"] == "ok"
    assert (out / "plot.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not [f for f in os.listdir(tmp_path) if f.startswith(".vimpact-staging")]


BAD_INPUTS = [
    (["period", "--set", "nope=1"], "nope"),
    (["period", "--set", "Ur=abc"], "abc"),
    (["period", "--set", "r=1.5"], "r = 1.5"),
    (["period", "--set", "mu=0"], "mu"),
    (["period", "--ic", "-0.5,0,0,0.1"], "below the barrier"),
    (["period", "--ic", "0,0,0"], "--ic"),
    (["period", "--config", "/nonexistent/file.toml"], "config"),
    (["period", "--rtol", "2"], "rtol"),
    (["period", "--record", "0"], "record"),
    (["period", "--method", "euler"], "method"),
    (["period", "--section", "sideways"], "section"),
    (["frobnicate"], ""),
]


@pytest.mark.parametrize("args,needle", BAD_INPUTS)
def test_bad_input_exits_2_with_one_line_and_writes_nothing(vimpact, tmp_path, args, needle):
    out = tmp_path / "out"
    p = run(vimpact, *args, "--out", str(out)) if args[0] != "frobnicate" else run(vimpact, *args)
    assert p.returncode == 2, (p.returncode, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1, p.stderr
    assert needle in lines[0]
    assert p.stdout == ""
    assert not out.exists()
    assert not [f for f in os.listdir(tmp_path) if f.startswith(".vimpact-staging")]


@pytest.mark.parametrize("content,needle", [
    ("Ur = 16\nbogus = 3\n", "bogus"),
    ("Ur = [1, 2\n", "config"),
    ("Ur = 'fast'\n", "Ur"),
])
def test_bad_config_exits_2(vimpact, tmp_path, content, needle):
    cfg = tmp_path / "bad.toml"
    cfg.write_text(content)
    p = run(vimpact, "period", "--config", str(cfg))
    assert p.returncode == 2
    assert len(p.stderr.strip().splitlines()) == 1
    assert needle in p.stderr
