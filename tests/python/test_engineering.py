"""The engineering front end from Python: PhysicalUnits both ways (hand-computed values and
round trips), impact statistics on results (against each impact's own numbers, and the same
as the command line's), vimpact.clearance against vimpact.grazing at the matching Ur times D,
and the pictures (the impact-velocity histogram, the design chart)."""
import math

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

import vimpact  # noqa: E402
import vimpact.plot as plot  # noqa: E402
from test_plot_quality import check_layout  # noqa: E402

TUBE = dict(D=0.02, m=0.6, fn=12.0, zeta=0.002, rho=1000.0)
SHORT = dict(transient=100, record=40)


def test_si_to_model_and_back():
    u = vimpact.PhysicalUnits(**TUBE, U=4.0, gap=0.003)
    m = u.model()
    p = m.parameters
    assert p["Ur"] == pytest.approx(4 / (12 * 0.02), rel=1e-15)
    assert p["mu"] == pytest.approx(1.5 + math.pi / 4, rel=1e-15)
    assert p["sigma"] == pytest.approx(-0.15, abs=1e-16)
    assert (p["xi"], p["St"]) == (0.002, 0.2)
    assert u.parameters(vimpact.Model("wake_impact")) == {k: p[k] for k in ("Ur", "sigma", "xi", "St", "mu")}
    # Back: any model's Ur and sigma to U and the gap.
    for ur, sigma in ((12.5, -0.1), (25.0, -0.2)):
        other = m.with_(Ur=ur, sigma=sigma)
        assert u.flow_speed(other) == pytest.approx(ur * 12 * 0.02, rel=1e-15)
        assert u.gap(other) == pytest.approx(-sigma * 0.02, rel=1e-15)
        assert u.parameter("U", u.flow_speed(other), m) == ("Ur", pytest.approx(ur, rel=1e-15))
        assert u.parameter("gap", u.gap(other), m) == ("sigma", pytest.approx(sigma, rel=1e-14))
    v = u.values(m)
    assert v["time_scale"] == pytest.approx(0.02 / (2 * math.pi * 0.2 * 4.0), rel=1e-15)
    assert v["Re"] == pytest.approx(4 * 0.02 / 1e-6, rel=1e-15)
    assert u.warnings(m) == []
    assert "PhysicalUnits(D=0.02" in repr(u)


def test_any_model_by_its_units():
    u = vimpact.PhysicalUnits(length=0.001, time=0.5, gap=0.0015)
    m = u.model(vimpact.Model("two_sided_impact_oscillator"))
    assert m.parameters["d"] == pytest.approx(1.5, rel=1e-15)
    assert math.isnan(u.flow_speed(m))
    with pytest.raises(vimpact.InputError, match="U .flow speed. needs a cylinder"):
        vimpact.PhysicalUnits(length=1, time=1, U=3)


@pytest.mark.parametrize("bad,needle", [(dict(TUBE, rho=-1000.0), "rho"), (dict(TUBE, D=0.0), "D .diameter"),
                                        (dict(TUBE, gap=-0.001), "gap"), (dict(TUBE, fn="fast"), "fn must be")])
def test_bad_inputs_are_named(bad, needle):
    with pytest.raises(vimpact.InputError, match=needle):
        vimpact.PhysicalUnits(**bad)


def test_statistics_of_a_run_against_its_impacts():
    r = vimpact.simulate(vimpact.Model("wake_impact", Ur=16), **SHORT)
    s = r.statistics
    v = -r.impact_pre[:, 1]  # the paper's gap is y - sigma: v = -ydot before the reset
    assert np.allclose(r.impact_velocity, v, rtol=0, atol=0)
    assert np.allclose(r.impact_rebound, 0.8 * v, rtol=1e-14)
    assert np.allclose(r.impact_energy, 0.18 * v ** 2, rtol=1e-14)
    assert s["impacts_recorded"] == len(v)
    assert s["impact_velocity_mean"] == pytest.approx(v.mean(), rel=1e-14)
    assert s["impact_velocity_rms"] == pytest.approx(np.sqrt((v ** 2).mean()), rel=1e-14)
    assert s["duration"] == pytest.approx(r.t_record_end - r.t_record_start, rel=1e-15)
    assert s["power"] == pytest.approx(r.impact_energy.sum() / s["duration"], rel=1e-14)
    assert s["excursion"] == pytest.approx(r.section[:, 0].max() + 0.150298, rel=1e-13)
    assert vimpact._units.impact_statistics_names()[0] == "impacts_recorded"
    # In SI with the tube: the rate times Omega_f.
    u = vimpact.PhysicalUnits(**TUBE)
    m = u.model(vimpact.Model("wake_impact", Ur=16))
    k = u.statistics(vimpact.simulate(m, **SHORT))
    omega = 2 * math.pi * 0.2 * (16 * 12 * 0.02) / 0.02
    assert k["impact_rate"] == pytest.approx(vimpact.simulate(m, **SHORT).statistics["impact_rate"] * omega,
                                             rel=1e-14)


