"""vimpact continue: the contract of --json, the files of --out, and bad input (exit 2,
nothing written). The numbers themselves are checked against closed forms and other analyses
by the unit tests (tests/continuation_test.cpp); here the program must give the library's."""
import csv
import json
import os
import subprocess

import numpy as np
import pytest

from conftest import TWO_SIDED_TOML, check_png

SHORT = ["--transient", "200", "--record", "20"]


def run(vimpact, args):
    return subprocess.run([vimpact, *args], capture_output=True, text=True)


def continue_json(vimpact, args):
    p = run(vimpact, ["continue", *args, "--json"])
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


def test_json_keys_of_the_contract(vimpact):
    j = continue_json(vimpact, ["--param", "Ur", "--range", "14.5:15.3", "--switch", "1"])
    assert j["command"] == "continue" and j["param"] == "Ur" and j["status"] == "ok" and j["start_label"] == "P1"
    assert len(j["branches"]) == 2 and len(j["branch_info"]) == 2
    for branch, info in zip(j["branches"], j["branch_info"]):
        assert len(branch) == info["points"] >= 5
        for p in branch:
            assert set(p) >= {"param", "stable", "multipliers", "period", "impacts", "state"}
            assert len(p["state"]) == 4 and len(p["multipliers"]) == 4 and len(p["multipliers"][0]) == 2
            assert len(p["section_points"]) == info["returns"]
            assert p["closure"] <= 1e-10
            # Stable means every nontrivial multiplier inside the unit circle.
            assert p["stable"] == all(abs(complex(*m)) < 1 for m in p["multipliers"][1:]) or \
                abs(max(abs(complex(*m)) for m in p["multipliers"][1:]) - 1) < 1e-9
    types = [b["type"] for b in j["bifurcations"]]
    assert types == ["period_doubling", "grazing"]
    pd = j["bifurcations"][0]
    assert set(pd) >= {"type", "param", "branch", "state"}
    assert abs(pd["param"] - 15.0181581267) < 1e-8
    # Its nontrivial multipliers: one at -1.
    assert min(abs(complex(*m) + 1) for m in pd["multipliers"][1:]) < 1e-6
    # The switched branch: twice the returns, starting at the period doubling.
    for info, branch in zip(j["branch_info"][1:], j["branches"][1:]):
        assert info["returns"] == 2 and info["parent"] == 0 and info["origin"] == 0
        assert branch[0]["param"] == pd["param"]
    g = j["bifurcations"][1]
    assert g["surface"] == "barrier" and g["sequence_before"] == ["barrier", "barrier"]
    assert g["sequence_after"] == ["barrier"]


def test_a_start_from_a_point_with_its_period(vimpact):
    # The unstable P2 orbit near the period doubling, from a point of it on the section.
    j = continue_json(vimpact, ["--param", "Ur", "--range", "14.5:15.3", "--switch", "1"])
    p = next(q for q in j["branches"][1] if not q["stable"] and q["param"] < 15.0)
    ic = ",".join(repr(v) for v in p["state"])
    k = continue_json(vimpact, ["--param", "Ur", "--range", f"{p['param']!r}:15.3", "--period", "2", "--ic", ic])
    first = k["branches"][0][0]
    assert k["start_label"] == "" and not first["stable"]
    assert max(abs(a - b) for a, b in zip(first["state"], p["state"])) < 1e-8


def test_two_parameter_curves_and_out_files(vimpact, tmp_path):
    out = str(tmp_path / "c")
    p = run(vimpact, ["continue", "--param", "Ur", "--range", "14.3:15.1", "--param2", "sigma", "--range2",
                      "-0.16:-0.14", "--map", "3,3", *SHORT, "--out", out])
    assert p.returncode == 0, p.stderr
    for f in ("branches.csv", "sections.csv", "bifurcations.csv", "curves.csv", "map.csv", "run.json",
              "config.toml", "plot.png"):
        assert os.path.exists(os.path.join(out, f)), f
    check_png(os.path.join(out, "plot.png"))
    res = json.load(open(os.path.join(out, "run.json")))["result"]
    assert res["param2"] == "sigma" and len(res["curves"]) == 1
    curve = res["curves"][0]
    assert curve["type"] == "period_doubling"
    for q in curve["points"]:
        assert -0.16 <= q["param2"] <= -0.14 and 14.3 <= q["param"] <= 15.1
        assert min(abs(complex(*m) + 1) for m in q["multipliers"][1:]) < 1e-6
    rows = list(csv.DictReader(open(os.path.join(out, "curves.csv"))))
    assert len(rows) == len(curve["points"]) and float(rows[0]["sigma"]) == curve["points"][0]["param2"]
    rows = list(csv.DictReader(open(os.path.join(out, "map.csv"))))
    assert len(rows) == 9 and {"Ur", "sigma", "label"} <= set(rows[0])


