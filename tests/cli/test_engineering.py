"""The engineering front end on the command line: `clearance` (the issue's contract, the
clearance against `grazing` at the matching Ur times D), `--si` on the run commands (inputs
converted and echoed in run.json, statistics in SI against the scales computed by hand),
impact statistics in every run's JSON and tables, the calibration warning, and bad physical
input refused with exit 2, naming the input, with nothing written."""
import csv
import json
import math
import os

import pytest

from conftest import TWO_SIDED_TOML, check_png
from test_cli import run, run_json

SI = "D=0.02,m=0.6,fn=12,zeta=0.002,rho=1000"
SHORT = ["--transient", "100", "--record", "40"]


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_the_clearance_contract(vimpact):
    j = run_json(vimpact, "clearance", "--si", SI, "--speeds", "3:6:7")
    speeds = [3.0, 3.5, 4.0, 4.5, 5.0, 5.5, 6.0]
    assert [u for u, _ in j["clearance"]] == speeds
    assert all(g is not None and 0 < g < 0.02 for _, g in j["clearance"])  # metres, below a diameter
    assert len(j["dimensionless"]) == 7
    for u, row in zip(speeds, j["dimensionless"]):
        assert {"U", "Ur", "mu", "xi"} <= set(row)
        assert row["U"] == u and math.isclose(row["Ur"], u / (12 * 0.02), rel_tol=1e-15)
        assert math.isclose(row["mu"], (0.6 + math.pi / 4 * 1000 * 0.02 ** 2) / (1000 * 0.02 ** 2), rel_tol=1e-15)
        assert row["xi"] == 0.002
    # The chart: a regime at every gap, and an aperiodic range per speed (null where none).
    assert sum(j["label_counts"].values()) == 7 * 13
    assert len(j["aperiodic"]) == 7


@pytest.mark.parametrize("u", [3.5, 5.0])
def test_the_clearance_is_the_grazing_value_at_the_matching_ur_times_d(vimpact, u):
    j = run_json(vimpact, "clearance", "--si", SI, "--speeds", f"{u}:{u}:1", "--fractions", "1.2:1.2:1", *SHORT)
    (speed, gap), = j["clearance"]
    row, = j["dimensionless"]
    g = run_json(vimpact, "grazing", "--set", f"Ur={u / 0.24!r}", "--set", f"mu={row['mu']!r}", "--set", "xi=0.002")
    assert speed == u
    assert gap == -g["sigma_graze"] * 0.02
    assert row["sigma_graze"] == g["sigma_graze"]
    # The same with --si on grazing: the smallest gap in metres.
    gs = run_json(vimpact, "grazing", "--si", f"{SI},U={u!r}")
    assert gs["surfaces"][0]["gap_si"] == gap


def test_clearance_writes_its_files_and_replays(vimpact, tmp_path):
    out, again = str(tmp_path / "c"), str(tmp_path / "again")
    args = ["clearance", "--si", SI, "--speeds", "4:5:2", "--fractions", "0.5:1.1:3", *SHORT]
    p = run(vimpact, *args, "--no-plot", "--out", out)
    assert p.returncode == 0, p.stderr
    record = json.load(open(os.path.join(out, "run.json")))
    assert set(record["files"]) == {"clearance.csv", "chart.csv", "run.json", "config.toml"}
    si = record["config"]["si"]
    assert si["inputs"]["D"] == 0.02 and si["inputs"]["nu"] == 1e-6
    assert set(si["parameters"]) == {"mu", "xi", "St"}
    chart = rows(os.path.join(out, "chart.csv"))
    assert len(chart) == 2 * 3
    for r in chart:
        assert math.isclose(float(r["gap_si"]), float(r["gap"]) * 0.02, rel_tol=1e-15)
        assert math.isclose(float(r["sigma"]), -float(r["gap"]), rel_tol=1e-12)
    cl = rows(os.path.join(out, "clearance.csv"))
    assert [float(r["U"]) for r in cl] == [4.0, 5.0]
    p = run(vimpact, "clearance", "--config", os.path.join(out, "config.toml"), "--no-plot", "--out", again, cwd="/")
    assert p.returncode == 0, p.stderr
    for name in ("clearance.csv", "chart.csv", "config.toml"):
        assert open(os.path.join(out, name), "rb").read() == open(os.path.join(again, name), "rb").read(), name


