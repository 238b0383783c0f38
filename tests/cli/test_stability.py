"""The stability commands end to end: floquet and lyapunov (docs/stability.md)."""
import json
import math
import os
import subprocess

import pytest

from conftest import check_png


def run(vimpact, *args):
    return subprocess.run([vimpact, *args], capture_output=True, text=True, timeout=600)


def run_json(vimpact, *args):
    p = run(vimpact, *args, "--json")
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


# Reference values, not the paper's (it prints no multipliers): measured on the paper preset,
# sigma = -0.150298, by an independent computation when this project was specified, and kept
# only here, never in the program, which computes them.
REFERENCE = {
    "16": {"T": 15.2892, "mu": [-0.19582, 0.0023068]},
    "14.9": {"T": 15.2250, "mu": [-0.081771, 0.0037145]},
}


@pytest.mark.parametrize("ur", sorted(REFERENCE))
def test_floquet_reproduces_the_reference_multipliers(vimpact, ur):
    j = run_json(vimpact, "floquet", "--set", f"Ur={ur}")
    ref = REFERENCE[ur]
    assert j["outcome"] == "ok"
    assert j["label"] == "P2"
    assert j["impacts_per_period"] == 1
    assert abs(j["period"] - ref["T"]) < 1e-4
    assert j["closure"] <= 1e-11
    mu = [complex(re, im) for re, im in j["multipliers"]]
    assert len(mu) == 4
    # An autonomous flow's monodromy has the multiplier 1 along the orbit.
    assert abs(mu[0] - 1) < 1e-9
    # The nontrivial ones by decreasing modulus: -0.19582, 0.0023068, ~0 (printed digits).
    for got, want in zip(mu[1:3], ref["mu"]):
        assert abs(got.imag) < 1e-12
        assert abs(got.real - want) <= 0.6 * 10 ** (math.floor(math.log10(abs(want))) - 4)
    assert abs(mu[3]) < 1e-6
    assert j["stable"] is True
    assert j["moduli"][1:] == sorted(j["moduli"][1:], reverse=True)
    assert j["impacts_by_surface"] == {"barrier": 1}


def test_floquet_without_saltation_loses_the_trivial_multiplier(vimpact):
    for jump in ("reset-jacobian", "identity"):
        j = run_json(vimpact, "floquet", "--set", "Ur=16", "--impact-map", jump)
        assert j["impact_map"] == jump
        mu = [complex(re, im) for re, im in j["multipliers"]]
        assert min(abs(m - 1) for m in mu) > 0.03


def test_floquet_of_an_aperiodic_point_has_no_multipliers(vimpact):
    j = run_json(vimpact, "floquet", "--set", "Ur=25", "--set", "sigma=-0.146")
    assert j["label"] == "aperiodic"
    assert j["outcome"] == "aperiodic"
    assert j["multipliers"] == []
    assert j["period"] is None
    assert j["trivial_error"] is None


def test_lyapunov_json_contract_on_a_periodic_orbit(vimpact):
    j = run_json(vimpact, "lyapunov", "--set", "Ur=16", "--impacts", "300")
    assert j["outcome"] == "ok"
    assert j["tdm"] == "saltation"
    e = j["exponents"]
    assert len(e) == 4 and e == sorted(e, reverse=True)
    assert abs(e[0]) < 2e-3  # the flow direction of a periodic orbit
    assert j["impacts"] >= 300
    assert sum(j["impacts_by_surface"].values()) == j["impacts"]
    assert j["time"] > 0
    assert abs(sum(e) - j["sum_rule"]) < 1e-8
    r = 0.8
    assert abs(j["sum_rule"] - (j["divergence_average"] + j["impacts"] / j["time"] * math.log(r * r))) < 1e-10


@pytest.mark.parametrize("tdm", ["second-order", "trajectory"])
def test_lyapunov_other_mappings(vimpact, tdm):
    j = run_json(vimpact, "lyapunov", "--set", "Ur=16", "--impacts", "300", "--tdm", tdm)
    assert j["outcome"] == "ok"
    assert j["tdm"] == tdm
    assert abs(j["exponents"][0]) < 2e-3
    if tdm == "trajectory":
        assert j["sum_rule"] is None


def test_lyapunov_chaotic_point_is_positive(vimpact):
    j = run_json(vimpact, "lyapunov", "--set", "Ur=25", "--set", "sigma=-0.146")
    assert j["lle"] > 5 * j["lle_standard_error"]
    assert j["lle"] > 0.01