def test_sweep_and_map_carry_statistics_per_run():
    w = vimpact.sweep(vimpact.Model("wake_impact"), "Ur", [16, 17], **SHORT)
    single = vimpact.simulate(vimpact.Model("wake_impact", Ur=17), **SHORT).statistics
    assert set(w.statistics) == set(single)
    for k, col in w.statistics.items():
        assert col.shape == (2,) + np.shape(single[k])  # excursion_by_surface: (runs, surfaces)
        assert col[1] == pytest.approx(single[k], rel=1e-15, nan_ok=True), k
    mp = vimpact.map(vimpact.Model("wake_impact"), x=("Ur", [16, 17]), y=("sigma", [-0.15, -0.14]), **SHORT)
    assert mp.statistics["impact_rate"].shape == (2, 2)


def test_same_statistics_as_the_command_line(cli, tmp_path):
    out = tmp_path / "s"
    cli("simulate", "--set", "Ur=17", "--transient", "100", "--record", "40", "--no-plot", "--out", str(out))
    loaded = vimpact.Simulation.load(str(out))
    mine = vimpact.simulate(vimpact.Model("wake_impact", Ur=17), **SHORT)
    for k in vimpact._units.impact_statistics_names():
        assert loaded.statistics[k] == pytest.approx(mine.statistics[k], rel=1e-15, nan_ok=True), k
    assert np.array_equal(loaded.impact_velocity, mine.impact_velocity)


def test_clearance_is_the_grazing_value_at_the_matching_ur_times_d():
    u = vimpact.PhysicalUnits(**TUBE)
    c = vimpact.clearance(units=u, speeds=[4.0, 5.0], fractions=[0.5, 1.2], **SHORT)
    assert c.x == "U" and c.param == "Ur" and c.gap_param == "sigma"
    m = u.model()
    for k, speed in enumerate((4.0, 5.0)):
        g = vimpact.grazing(m.with_(Ur=speed / 0.24), param="sigma")
        assert c.grazing_value[k] == g.value[0]
        assert c.clearance[k] == -g.value[0]
        assert c.clearance_si[k] == pytest.approx(-g.value[0] * 0.02, rel=1e-15)
    assert c.gap.shape == (2, 2) and c.label.shape == (2, 2)
    assert np.allclose(c.gap_si, c.gap * 0.02, rtol=1e-15)
    assert (c.label[:, 1] == "P0").all()  # 1.2 times the clearance: no impact
    assert (c.statistics["impacts_recorded"][:, 0] > 0).all()
    assert c.statistics_si["impact_rate"][0, 0] == pytest.approx(
        c.statistics["impact_rate"][0, 0] * 2 * math.pi * 0.2 * 4.0 / 0.02, rel=1e-14)


def test_clearance_gaps_in_metres():
    u = vimpact.PhysicalUnits(**TUBE)
    c = vimpact.clearance(units=u, speeds=[4.0], gaps=[0.0005, 0.002], **SHORT)
    assert np.allclose(c.gap_si, [[0.0005, 0.002]], rtol=1e-15) and np.allclose(c.gap, [[0.025, 0.1]], rtol=1e-14)
    assert c.label[0, 1] == "P0" and c.label[0, 0] != "P0"
    with pytest.raises(vimpact.InputError, match="gap -0.001 m is below zero"):
        vimpact.clearance(units=u, speeds=[4.0], gaps=[-0.001, 0.001])


def test_clearance_of_any_model_in_its_units():
    c = vimpact.clearance(vimpact.Model("two_sided_impact_oscillator"), "w", [1.2], fractions=[1.5], **SHORT)
    assert c.gap_param == "d" and c.speed is None and c.clearance_si is None
    assert c.clearance[0] > 0 and c.label[0, 0] == "P0"


def test_the_pictures(tmp_path):
    r = vimpact.simulate(vimpact.Model("wake_impact", Ur=16), sample_dt=0.1, **SHORT)
    fig = plot.phase(r, str(tmp_path / "p.png"))
    hist = fig.axes[2]
    assert sum(p.get_height() for p in hist.patches) == len(r.impact_velocity)
    assert "impact velocity" in hist.get_xlabel()
    check_layout(fig)
    c = vimpact.clearance(units=vimpact.PhysicalUnits(**TUBE), speeds=[4.0, 4.5, 5.0], fractions=[0.3, 0.7, 1.2],
                          **SHORT)
    fig = plot.design_chart(c, str(tmp_path / "c.png"))
    ax = fig.axes[0]
    assert ax.get_xlabel() == "U, flow speed [m/s]" and ax.get_ylabel() == "gap to the barrier [m]"
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "P0, no impact" in texts and any(t.startswith("clearance") for t in texts)
    assert "impact rate [Hz]" in texts and "dissipated power [W/m]" in texts
    check_layout(fig)