def test_simulate_in_si_echoes_the_conversion_and_converts_the_statistics(vimpact, tmp_path):
    out = str(tmp_path / "s")
    p = run(vimpact, "simulate", "--si", f"{SI},U=4,gap=0.001", "--json", "--no-plot", "--out", out, *SHORT)
    assert p.returncode == 0, p.stderr
    j = json.loads(p.stdout)
    cfg = json.load(open(os.path.join(out, "run.json")))["config"]
    assert cfg["parameters"]["sigma"] == pytest.approx(-0.05, abs=1e-15)
    assert cfg["parameters"]["Ur"] == pytest.approx(4 / 0.24, rel=1e-15)
    assert cfg["si"]["parameters"]["sigma"] == cfg["parameters"]["sigma"]
    assert cfg["si"]["values"]["U"] == pytest.approx(4.0, rel=1e-15)
    # By hand: one model unit of time 1/Omega_f, Omega_f = 2 pi St U / D = 80 pi /s; velocity
    # D Omega_f; energy per metre (m + m_f) (D Omega_f)^2.
    omega = 2 * math.pi * 0.2 * 4 / 0.02
    mass = 0.6 + math.pi / 4 * 1000 * 0.02 ** 2
    s, k = j["impact_statistics"], j["impact_statistics_si"]
    assert s["impacts_recorded"] > 0
    assert k["impact_rate"] == pytest.approx(s["impact_rate"] * omega, rel=1e-14)
    assert k["impact_velocity_max"] == pytest.approx(s["impact_velocity_max"] * 0.02 * omega, rel=1e-14)
    assert k["energy_per_impact"] == pytest.approx(s["energy_per_impact"] * mass * (0.02 * omega) ** 2, rel=1e-14)
    assert k["power"] == pytest.approx(s["power"] * mass * (0.02 * omega) ** 2 * omega, rel=1e-14)
    assert k["excursion"] == pytest.approx(s["excursion"] * 0.02, rel=1e-15)
    assert k["duration"] == pytest.approx(s["duration"] / omega, rel=1e-14)
    assert "in SI: impacts" in run(vimpact, "simulate", "--si", f"{SI},U=4,gap=0.001", *SHORT).stdout


def test_impacts_csv_has_each_impacts_velocity_and_energy(vimpact, tmp_path):
    out = str(tmp_path / "s")
    p = run(vimpact, "simulate", "--no-plot", "--out", out, *SHORT)
    assert p.returncode == 0, p.stderr
    imp = rows(os.path.join(out, "impacts.csv"))
    assert imp
    for r in imp:  # the paper's barrier: v = -ydot, u = r v, e = (1 - r^2) v^2 / 2
        v = -float(r["ydot_before"])
        assert float(r["normal_velocity"]) == pytest.approx(v, rel=1e-15)
        assert float(r["rebound_velocity"]) == pytest.approx(0.8 * v, rel=1e-14)
        assert float(r["energy"]) == pytest.approx(0.18 * v * v, rel=1e-14)
    s = json.load(open(os.path.join(out, "run.json")))["result"]["impact_statistics"]
    assert s["impacts_recorded"] == len(imp)
    assert s["impact_velocity_max"] == pytest.approx(max(float(r["normal_velocity"]) for r in imp), rel=1e-15)