def test_a_model_file(vimpact):
    j = continue_json(vimpact, ["--model", TWO_SIDED_TOML, "--section", "strobe", "--param", "w", "--range",
                                "1.2:1.0", *SHORT])
    assert j["status"] == "ok" and len(j["branches"][0]) >= 5
    assert j["branches"][0][0]["impacts_by_surface"] == {"right": 1, "left": 1}


# The two-sided oscillator's symmetric P1 orbit in closed form (numpy, nothing of vimpact): it
# hits the right stop x = d at time t0 with velocity v > 0 and, half a forcing period later,
# the left stop with -v. Between impacts x = x_p + e with the periodic response x_p (odd under a
# half-period shift) and e propagated by exp(A T/2), A = [[0, 1], [-1, -2 zeta]], so the two
# conditions at t0 + T/2 are linear in (d, v) for each phase w t0.
ZETA, R = 0.05, 0.8


def _response(w, t):
    D = (1 - w * w) ** 2 + (2 * ZETA * w) ** 2
    A, B = (1 - w * w) / D, 2 * ZETA * w / D
    return A * np.cos(w * t) + B * np.sin(w * t), w * (-A * np.sin(w * t) + B * np.cos(w * t))


def _free(e0, e1, s):
    wd = np.sqrt(1 - ZETA ** 2)
    k, c, sn = np.exp(-ZETA * s), np.cos(wd * s), np.sin(wd * s)
    return k * (e0 * c + (e1 + ZETA * e0) / wd * sn), k * (e1 * c - (e0 + ZETA * e1) / wd * sn)


def _symmetric(w, phi):
    """The half clearance d and impact velocity v of the symmetric orbit with its right-stop
    impact at phase phi."""
    tau = np.pi / w
    E00, E10 = _free(1.0, 0.0, tau)
    E01, E11 = _free(0.0, 1.0, tau)
    xp, vp = _response(w, phi / w)
    M = np.array([[1 + E00, -R * E01], [E10, 1 - R * E11]])
    b = np.array([(1 + E00) * xp + E01 * vp, (1 + E11) * vp + E10 * xp])
    return np.linalg.solve(M, b)


def _bisect(f, lo, hi, n=80):
    flo = f(lo) > 0
    for _ in range(n):
        mid = 0.5 * (lo + hi)
        if (f(mid) > 0) == flo:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _phase_near(w, ref):
    grid = np.linspace(ref - 0.1, ref + 0.1, 201)
    f = [_symmetric(w, p)[0] - 1.0 for p in grid]
    roots = [_bisect(lambda p: _symmetric(w, p)[0] - 1.0, grid[k], grid[k + 1])
             for k in range(200) if (f[k] > 0) != (f[k + 1] > 0)]
    return min(roots, key=lambda p: abs(p - ref))


def _largest_interior_max(w, phi):
    d, v = _symmetric(w, phi)
    t0 = phi / w
    t = np.linspace(0, np.pi / w, 4001)[1:-1]
    xp0, vp0 = _response(w, t0)

    def state(s):
        e = _free(d - xp0, -R * v - vp0, s)
        xp, vp = _response(w, t0 + s)
        return xp + e[0], vp + e[1]

    vel = state(t)[1]
    tops = [_bisect(lambda s: state(s)[1], t[k], t[k + 1]) for k in range(len(t) - 1) if vel[k] > 0 >= vel[k + 1]]
    return max(state(s)[0] for s in tops) if tops else -np.inf


def closed_form_grazing_w():
    phi = _phase_near(1.0, 0.0754)
    for w in np.arange(0.995, 0.5299, -0.005):
        phi = _phase_near(w, phi)
    return _bisect(lambda w: _largest_interior_max(w, _phase_near(w, phi)) - 1.0, 0.53, 0.52, n=45)


def test_the_branch_goes_on_where_the_strobe_meets_an_impact_to_the_double_grazing(vimpact):
    # Down from w = 1 the strobe point meets the right-stop impact at w = 0.789: the branch
    # goes on past it, to where the flight's interior maximum reaches the stop (and, by
    # symmetry, its minimum the other stop), located to the closed form's w.
    w_graze = closed_form_grazing_w()
    j = continue_json(vimpact, ["--model", "two_sided_impact_oscillator", "--section", "strobe", "--param", "w",
                                "--range", "1:0.4"])
    info, branch = j["branch_info"][0], j["branches"][0]
    assert min(p["param"] for p in branch) < 0.6
    assert any(abs(p["state"][0] - 1.0) < 1e-9 and 0.78 < p["param"] < 0.8 for p in branch)
    grazings = [b for b in j["bifurcations"] if b["type"] == "grazing"]
    assert sorted(b["surface"] for b in grazings) == ["left", "right"]
    for b in grazings:
        assert abs(b["param"] - w_graze) < 1e-9, (b["param"], w_graze)
        assert b["located"]
    assert info["end"] == "grazing"
    assert info["end_reason"] == "grazing at w = " + repr(branch[-1]["param"])
    p = run(vimpact, ["continue", "--model", "two_sided_impact_oscillator", "--section", "strobe", "--param", "w",
                      "--range", "1:0.4"])
    assert p.returncode == 0 and "ends: grazing at w = " + repr(branch[-1]["param"]) in p.stdout