def test_the_command_lines_clearance_loads_as_the_same_result(cli, tmp_path):
    out = tmp_path / "c"
    p = cli("clearance", "--si", "D=0.02,m=0.6,fn=12,zeta=0.002,rho=1000", "--speeds", "4:5:2", "--fractions",
            "0.5:1.2:2", "--transient", "100", "--record", "40", "--out", str(out))
    assert p.returncode == 0, p.stderr
    assert (out / "plot.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    loaded = vimpact.Clearance.load(str(out))
    mine = vimpact.clearance(units=vimpact.PhysicalUnits(**TUBE), speeds=[4.0, 5.0], fractions=[0.5, 1.2], **SHORT)
    assert np.array_equal(loaded.speed, mine.speed)
    assert np.array_equal(loaded.clearance_si, mine.clearance_si)
    assert np.array_equal(loaded.gap_si, mine.gap_si)
    assert (loaded.label == mine.label).all()
    for k in ("impact_rate", "power", "excursion"):
        assert np.allclose(loaded.statistics_si[k], mine.statistics_si[k], rtol=1e-15, equal_nan=True), k


# m* = 3 on the 20 mm tube in water (m = 0.3 pi kg/m; 0.4 pi kg/m with the added mass) and a
# stiffness per metre k = 160 pi^3 N/m^2 = 0.4 pi (2 pi 10 Hz)^2: fn = 10 Hz.
STIFF = dict(D=0.02, mstar=3.0, k=160 * math.pi ** 3, zeta=0.002, rho=1000.0)


def test_mass_ratio_and_stiffness_instead_of_mass_and_frequency():
    u = vimpact.PhysicalUnits(**STIFF, U=2.0)
    p = u.parameters()
    assert p["Ur"] == pytest.approx(2.0 / (10 * 0.02), rel=1e-13)
    assert p["mu"] == pytest.approx(math.pi, rel=1e-14)  # (m* + CM) pi / 4
    assert u.inputs["m"] == pytest.approx(0.3 * math.pi, rel=1e-15) and u.inputs["fn"] == pytest.approx(10, rel=1e-14)
    assert (u.inputs["mstar"], u.inputs["k"]) == (3.0, STIFF["k"])
    with pytest.raises(vimpact.InputError, match=r"m \(structural mass per unit length, kg/m\) and mstar"):
        vimpact.PhysicalUnits(**STIFF, m=0.6)
    with pytest.raises(vimpact.InputError, match=r"^PhysicalUnits: missing fn \(natural frequency in still fluid, "
                                                 r"Hz\) or k"):
        vimpact.PhysicalUnits(D=0.02, m=0.6, zeta=0.002, rho=1000.0)


@pytest.mark.parametrize("values, needle", [
    (dict(D=-1), "PhysicalUnits: missing zeta (keys: "),
    (dict(TUBE, D=-1), "PhysicalUnits: D (diameter, m) must be a finite number > 0 (got -1)"),
    (dict(TUBE, Q=1), "PhysicalUnits: unknown key 'Q' (keys: "),
    (dict(TUBE, length=1), "PhysicalUnits: give either a cylinder"),
    (dict(TUBE, D=1e300), "PhysicalUnits: rho D^2 = inf from rho = 1000, D = 1e+300 is outside the range of a "
                          "double: the inputs must keep its magnitude in [2.2250738585072014e-308, "
                          "1.7976931348623157e+308]"),
    (dict(TUBE, U=1e308), "PhysicalUnits: Ur = U / (fn D) = inf from U = 1e+308, fn = 12, D = 0.02"),
    (dict(length=1e200, time=1e-200), "PhysicalUnits: the velocity scale = inf from length = 1e+200, time = 1e-200"),
])
def test_messages_are_pythons_not_the_command_lines(values, needle):
    # The library's words with the front end's name: no --si, no option spelling.
    with pytest.raises(vimpact.InputError) as e:
        vimpact.PhysicalUnits(**values)
    assert str(e.value).startswith(needle), str(e.value)
    assert "--" not in str(e.value)


def test_a_tube_given_by_its_stiffness_oscillates_at_sqrt_k_over_its_total_mass():
    # A free decay far below lock-in, the wake's coupling and lift off (A = 0, CL0 = 0 given
    # as an SI input), no barrier in reach: the structure's period, in seconds by the run's
    # time scale, is that of sqrt(k / (m + m_f)) = 2 pi 10 rad/s (to the 0.2 % damping's
    # correction and the section's sampling).
    u = vimpact.PhysicalUnits(**STIFF, U=0.4, CL0=0.0)
    m = u.model().with_(A=0.0, gamma=0.0, sigma=-10.0)
    assert m.parameters["CL0"] == 0.0 and u.values(m)["CL0"] == 0.0
    r = vimpact.simulate(m, ic=[0.01, 0.0, 0.0, 0.0], transient=0, record=40, section="maxima")
    t = r.section_t
    period_s = (t[-1] - t[0]) / (len(t) - 1) * u.values(m)["time_scale"]
    assert 1.0 / period_s == pytest.approx(math.sqrt(160 * math.pi ** 3 / (0.4 * math.pi)) / (2 * math.pi), rel=1e-4)


def test_the_picture_of_a_run_in_si(cli, tmp_path):
    out = tmp_path / "s"
    p = cli("simulate", "--si", "D=0.02,m=0.6,fn=12,zeta=0.002,rho=1000,U=4,gap=0.001", "--transient", "100",
            "--record", "40", "--out", str(out))
    assert p.returncode == 0, p.stderr
    r = vimpact.Simulation.load(str(out))
    assert r.si["values"]["length_scale"] == 0.02
    fig = plot.phase(r, str(tmp_path / "si.png"), units="si")
    series, portrait, hist = fig.axes[:3]
    assert series.get_xlabel() == "t [s]" and series.get_ylabel().endswith("[m]")
    assert portrait.get_ylabel().endswith("[m/s]")
    assert hist.get_xlabel() == "impact velocity -dg/dt [m/s]"
    # The barrier 1 mm below the rest position, drawn in metres.
    assert any(abs(line.get_ydata()[0] + 0.001) < 1e-12 for line in series.get_lines()[1:2])
    check_layout(fig)
    with pytest.raises(ValueError, match="units='si' needs a run with its SI scales"):
        plot.phase(vimpact.simulate(vimpact.Model("wake_impact"), **SHORT), units="si")


def test_the_pictures_of_period_floquet_and_lyapunov_in_si(cli, tmp_path):
    # Each command with --si draws in SI (run.json's plot_options); the data drawn are the
    # model's values times the scales computed here by hand: D = 0.02 m, and one model time
    # unit 1 / Omega_f with Omega_f = 2 pi St U / D = 80 pi rad/s at U = 4 m/s.
    si = "D=0.02,m=0.6,fn=12,zeta=0.002,rho=1000,U=4,gap=0.001"
    second = 1.0 / (2 * math.pi * 0.2 * 4 / 0.02)
    runs = {}
    for command, extra in (("period", ["--transient", "100", "--record", "40"]), ("floquet", []),
                           ("lyapunov", ["--impacts", "100"])):
        out = tmp_path / command
        p = cli(command, "--si", si, *extra, "--out", str(out))
        assert p.returncode == 0, p.stderr
        record = vimpact.results.read_record(str(out))
        assert record["plot_options"] == {"units": "si"}, command
        runs[command] = out

    r = vimpact.Period.load(str(runs["period"]))
    ax = plot.sections(r, units="si").axes[0]
    x = ax.get_lines()[0].get_xdata()
    assert np.allclose(x, np.asarray(r.section)[:, 0] * 0.02, rtol=1e-15, atol=0)
    assert ax.get_xlabel().endswith("[m]")

    f = vimpact.Floquet.load(str(runs["floquet"]))
    fig = plot.floquet(f, units="si")
    orbit_line = fig.axes[1].get_lines()[0]
    assert np.allclose(orbit_line.get_xdata(), f.orbit[:, 0] * 0.02, rtol=1e-15, atol=0)
    assert np.allclose(orbit_line.get_ydata(), f.orbit[:, 1] * 0.02 / second, rtol=1e-14, atol=0)
    assert f"T = {f.period * second:.6g} s" in fig.axes[0].get_title()
    assert f.si["period_si"] == pytest.approx(f.period * second, rel=1e-14)

    ly = vimpact.Lyapunov.load(str(runs["lyapunov"]))
    fig = plot.lyapunov(ly, units="si")
    last = [line.get_ydata()[-1] for line in fig.axes[1].get_lines() if line.get_label().startswith("lambda")]
    assert np.allclose(last, ly.running_exponents[-1] * (1 / second), rtol=1e-12, atol=0)
    assert np.allclose(last, ly.si["exponents_si"], rtol=1e-9, atol=1e-9)
    assert fig.axes[1].get_ylabel() == "running estimate [1/s]"