def test_sweep_over_the_flow_speed_in_si(vimpact, tmp_path):
    out = str(tmp_path / "w")
    p = run(vimpact, "sweep", "--si", f"{SI},gap=0.001", "--param", "U", "--range", "3.5:4.5:3", "--no-plot",
            "--out", out, *SHORT)
    assert p.returncode == 0, p.stderr
    lab = rows(os.path.join(out, "labels.csv"))
    assert [float(r["U"]) for r in lab] == [3.5, 4.0, 4.5]
    for r in lab:
        assert float(r["Ur"]) == pytest.approx(float(r["U"]) / 0.24, rel=1e-15)
        omega = 2 * math.pi * 0.2 * float(r["U"]) / 0.02
        assert float(r["impact_rate_si"]) == pytest.approx(float(r["impact_rate"]) * omega, rel=1e-14)
    p = run(vimpact, "map", "--si", SI, "--x", "U:3.5:4.5:2", "--y", "gap:0.002:0.003:2", "--no-plot", "--out",
            str(tmp_path / "m"), *SHORT)
    assert p.returncode == 0, p.stderr
    cells = rows(os.path.join(str(tmp_path / "m"), "labels.csv"))
    assert [(float(c["U"]), float(c["gap"])) for c in cells] == [(3.5, 0.002), (4.5, 0.002), (3.5, 0.003),
                                                                  (4.5, 0.003)]
    assert all(float(c["sigma"]) == pytest.approx(-float(c["gap"]) / 0.02, rel=1e-14) for c in cells)


def test_the_calibration_warning(vimpact):
    p = run(vimpact, "clearance", "--si", "D=0.02,m=0.6,fn=12,zeta=0.002,rho=1.2", "--speeds", "4:4:1",
            "--fractions", "1.2:1.2:1", *SHORT)
    assert p.returncode == 0, p.stderr
    assert "vimpact: warning: the mass ratio m* = m / (rho pi D^2 / 4) = " in p.stderr
    p = run(vimpact, "simulate", "--si", f"{SI},U=10", *SHORT)
    assert p.returncode == 0 and "warning: Re = U D / nu = 200000" in p.stderr
    assert "warning" not in run(vimpact, "simulate", "--si", f"{SI},U=4", *SHORT).stderr