def test_end_reasons_say_what_happened_and_where(vimpact):
    base = ["--model", "two_sided_impact_oscillator", "--section", "strobe", "--param", "w", *SHORT]
    j = continue_json(vimpact, [*base, "--range", "1:0.9"])
    assert (j["branch_info"][0]["end"], j["branch_info"][0]["end_reason"]) == ("range", "range")
    j = continue_json(vimpact, [*base, "--range", "1:0.9", "--max-points", "3"])
    last = j["branches"][0][-1]["param"]
    assert (j["branch_info"][0]["end"], j["branch_info"][0]["end_reason"]) == ("point_limit", f"max points at w = {last!r}")
    # Steps that the corrector cannot close and may not shorten.
    j = continue_json(vimpact, [*base, "--range", "1:0.4", "--newton-iterations", "1", "--ds", "0.05",
                                "--ds-min", "0.05", "--ds-max", "0.05"])
    assert (j["branch_info"][0]["end"], j["branch_info"][0]["end_reason"]) == ("step_too_small", "step too small at w = 1")


@pytest.mark.parametrize("args, message", [
    (["--param", "Uq", "--range", "12:13"], "--param"),
    (["--param", "Ur", "--range", "12"], "--range"),
    (["--param", "Ur", "--range", "12:12"], "--range"),
    (["--param", "Ur", "--range", "12:x"], "--range"),
    (["--param", "Ur", "--range", "-1:13"], "Ur"),
    (["--param", "Ur", "--range", "12:13", "--period", "-1"], "--period = -1 is outside its valid range [0, 1000]"),
    (["--param", "Ur", "--range", "12:13", "--param2", "sigma"], "--range2"),
    (["--param", "Ur", "--range", "12:13", "--param2", "sigma", "--range2", "0:0.1"], "outside its range"),
    (["--param", "Ur", "--range", "12:13", "--param2", "Ur", "--range2", "11:14"], "differ"),
    (["--param", "Ur", "--range", "12:13", "--map", "3,3"], "--param2"),
    (["--param", "Ur", "--range", "12:13", "--switch", "9"], "--switch = 9 is outside its valid range [0, 8]"),
    (["--param", "Ur", "--range", "12:13", "--closure-tol", "0"], "--closure-tol = 0 is outside its valid range (0, 1e-04]"),
    (["--param", "Ur", "--range", "12:13", "--max-points", "1"], "--max-points = 1 is outside its valid range [2, 1e+06]"),
    (["--param", "Ur", "--range", "12:13", "--ds", "-1"], "--ds = -1 is outside its valid range >= 0"),
    (["--param", "Ur", "--range", "12:13", "--section", "impacts"], "section crossing"),
    (["--param", "Ur", "--range", "12:13", "--param2", "sigma", "--range2", "-0.2:0", "--curves", "hopf"],
     "--curves"),
])
def test_bad_input_exits_2_and_writes_nothing(vimpact, tmp_path, args, message):
    out = tmp_path / "never"
    p = run(vimpact, ["continue", *args, "--out", str(out)])
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert message in p.stderr and p.stderr.startswith("vimpact: error:")
    assert not out.exists()


SI = "D=0.02,m=0.6,fn=12,zeta=0.002,rho=1000"


@pytest.mark.parametrize("args, needle", [
    (["--param", "Ur", "--range", "14.5:15", "--curves", "fold"],
     "--curves chooses the curves of --param2: give --param2 Q and --range2 c:d with it"),
    (["--param", "Ur", "--range", "14.5:15", "--diagram", "5"],
     "--diagram N draws the brute-force diagram in the picture of --out DIR: give --out"),
])
def test_options_that_would_be_ignored_are_refused(vimpact, args, needle):
    p = run(vimpact, ["continue", *args, *SHORT])
    assert p.returncode == 2, p.stderr
    assert p.stderr.strip() == "vimpact: error: " + needle
    assert p.stdout == ""


def test_a_second_range_in_si_is_reported_in_si(vimpact):
    # The user gave metres: the range and the run's gap are said in metres, not in sigma.
    p = run(vimpact, ["continue", "--si", SI + ",gap=0.003", "--param", "Ur", "--range", "14.5:15", "--param2", "gap",
                      "--range2", "0.001:0.002", *SHORT])
    assert p.returncode == 2, p.stderr
    line = p.stderr.strip()
    assert line.startswith("vimpact: error: --range2 0.001:0.002 (gap, m) does not hold the run's gap = 0.003"), line
    assert " m (set by --si or the model's default), where the curves start" in line, line
    assert "sigma" not in line and "-0.15" not in line, line
