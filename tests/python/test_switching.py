"""Switching surfaces from Python, against values from elsewhere: the forced oscillator with a
compliant stop (examples/models/compliant_stop.toml) integrated by scipy's DOP853, an
independent piecewise solver (an event at y = d, then the field of the side entered), and its
limit of infinite contact stiffness, the rigid stop with the same coefficient of restitution."""
import math
import os

import numpy as np
from scipy.integrate import solve_ivp

import vimpact

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
STOP = os.path.join(ROOT, "examples", "models", "compliant_stop.toml")
IC = [0.0, 0.0, 0.5]


def piecewise(p, x0, t_end, tol=1e-12):
    """The compliant stop from x0 to t_end by scipy, one smooth piece per side of y = d: the
    crossing times and a function giving the state at any time of [0, t_end]."""
    zeta, omega, F, d, kc, cc = (p[k] for k in ("zeta", "omega", "F", "d", "kc", "cc"))

    def field(on):
        return lambda t, x: [x[1], -2 * zeta * x[1] - x[0] + F * np.cos(x[2]) - on * (kc * (x[0] - d) + cc * x[1]),
                             omega]

    t, x, on = 0.0, np.array(x0, dtype=float), float(x0[0] >= d)
    crossings, pieces = [], []
    while t < t_end:
        # Leaving the contact (on) is a downward crossing, entering it an upward one; the event
        # direction keeps the piece from finding the crossing it starts on.
        event = lambda t, x: x[0] - d  # noqa: E731
        event.terminal, event.direction = True, -1.0 if on else 1.0
        sol = solve_ivp(field(on), (t, t_end), x, method="DOP853", rtol=tol, atol=tol, events=event,
                        dense_output=True)
        pieces.append((t, sol.t[-1], sol.sol))
        if sol.status != 1:
            break
        t, x, on = sol.t_events[0][0], sol.y_events[0][0], 1.0 - on
        crossings.append(t)

    def state(s):
        for a, b, f in pieces:
            if a <= s <= b:
                return f(s)
        raise ValueError(s)
    return np.array(crossings), state


def test_crossings_and_strobe_points_match_an_independent_piecewise_solver():
    """Section points (the strobe, once per forcing period) and every crossing time of the
    switch from the start, against scipy's DOP853 restarted at each crossing (both at
    tolerance 1e-12): to 1e-9 (they agree to about 1e-11)."""
    m = vimpact.Model(STOP)
    s = vimpact.simulate(m, IC, section="strobe", transient=0, record=20, rtol=1e-12, atol=1e-12)
    assert s.outcome == "ok" and len(s.section_t) == 20
    assert s.switches == ("contact",)
    crossings, state = piecewise(m.parameters, IC, s.section_t[-1] + 1.0)
    window = crossings[(crossings >= s.t_record_start) & (crossings <= s.t_record_end)]
    assert len(s.switching_t) == len(window) > 20
    assert np.max(np.abs(s.switching_t - window)) < 1e-9
    assert np.all(s.switching_surface == 0)
    assert np.max(np.abs(s.switching_pre[:, 0] - m.parameters["d"])) < 1e-9
    np.testing.assert_array_equal(s.switching_pre, s.switching_post)  # no reset: the state goes on
    expected = np.array([state(t) for t in s.section_t])
    assert np.max(np.abs(s.section[:, :2] - expected[:, :2])) < 1e-9


def test_floquet_multipliers_are_those_of_the_piecewise_solvers_strobe_map():
    """The multipliers of the P1 orbit against the eigenvalues of the strobe map's Jacobian by
    central differences of scipy's piecewise solution (h = 1e-5): to 1e-6."""
    m = vimpact.Model(STOP)
    f = vimpact.floquet(m, IC, section="strobe", record=20)
    assert f.status == "ok" and f.label == "P1"
    T = 2 * math.pi / m.parameters["omega"]
    assert abs(f.period - T) < 1e-9
    x0 = f.orbit_point

    def strobe(y, v):
        return piecewise(m.parameters, [y, v, x0[2]], T)[1](T)[:2]
    h = 1e-5
    J = np.column_stack([(strobe(*(x0[:2] + h * e)) - strobe(*(x0[:2] - h * e))) / (2 * h) for e in np.eye(2)])
    mu = np.sort_complex(np.linalg.eigvals(J))
    got = np.sort_complex(np.array([z for z in f.multipliers if abs(z - 1) > 1e-6]))
    assert len(got) == 2 and np.max(np.abs(got - mu)) < 1e-6, (got, mu)