def test_lyapunov_time_option_averages_over_time(vimpact):
    j = run_json(vimpact, "lyapunov", "--set", "Ur=16", "--time", "1000", "--t0", "1")
    # The window ends at the first interval end at or past the time, to rounding: the
    # intervals' ends are sums of doubles, so 1000 may come out an ulp or two short.
    assert 1000 * (1 - 1e-12) <= j["time"] < 1001
    assert j["t0"] == 1


def test_results_are_deterministic(vimpact):
    a = run(vimpact, "lyapunov", "--json", "--set", "Ur=19", "--impacts", "100", "--tdm", "trajectory")
    b = run(vimpact, "lyapunov", "--json", "--set", "Ur=19", "--impacts", "100", "--tdm", "trajectory")
    assert a.returncode == 0 and a.stdout == b.stdout


@pytest.mark.parametrize("command,files", [
    (["floquet", "--set", "Ur=16"], ["multipliers.csv", "orbit.csv", "impacts.csv"]),
    (["lyapunov", "--set", "Ur=16", "--impacts", "100"], ["convergence.csv"]),
])
def test_out_directory_has_csv_record_and_png(vimpact, tmp_path, command, files):
    out = tmp_path / "run"
    p = run(vimpact, *command, "--out", str(out))
    assert p.returncode == 0, p.stderr
    for name in files:
        lines = (out / name).read_text().splitlines()
        assert len(lines) > 1
    record = json.loads((out / "run.json").read_text())
    assert record["command"] == command[0]
    assert record["version"] and record["git_hash"]
    assert record["result"]["outcome"] == "ok"
    assert record["model"]["name"] == "wake_impact"
    check_png(out / "plot.png")
    if command[0] == "lyapunov":
        assert (out / "convergence.csv").read_text().splitlines()[0] == "t,lambda1,lambda2,lambda3,lambda4"
    if command[0] == "floquet":
        assert (out / "impacts.csv").read_text().splitlines()[0] == \
            "t,y,ydot_before,ydot_after,x,xdot,surface,normal_velocity,rebound_velocity,energy"
        orbit = (out / "orbit.csv").read_text().splitlines()
        assert orbit[0] == "t,y,ydot,x,xdot"
        t_last = float(orbit[-1].split(",")[0])
        assert abs(t_last - record["result"]["period"]) < 1e-9
        assert len(record["result"]["monodromy"]) == 4


BAD_INPUTS = [
    (["lyapunov", "--tdm", "fourth-order"], "--tdm"),
    (["lyapunov", "--r0", "0"], "--r0 = 0 is outside its valid range (0, 1)"),
    (["lyapunov", "--r0", "2"], "--r0 = 2 is outside its valid range (0, 1)"),
    (["lyapunov", "--t0", "-1"], "--t0"),
    (["lyapunov", "--impacts", "0"], "--impacts = 0 is outside its valid range >= 1"),
    (["lyapunov", "--time", "-5"], "--time = -5 is outside its valid range >= 0"),
    (["lyapunov", "--warmup", "-1"], "--warmup"),
    (["lyapunov", "--p0-time", "0"], "--p0-time = 0 is outside its valid range > 0"),
    (["lyapunov", "--max-time", "-1"], "--max-time = -1 is outside its valid range > 0"),
    (["lyapunov", "--record", "10"], "--record"),
    (["lyapunov", "--set", "r=1.5"], "r = 1.5"),
    (["floquet", "--impact-map", "nothing"], "--impact-map"),
    (["floquet", "--section", "impacts"], "section crossing"),
    (["lyapunov", "--section", "minima"], "--section"),
    (["floquet", "--tol", "0"], "--tol"),
    (["floquet", "--newton-tol", "-1"], "--newton-tol"),
    (["floquet", "--newton-iterations", "-2"], "--newton-iterations = -2 is outside its valid range [0, 1000]"),
    (["floquet", "--record", "1"], "--record"),
]