@pytest.mark.parametrize("args,needle", [
    (["clearance", "--si", "D=0.02,m=0.6,fn=12,zeta=0.002,rho=-1000", "--speeds", "3:6:7"], "rho (fluid density"),
    (["clearance", "--si", "D=0,m=0.6,fn=12,zeta=0.002,rho=1000", "--speeds", "3:6:7"], "D (diameter, m) must be"),
    (["clearance", "--si", SI, "--speeds", "3:6:7", "--gaps", "-0.001:0.004:6"], "--gaps: gap -0.001 m is below zero"),
    (["simulate", "--si", f"{SI},U=4,gap=-0.001"], "gap (distance to the neighbouring surface, m)"),
    (["clearance", "--si", "D=0.02,m", "--speeds", "3:6:7"], "--si expects KEY=VALUE"),
    (["clearance", "--si", "D=0.02,m=abc,fn=12,zeta=0.002,rho=1000", "--speeds", "3:6:7"], "--si m"),
    (["clearance", "--si", SI + ",Q=1", "--speeds", "3:6:7"], "unknown key 'Q'"),
    (["clearance", "--speeds", "3:6:7"], "--speeds needs a cylinder in --si"),
    (["clearance", "--si", SI, "--speeds", "0:6:7"], "U (flow speed, m/s) must be"),
    (["simulate", "--si", SI, "--set", "mu=2"], "--set mu=2 and --si both set mu"),
    (["simulate", "--model", "two_sided_impact_oscillator", "--si", SI], "model two_sided_impact_oscillator"),
    (["simulate", "--si", SI + ",mstar=2"], "m (structural mass per unit length, kg/m) and mstar (mass ratio"),
    (["simulate", "--si", "D=0.02,fn=12,zeta=0.002,rho=1000"], "--si: missing m (structural mass per unit length"),
    (["floquet", "--si", SI + ",k=5000"], "fn (natural frequency in still fluid, Hz) and k (stiffness per unit"),
    (["lyapunov", "--si", "D=0.02,m=0.6,zeta=0.002,rho=1000"], "--si: missing fn (natural frequency in still fluid"),
    (["basins", "--si", "D=0.02,m=0.6,k=0,zeta=0.002,rho=1000", "--x", "y:0:0.1:2", "--y", "ydot:0:0.1:2"],
     "k (stiffness per unit length, N/m^2) must be a finite number > 0"),
    (["simulate", "--si", "D=0.02,mstar=-1,fn=12,zeta=0.002,rho=1000"], "mstar (mass ratio m / (rho pi D^2 / 4)) must"),
    (["simulate", "--si", SI + ",CL0=-0.3"], "CL0 (lift coefficient of the fixed cylinder) must be a finite number >= 0"),
    (["simulate", "--si", SI + ",CL0=0.3", "--set", "CL0=0.2"], "--set CL0=0.2 and --si both set CL0"),
    (["response", "--si", SI, "--param", "U", "--range", "-1:2:3"], "U (flow speed, m/s) must be"),
    (["floquet", "--si", SI, "--param", "gap", "--range", "-0.001:0.001:3"], "gap (distance to the neighbouring"),
    (["continue", "--si", SI, "--param", "U", "--range", "0:4"], "U (flow speed, m/s) must be"),
    (["lyapunov", "--si", SI, "--param", "U", "--range", "3:4:2", "--model", "forced_impact_oscillator"],
     "model forced_impact_oscillator"),
    (["clearance", "--si", SI, "--speeds", "3:4:2", "--transient-time", "-1"],
     "--transient-time = -1 is outside its valid range >= 0"),
    (["clearance", "--si", SI, "--speeds", "3:4:2", "--tol", "0"], "--tol = 0 is outside its valid range > 0"),
])
def test_bad_physical_input_exits_2_naming_it_and_writes_nothing(vimpact, tmp_path, args, needle):
    out = tmp_path / "out"
    p = run(vimpact, *args, "--out", str(out))
    assert p.returncode == 2, p.stderr
    assert needle in p.stderr, p.stderr
    assert not out.exists() and not (tmp_path / "out.jobs").exists()


def test_statistics_in_every_sweep_and_map_table(vimpact, tmp_path):
    out = str(tmp_path / "w")
    p = run(vimpact, "sweep", "--param", "Ur", "--range", "16:17:2", "--no-plot", "--out", out, *SHORT)
    assert p.returncode == 0, p.stderr
    names = json.load(open(os.path.join(out, "run.json")))["result"]["statistics_columns"]
    assert names[:3] == ["impacts_recorded", "duration", "impact_rate"]
    lab = rows(os.path.join(out, "labels.csv"))
    assert all(set(names) <= set(r) for r in lab)
    # Each point's statistics are those of the same run alone.
    single = run_json(vimpact, "simulate", "--set", "Ur=17", *SHORT)["impact_statistics"]
    for k in names:
        assert float(lab[1][k]) == pytest.approx(single[k], rel=1e-15), k


def test_clearance_runs_through_the_job_loop(vimpact, tmp_path):
    """Threads and shards give the same files as one thread."""
    args = ["clearance", "--si", SI, "--speeds", "3.5:5:4", "--fractions", "0.5:1.2:2", *SHORT, "--no-plot"]
    whole, threads, sharded = tmp_path / "whole", tmp_path / "threads", tmp_path / "sharded"
    assert run(vimpact, *args, "--threads", "1", "--out", str(whole)).returncode == 0
    assert run(vimpact, *args, "--threads", "2", "--out", str(threads)).returncode == 0
    for i in range(2):
        p = run(vimpact, *args, "--threads", "1", "--shard", f"{i}/2", "--out", str(sharded))
        assert p.returncode == 0, p.stderr
        assert (sharded / "chart.csv").exists() == (i == 1)
    for d in (threads, sharded):
        for name in ("clearance.csv", "chart.csv"):
            assert (whole / name).read_bytes() == (d / name).read_bytes(), (d, name)
    assert not os.path.exists(str(sharded) + ".jobs")