def test_a_stiffening_stop_converges_to_the_rigid_stop_at_rate_one_over_root_kc():
    """A spring-dashpot contact of stiffness kc and damping ratio zc = cc/(2 sqrt(kc)) returns
    an unforced mass with r = exp(-pi zc/sqrt(1 - zc^2)) after pi/sqrt(kc (1 - zc^2)): as kc
    grows the forced oscillator's P1 orbit tends to that of the rigid stop with restitution r
    (the built-in forced_impact_oscillator, mirrored: its barrier is below, at sigma = -d,
    with the forcing -F), the distance falling as kc^(-1/2) (the contact's duration)."""
    r, d, F = 0.8, 1.0, 1.0
    zc = -math.log(r) / math.sqrt(math.pi ** 2 + math.log(r) ** 2)
    assert abs(math.exp(-math.pi * zc / math.sqrt(1 - zc * zc)) - r) < 1e-15
    rigid = vimpact.floquet(vimpact.Model("forced_impact_oscillator", sigma=-d, F=-F, r=r), IC, section="strobe",
                            record=20)
    assert rigid.status == "ok" and rigid.label == "P1"
    kcs = [1e3, 1e4, 1e5, 1e6]
    errors, multiplier_errors = [], []
    for kc in kcs:
        m = vimpact.Model(STOP, d=d, F=F, kc=kc, cc=2 * zc * math.sqrt(kc))
        f = vimpact.floquet(m, IC, section="strobe", record=20)
        assert f.status == "ok" and f.label == "P1", kc
        errors.append(np.max(np.abs(-f.orbit_point[:2] - rigid.orbit_point[:2])))
        multiplier_errors.append(np.max(np.abs(np.sort_complex(f.multipliers) - np.sort_complex(rigid.multipliers))))
    slopes = np.diff(np.log(errors)) / np.diff(np.log(kcs))
    assert np.all(np.abs(slopes + 0.5) < 0.05), slopes
    assert errors[-1] < 5e-3
    assert all(b < a for a, b in zip(multiplier_errors, multiplier_errors[1:])) and multiplier_errors[-1] < 0.02


def test_grazing_gives_each_switch_its_margin_and_grazing_value():
    """Grazing of the compliant stop's switch from Python, against the closed form of the
    switch-free (linear) orbit's amplitude X: d_graze = X, margin d - X."""
    m = vimpact.Model(STOP, d=3.0)
    p = m.parameters
    X = p["F"] / math.sqrt((1 - p["omega"] ** 2) ** 2 + (2 * p["zeta"] * p["omega"]) ** 2)
    g = vimpact.grazing(m, IC)
    assert g.converged and g.surfaces == () and set(g.by_switch) == {"contact"}
    w = g.by_switch["contact"]
    assert w["param"] == "d" and w["converged"]
    assert abs(w["value"] - X) < 1e-9 and abs(w["margin"] - (3.0 - X)) < 1e-9
    assert "switch contact: d = " in repr(g)


def free_amplitude(p, **changed):
    """The amplitude of the compliant stop's switch-free orbit, the linear forced response."""
    q = dict(p, **changed)
    return q["F"] / math.sqrt((1 - q["omega"] ** 2) ** 2 + (2 * q["zeta"] * q["omega"]) ** 2)