@pytest.mark.parametrize("args,needle", BAD_INPUTS)
def test_bad_input_exits_2_with_one_line_and_writes_nothing(vimpact, tmp_path, args, needle):
    out = tmp_path / "out"
    p = run(vimpact, *args, "--out", str(out))
    assert p.returncode == 2, (p.returncode, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1, p.stderr
    assert lines[0].startswith("vimpact: error: ")
    assert needle in lines[0]
    assert p.stdout == ""
    assert not out.exists()
    assert not [f for f in os.listdir(tmp_path) if f.startswith(".vimpact-staging")]


# ---- sweeps through the job loop (Figures 14-17) --------------------------------------------

def test_floquet_sweep_is_the_single_runs_and_thread_independent(vimpact):
    one = run(vimpact, "floquet", "--param", "Ur", "--range", "14:16:3", "--json", "--threads", "1")
    two = run(vimpact, "floquet", "--param", "Ur", "--range", "14:16:3", "--json", "--threads", "2")
    assert one.returncode == 0, one.stderr
    assert one.stdout == two.stdout
    j = json.loads(one.stdout)
    assert [p["label"] for p in j["points"]] == ["P1", "P2", "P2"]
    single = run_json(vimpact, "floquet", "--set", "Ur=16")
    assert j["points"][2]["multipliers"] == single["multipliers"]
    assert j["points"][2]["period"] == single["period"]


def test_lyapunov_sweep_is_the_single_runs(vimpact):
    j = run_json(vimpact, "lyapunov", "--param", "Ur", "--range", "16:19:2", "--impacts", "100", "--threads", "2")
    assert [p["value"] for p in j["points"]] == [16, 19]
    single = run_json(vimpact, "lyapunov", "--set", "Ur=19", "--impacts", "100")
    assert j["points"][1]["exponents"] == single["exponents"]


@pytest.mark.parametrize("command,files", [
    (["floquet", "--param", "sigma", "--range", "-0.150298:-0.14:3", "--set", "Ur=25"],
     ["labels.csv", "multipliers.csv", "points.csv"]),
    (["lyapunov", "--param", "Ur", "--range", "24:25:3", "--impacts", "100", "--record", "50"],
     ["exponents.csv", "points.csv"]),
])
def test_sweep_out_directory(vimpact, tmp_path, command, files):
    out = tmp_path / "sweep"
    p = run(vimpact, *command, "--out", str(out))
    assert p.returncode == 0, p.stderr
    for name in files:
        assert len((out / name).read_text().splitlines()) > 1
    record = json.loads((out / "run.json").read_text())
    assert record["result"]["values"] == 3
    check_png(out / "plot.png")
    assert not (tmp_path / "sweep.jobs").exists()
    if command[0] == "lyapunov":
        rows = (out / "points.csv").read_text().splitlines()
        assert rows[0] == "Ur,y,ydot,x,xdot"
        assert len(rows) == 1 + 3 * 50
        assert (out / "exponents.csv").read_text().splitlines()[0] == (
            "Ur,lambda1,lambda2,lambda3,lambda4,lle_standard_error,settled,impacts,time,misses,outcome,"
            "impacts_barrier,positive")
    else:
        assert (out / "labels.csv").read_text().splitlines()[0] == (
            "sigma,label,period,impacts,trivial_error,max_nontrivial_modulus,closure,outcome,impacts_barrier,stable")


SWEEP_BAD = [
    (["floquet", "--param", "nope", "--range", "1:2:3"], "nope"),
    (["floquet", "--param", "Ur", "--range", "1:2"], "--range"),
    (["lyapunov", "--param", "Ur"], "--range"),
    (["lyapunov", "--param", "Ur", "--range", "14:16:3", "--shard", "3/2"], "--shard"),
    (["floquet", "--param", "sigma", "--range", "0.5:0.6:2"], "beyond a surface"),
    (["lyapunov", "--param", "Ur", "--range", "14:16:3", "--section", "impacts"], "section crossing"),
]


@pytest.mark.parametrize("args,needle", SWEEP_BAD)
def test_bad_sweep_input_exits_2(vimpact, tmp_path, args, needle):
    out = tmp_path / "out"
    p = run(vimpact, *args, "--out", str(out))
    assert p.returncode == 2, (p.returncode, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("vimpact: error: ")
    assert needle in lines[0]
    assert not out.exists()


def test_lyapunov_options_come_from_the_librarys_declaration(vimpact):
    """Every option lyapunov_options declares is an option of the command, with its help,
    default and range (cli/declared_options.hpp), underscores written as hyphens."""
    p = run(vimpact, "lyapunov", "--help")
    assert p.returncode == 0, p.stderr
    text = " ".join(p.stdout.split())
    assert "--r0 FLOAT Size of the deviation vectors (default 1e-04; (0, 1))" in text
    assert "--warmup INT Intervals of t0 not counted while the vectors align (default 16; [0, 1e+06])" in text
    assert "(default saltation; one of saltation, second-order, trajectory)" in text
    for key in ("--t0", "--impacts", "--time", "--p0-time", "--max-time", "--no-divergence"):
        assert key in text, key