# ---------------------------------------------------------------- the alternatives to m and fn, CL0

# m* = 3 on the 20 mm tube in water: m = 0.3 pi kg/m, 0.4 pi kg/m with the added mass; the
# stiffness k = 160 pi^3 N/m^2 = 0.4 pi (2 pi 10 Hz)^2 gives fn = 10 Hz.
STIFF = f"D=0.02,mstar=3,k={160 * math.pi ** 3!r},zeta=0.002,rho=1000"


def test_mass_ratio_and_stiffness_give_the_model_by_hand(vimpact):
    j = run_json(vimpact, "units", "--si", STIFF, "--speeds", "2:4:2")
    for row, u in zip(j["dimensionless"], (2.0, 4.0)):
        assert row["Ur"] == pytest.approx(u / (10 * 0.02), rel=1e-13)
        assert row["mu"] == pytest.approx(math.pi, rel=1e-14)  # (m* + CM) pi / 4
        assert row["mass_ratio"] == pytest.approx(3.0, rel=1e-15)
    assert j["si"]["mstar"] == 3 and j["si"]["m"] == pytest.approx(0.3 * math.pi, rel=1e-15)
    assert j["si"]["fn"] == pytest.approx(10.0, rel=1e-14)
    # The same model as with m and fn given.
    same = run_json(vimpact, "units", "--si", f"D=0.02,m={0.3 * math.pi!r},fn=10,zeta=0.002,rho=1000", "--speeds",
                    "2:4:2")
    for a, b in zip(j["dimensionless"], same["dimensionless"]):
        assert a["Ur"] == pytest.approx(b["Ur"], rel=1e-13) and a["mu"] == pytest.approx(b["mu"], rel=1e-15)


def test_the_lift_coefficient_is_set_and_echoed(vimpact, tmp_path):
    paper_cl0 = 0.05 * 16 * math.pi ** 2 * 0.2 ** 2  # the paper preset's back-fitted value
    for extra, preset, expected in (("", [], paper_cl0), ("", ["--preset", "facchinetti"], 0.3),
                                    (",CL0=0.25", ["--preset", "facchinetti"], 0.25)):
        out = tmp_path / f"cl0{len(extra)}{len(preset)}"
        p = run(vimpact, "simulate", "--si", f"{SI},U=4{extra}", *preset, *SHORT, "--no-plot", "--out", str(out))
        assert p.returncode == 0, p.stderr
        cfg = json.load(open(out / "run.json"))["config"]
        assert cfg["parameters"]["CL0"] == pytest.approx(expected, rel=1e-15)
        assert cfg["si"]["values"]["CL0"] == cfg["parameters"]["CL0"]
        assert ("CL0" in cfg["si"]["inputs"]) == bool(extra)
        assert ("CL0" in cfg["si"]["parameters"]) == bool(extra)
    assert "--set CL0=0.3" in run(vimpact, "units", "--si", SI + ",CL0=0.3", "--speeds", "4:4:1").stdout


# ---------------------------------------------------------------- the run's tables in SI