def test_a_sweep_gives_the_grazing_value_of_each_switch_at_every_point(cli, tmp_path):
    """A sweep over F with its grazing line (the default parameter: d, which moves the switch
    alone) gives at each point d_graze = X(F), the closed form; the command line writes it as
    labels.csv's d_graze_contact, and Sweep.load reads it back."""
    m = vimpact.Model(STOP, d=3.0)
    F = np.linspace(0.5, 1.5, 5)
    s = vimpact.sweep(m, "F", F, IC, grazing=True)
    expected = np.array([free_amplitude(m.parameters, F=f) for f in F])
    assert s.records["switch_grazing"].shape == (5, 1)
    assert np.max(np.abs(s.records["switch_grazing"][:, 0] - expected)) < 1e-9
    assert s.records["grazing"].shape == (5, 0)
    p = cli("sweep", "--model", STOP, "--param", "F", "--range", "0.5:1.5:5", "--set", "d=3", "--ic", "0,0,0.5",
            "--grazing", "--out", tmp_path / "s")
    assert p.returncode == 0, p.stderr
    with open(tmp_path / "s" / "labels.csv") as f:
        assert "d_graze_contact" in f.readline().strip().split(",")
    loaded = vimpact.Sweep.load(tmp_path / "s")
    assert np.array_equal(loaded.records["switch_grazing"], s.records["switch_grazing"])
    assert list(loaded.to_pandas().filter(like="switch_grazing").columns) == ["switch_grazing_contact"]


def test_a_maps_grazing_line_gives_each_switchs_grazing_value(cli, tmp_path):
    """A map over F x d with its grazing line (d moves the switch): d_graze = X(F) at each F,
    from Python and from the command line's grazing.csv read back by Map.load."""
    m = vimpact.Model(STOP)
    F, d = np.array([0.5, 1.0, 1.5]), np.array([2.0, 3.0])
    g = vimpact.map(m, ("F", F), ("d", d), IC, grazing=True)
    expected = np.array([free_amplitude(m.parameters, F=f) for f in F])
    assert g.grazing_param == "d" and g.grazing.shape == (3, 0) and g.switch_grazing.shape == (3, 1)
    assert np.array_equal(g.grazing_other, F)
    assert np.max(np.abs(g.switch_grazing[:, 0] - expected)) < 1e-9
    p = cli("map", "--model", STOP, "--x", "F:0.5:1.5:3", "--y", "d:2:3:2", "--ic", "0,0,0.5", "--grazing", "--out",
            tmp_path / "m")
    assert p.returncode == 0, p.stderr
    loaded = vimpact.Map.load(tmp_path / "m")
    assert np.array_equal(loaded.switch_grazing, g.switch_grazing) and loaded.grazing.shape == (3, 0)


def test_a_response_gives_each_switchs_grazing_value_and_margin():
    """The switch-free response over omega: the amplitude, the switch's grazing value X(omega)
    and margin d - X(omega), against the closed form."""
    m = vimpact.Model(STOP, d=3.0)
    omega = np.array([0.6, 0.8, 1.2, 1.5])
    r = vimpact.response(m, "omega", omega, IC)
    expected = np.array([free_amplitude(m.parameters, omega=w) for w in omega])
    assert r.records["switch_grazing"].shape == (1, 4, 1)
    assert np.max(np.abs(r.records["switch_grazing"][0, :, 0] - expected)) < 1e-8
    assert np.max(np.abs(r.records["switch_margin"][0, :, 0] - (3.0 - expected))) < 1e-8
    assert np.max(np.abs(r.amplitude[0] - expected)) < 1e-8