def test_simulate_writes_its_tables_also_in_si(vimpact, tmp_path):
    out = tmp_path / "s"
    p = run(vimpact, "simulate", "--si", f"{SI},U=4,gap=0.001", *SHORT, "--out", str(out))
    assert p.returncode == 0, p.stderr
    omega = 2 * math.pi * 0.2 * 4 / 0.02  # Omega_f = 80 pi rad/s: one model time unit is 1/Omega_f s
    mass = 0.6 + math.pi / 4 * 1000 * 0.02 ** 2
    ts = rows(out / "timeseries.csv")
    assert list(ts[0])[:5] == ["t", "y", "ydot", "x", "xdot"]  # the model's columns first, unchanged
    for r in ts:
        assert float(r["t_si"]) == pytest.approx(float(r["t"]) / omega, rel=1e-15)
        assert float(r["y_si"]) == pytest.approx(float(r["y"]) * 0.02, rel=1e-15, abs=1e-18)
        assert float(r["ydot_si"]) == pytest.approx(float(r["ydot"]) * 0.02 * omega, rel=1e-14, abs=1e-15)
        assert "x_si" not in r and "xdot_si" not in r  # the wake variable has no SI value
    # Another way to the velocity: the slope of the SI displacement over the SI time.
    t = [float(r["t_si"]) for r in ts]
    y = [float(r["y_si"]) for r in ts]
    v = [float(r["ydot_si"]) for r in ts]
    vmax = max(abs(x) for x in v)
    for i in range(1, len(t) - 1):
        if float(ts[i - 1]["y"]) > -0.05 + 1e-9 and float(ts[i + 1]["y"]) > -0.05 + 1e-9:  # no impact between
            slope = (y[i + 1] - y[i - 1]) / (t[i + 1] - t[i - 1])
            assert slope == pytest.approx(v[i], abs=2e-3 * vmax)
    imp = rows(out / "impacts.csv")
    assert imp
    for r in imp:  # the barrier 1 mm below the rest position; e = (1 - r^2) M v^2 / 2 per metre
        assert float(r["y_si"]) == pytest.approx(-0.001, rel=1e-13)
        v = -float(r["ydot_before_si"])
        assert float(r["normal_velocity_si"]) == pytest.approx(v, rel=1e-15)
        assert float(r["rebound_velocity_si"]) == pytest.approx(0.8 * v, rel=1e-14)
        assert float(r["energy_si"]) == pytest.approx(0.18 * mass * v * v, rel=1e-13)
    sec = rows(out / "sections.csv")
    assert all(float(r["ydot_si"]) == 0 for r in sec)  # the maxima of y
    si = json.load(open(out / "run.json"))["result"]["si"]
    assert si["columns"]["states"] == {"t_si": "s", "y_si": "m", "ydot_si": "m/s"}
    assert si["columns"]["impacts"]["energy_si"] == "J/m"
    assert json.load(open(out / "run.json"))["plot_options"] == {"units": "si"}
    check_png(out / "plot.png")


def test_any_models_tables_in_si(vimpact, tmp_path):
    """The two stops (a model file): x in m, v in m/s by the units given, the phase left out."""
    out = tmp_path / "two"
    p = run(vimpact, "simulate", "--model", TWO_SIDED_TOML, "--si", "length=0.001,time=0.5,gap=0.002", *SHORT,
            "--no-plot", "--out", str(out))
    assert p.returncode == 0, p.stderr
    for r in rows(out / "timeseries.csv"):
        assert float(r["x_si"]) == pytest.approx(float(r["x"]) * 0.001, rel=1e-15, abs=1e-19)
        assert float(r["v_si"]) == pytest.approx(float(r["v"]) * 0.002, rel=1e-15, abs=1e-19)
        assert "phi_si" not in r
    assert all(abs(float(r["x_si"])) == pytest.approx(0.002, rel=1e-12) for r in rows(out / "impacts.csv"))


# ---------------------------------------------------------------- --si on the other commands

def test_response_over_the_flow_speed_in_si(vimpact, tmp_path):
    j = run_json(vimpact, "response", "--si", SI, "--param", "U", "--range", "3:6:4")
    assert j["param"] == "Ur" and j["si_param"] == "U"
    curve, = j["curves"]
    assert curve["si_values"] == [3.0, 4.0, 5.0, 6.0]
    for i, u in enumerate(curve["si_values"]):
        assert curve["values"][i] == pytest.approx(u / 0.24, rel=1e-15)
        # Hz of the model's angular frequency: times Omega_f / (2 pi) = St U / D.
        assert curve["frequency_si"][i] == pytest.approx(curve["frequency"][i] * 0.2 * u / 0.02, rel=1e-14)
        assert curve["amplitude_si"][i] == pytest.approx(curve["amplitude"][i] * 0.02, rel=1e-15)
        assert curve["clearance_si"][i] == pytest.approx(-curve["sigma_graze"][i] * 0.02, rel=1e-14)
    # The clearance at 4 m/s is what `grazing --si` finds there.
    g = run_json(vimpact, "grazing", "--si", f"{SI},U=4")
    assert curve["clearance_si"][1] == pytest.approx(g["surfaces"][0]["gap_si"], rel=1e-12)
    out = tmp_path / "r"
    p = run(vimpact, "response", "--si", SI, "--param", "U", "--range", "3:6:4", "--no-plot", "--out", str(out))
    assert p.returncode == 0, p.stderr
    table = rows(out / "response.csv")
    assert [float(r["U"]) for r in table] == [3.0, 4.0, 5.0, 6.0]
    assert [float(r["frequency_si"]) for r in table] == pytest.approx(curve["frequency_si"], rel=1e-15)
    assert [float(r["y_max_si"]) for r in table] == pytest.approx([float(r["y_max"]) * 0.02 for r in table], rel=1e-15)


def test_floquet_and_lyapunov_in_si(vimpact, tmp_path):
    si = f"{SI},gap=0.001"
    f = run_json(vimpact, "floquet", "--si", f"{si},U=4", *SHORT)
    omega = 2 * math.pi * 0.2 * 4 / 0.02
    assert f["period_si"] == pytest.approx(f["period"] / omega, rel=1e-14)
    assert f["si"]["values"]["U"] == pytest.approx(4.0, rel=1e-15)
    # The impacts per second of the periodic orbit are those `simulate` counts at the same speed.
    s = run_json(vimpact, "simulate", "--si", f"{si},U=4", "--transient", "100", "--record", "400")
    rate = f["impacts_per_period"] / f["period_si"]
    assert s["impact_statistics_si"]["impact_rate"] == pytest.approx(rate, rel=2e-2)
    l = run_json(vimpact, "lyapunov", "--si", f"{si},U=4", "--transient", "100", "--impacts", "100")
    assert l["lle_si"] == pytest.approx(l["lle"] * omega, rel=1e-14)
    assert l["exponents_si"] == pytest.approx([e * omega for e in l["exponents"]], rel=1e-14)
    assert l["impact_rate_si"] == pytest.approx(l["impact_rate"] * omega, rel=1e-14)
    # Sweeps over the flow speed: U beside Ur, the period and the exponents in SI.
    out = tmp_path / "f"
    p = run(vimpact, "floquet", "--si", si, "--param", "U", "--range", "3.5:4.5:3", *SHORT, "--no-plot", "--out",
            str(out))
    assert p.returncode == 0, p.stderr
    for r in rows(out / "labels.csv"):
        u = float(r["U"])
        assert float(r["Ur"]) == pytest.approx(u / 0.24, rel=1e-15)
        assert float(r["period_si"]) == pytest.approx(float(r["period"]) * 0.02 / (2 * math.pi * 0.2 * u), rel=1e-14)
    out = tmp_path / "l"
    p = run(vimpact, "lyapunov", "--si", si, "--param", "U", "--range", "3.5:4.5:2", "--transient", "100",
            "--impacts", "100", "--record", "20", "--no-plot", "--out", str(out))
    assert p.returncode == 0, p.stderr
    for r in rows(out / "exponents.csv"):
        u = float(r["U"])
        assert float(r["lambda1_si"]) == pytest.approx(float(r["lambda1"]) * 2 * math.pi * 0.2 * u / 0.02, rel=1e-14)


def test_basins_in_si(vimpact, tmp_path):
    out = tmp_path / "b"
    p = run(vimpact, "basins", "--si", f"{SI},U=4,gap=0.001", "--x", "y:-0.04:0.2:3", "--y", "ydot:-0.1:0.1:2",
            "--transient", "50", "--record", "20", "--no-plot", "--out", str(out))
    assert p.returncode == 0, p.stderr
    omega = 2 * math.pi * 0.2 * 4 / 0.02
    cells = rows(out / "cells.csv")
    assert len(cells) == 6
    for c in cells:
        assert float(c["y_si"]) == pytest.approx(float(c["y"]) * 0.02, rel=1e-15)
        assert float(c["ydot_si"]) == pytest.approx(float(c["ydot"]) * 0.02 * omega, rel=1e-15)
    cfg = json.load(open(out / "run.json"))["config"]
    assert cfg["parameters"]["sigma"] == pytest.approx(-0.05, rel=1e-15)