def test_the_clearance_of_a_compliant_stop_is_the_free_amplitude(cli_json):
    """Clearance design with a switch for a barrier: at each omega the smallest gap without a
    crossing is the free response's amplitude X(omega) (the stop's d at grazing, from the rest
    state y = 0). Below resonance the chart's cells beyond it never touch the stop (P0) while
    those inside do; above it (omega = 1.2) the stiffening stop has a contacting orbit beside
    the free one, which the start's transient can reach from just beyond the clearance, so
    there only the cells inside are checked. The command line says so of the switch."""
    m = vimpact.Model(STOP)
    omega = np.array([0.6, 0.8, 1.2])
    c = vimpact.clearance(m, param="omega", values=omega, ic=IC)
    assert c.switch == "contact" and c.surface is None and c.gap_param == "d"
    expected = np.array([free_amplitude(m.parameters, omega=w) for w in omega])
    assert np.max(np.abs(c.clearance - expected)) < 1e-8
    fractions = c.gap / c.clearance[:, None]
    assert np.all((c.label[:2] == "P0") == (fractions[:2] > 1.0 + 1e-9)), c.label
    assert np.all(c.label[fractions < 1.0 - 1e-9] != "P0"), c.label
    j = cli_json("clearance", "--model", STOP, "--param", "omega", "--range", "0.6:1.2:2", "--ic", "0,0,0.5")
    assert j["switch"] == "contact" and j["surface"] is None
    assert abs(j["clearance"][0][1] - free_amplitude(m.parameters, omega=0.6)) < 1e-8


def test_continuation_labels_the_grazing_of_a_switch():
    """The P1 branch of the compliant stop from d = 5 to 2 grazes the switch where d is the
    free orbit's amplitude X, and goes on."""
    m = vimpact.Model(STOP, d=5.0)
    p = m.parameters
    X = p["F"] / math.sqrt((1 - p["omega"] ** 2) ** 2 + (2 * p["zeta"] * p["omega"]) ** 2)
    c = vimpact.continuation(m, "d", (5.0, 2.0), IC)
    [g] = [b for b in c.bifurcations if b.type == "grazing"]
    assert g.switch == "contact" and g.surface is None and abs(g.param - X) < 1e-8
    assert (g.crossings_before, g.crossings_after) == (0, 2)
    assert "(switch contact)" in repr(g)


def test_the_curve_of_a_switchs_grazing_is_the_free_amplitude_line():
    """The switch's grazing followed in (d, F): the orbit touches y = d where d is the free
    response's amplitude X(F), a straight line through 0 in the plane; every point of the
    curve lies on it, and the curve spans the box of F it was given."""
    m = vimpact.Model(STOP, d=5.0)
    c = vimpact.continuation(m, "d", (5.0, 1.0), IC, param2="F", range2=(0.6, 1.6))
    [k] = [i for i, b in enumerate(c.bifurcations) if b.type == "grazing"]
    [curve] = [cv for cv in c.curves if cv.origin == k]
    assert curve.switch == "contact" and curve.surface is None and curve.failure == "ok"
    expected = np.array([free_amplitude(m.parameters, F=f) for f in curve.param2])
    assert len(curve.param) > 5 and np.max(np.abs(curve.param - expected)) < 1e-8
    assert curve.param2.min() < 0.65 and curve.param2.max() > 1.55


def test_the_steppable_systems_give_each_calls_crossings():
    """HybridSystem and SectionSystem list the crossings of switches of each call, as their
    impacts: the compliant stop's, on y = d with the state unchanged, together those of
    simulate from the same start."""
    m = vimpact.Model(STOP)
    d = m.parameters["d"]
    h = vimpact.HybridSystem(m, IC, rtol=1e-12, atol=1e-12)
    times = []
    while h.time < 60.0:
        assert h.step() == "ok"
        c = h.switchings
        assert c["switching_pre"].shape == (len(c["switching_t"]), 3)
        assert np.all(c["switching_surface"] == 0)
        np.testing.assert_array_equal(c["switching_pre"], c["switching_post"])
        assert np.all(np.abs(c["switching_pre"][:, 0] - d) < 1e-9)
        times.extend(c["switching_t"])
    crossings, _ = piecewise(m.parameters, IC, times[-1] + 1.0)
    assert len(times) == len(crossings[crossings <= times[-1] + 1e-6]) > 5
    assert np.max(np.abs(np.array(times) - crossings[:len(times)])) < 1e-9
    s = vimpact.SectionSystem(m, IC, section="strobe")
    assert s.step(3) == "ok"
    assert len(s.switchings["switching_t"]) >= 1  # the crossings since the previous strobe point