def test_continuation_over_the_flow_speed_in_si(vimpact, tmp_path):
    out = tmp_path / "c"
    p = run(vimpact, "continue", "--si", f"{SI},gap=0.001", "--param", "U", "--range", "4:4.4", *SHORT, "--out",
            str(out), "--no-plot")
    assert p.returncode == 0, p.stderr
    assert "(U = 4 m/s) towards" in p.stdout
    record = json.load(open(out / "run.json"))
    assert record["result"]["range"] == pytest.approx([4 / 0.24, 4.4 / 0.24], rel=1e-15)
    branches = rows(out / "branches.csv")
    assert branches
    for r in branches:  # U = Ur fn D
        assert float(r["U"]) == pytest.approx(float(r["Ur"]) * 12 * 0.02, rel=1e-14)
    for branch in record["result"]["branches"]:
        for pt in branch:
            assert pt["param_si"] == pytest.approx(pt["param"] * 0.24, rel=1e-14)



def test_sweep_and_continuation_tables_have_their_states_in_si(vimpact, tmp_path):
    # Each point at its own flow speed: y_si = y D, ydot_si = ydot D Omega_f(U) with
    # Omega_f = 2 pi St U / D, so the velocities of two speeds scale differently.
    out = tmp_path / "w"
    p = run(vimpact, "sweep", "--si", f"{SI},gap=0.001", "--param", "U", "--range", "3.5:4.5:3", "--section",
            "impacts", "--no-plot", "--out", str(out), *SHORT)
    assert p.returncode == 0, p.stderr
    pts = rows(out / "points.csv")
    assert {float(r["U"]) for r in pts} == {3.5, 4.0, 4.5}
    moving = 0
    for r in pts:
        u = float(r["U"])
        assert float(r["Ur"]) == pytest.approx(u / 0.24, rel=1e-15)
        assert float(r["y_si"]) == pytest.approx(float(r["y"]) * 0.02, rel=1e-15, abs=1e-18)
        assert float(r["ydot_si"]) == pytest.approx(float(r["ydot"]) * 2 * math.pi * 0.2 * u, rel=1e-14, abs=1e-15)
        moving += float(r["ydot"]) != 0
    assert moving > 0 and "x_si" not in pts[0]
    out = tmp_path / "c"
    p = run(vimpact, "continue", "--si", f"{SI},gap=0.003", "--param", "U", "--range", "3.4:3.6", "--diagram", "3",
            "--no-plot", "--out", str(out), *SHORT)
    assert p.returncode == 0, p.stderr
    for name in ("branches.csv", "sections.csv", "diagram.csv"):
        table = rows(out / name)
        assert table, name
        for r in table:
            assert float(r["U"]) == pytest.approx(float(r["Ur"]) * 0.24, rel=1e-14), name
            assert float(r["y_si"]) == pytest.approx(float(r["y"]) * 0.02, rel=1e-15, abs=1e-18), name
    # Any model with the SI value of its units: a velocity is length / time.
    out = tmp_path / "f"
    p = run(vimpact, "continue", "--model", "forced_impact_oscillator", "--section", "strobe", "--set", "omega=1.5",
            "--set", "sigma=0", "--param", "sigma", "--range", "0:-0.2", "--si", "length=0.01,time=0.1", "--no-plot",
            "--out", str(out))
    assert p.returncode == 0, p.stderr
    sec = rows(out / "sections.csv")
    assert sec and all(float(r["ydot_si"]) == pytest.approx(float(r["ydot"]) * 0.1, rel=1e-15) for r in sec)
    assert "theta_si" not in sec[0]
