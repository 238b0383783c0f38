"""vimpact.cylinder_units: the same numbers as `vimpact units`, and a model built from them
runs at the tube's own natural frequency."""
import math

import pytest

import vimpact

TUBE = dict(D=0.02, m=0.6, fn=12.0, zeta=0.002, rho=1000.0)


def test_the_command_line_gives_the_same_numbers(cli_json):
    row = cli_json("units", "--si", "D=0.02,m=0.6,fn=12,zeta=0.002,rho=1000,CM=1.2,St=0.21", "--speeds",
                   "4:4:1")["dimensionless"][0]
    assert vimpact.cylinder_units(**TUBE, U=4, CM=1.2, St=0.21) == row


def test_a_model_from_the_conversion_oscillates_at_the_tubes_frequency():
    # Far below lock-in (U small: Ur = 2) with the wake coupling off (A = 0) and no barrier in
    # reach, a free decay from y = 0.01 oscillates at the structure's damped natural frequency:
    # in SI it must be the tube's f_n = 12 Hz (to the damping's correction and the sampling).
    d = vimpact.cylinder_units(**TUBE, U=0.48)
    assert math.isclose(d["Ur"], 2.0, rel_tol=1e-12)
    m = vimpact.Model("wake_impact", Ur=d["Ur"], mu=d["mu"], xi=d["xi"], St=d["St"], A=0.0, CL0=0.0, gamma=0.0,
                      sigma=-10.0)
    r = vimpact.simulate(m, ic=[0.01, 0.0, 0.0, 0.0], transient=0, record=40, section="maxima")
    t = r.section_t
    period_model = (t[-1] - t[0]) / (len(t) - 1)
    f_si = 1.0 / (period_model * d["time_scale"])
    assert f_si == pytest.approx(12.0, rel=1e-4)


def test_bad_values_are_refused():
    with pytest.raises(vimpact.InputError, match="D must be a number"):
        vimpact.cylinder_units(**{**TUBE, "D": "wide"}, U=1.0)
    with pytest.raises(vimpact.InputError, match="rho"):
        vimpact.cylinder_units(**{**TUBE, "rho": 0.0}, U=1.0)


def test_mass_ratio_and_stiffness_give_the_same_cylinder():
    # By hand: m_f = rho pi D^2 / 4 = 0.3141593 kg/m, so m = 0.6 is mstar = 0.6 / m_f, and
    # fn = 12 Hz on the total mass 0.9141593 kg/m is k = (2 pi 12)^2 0.9141593 N/m^2.
    m_f = 1000.0 * math.pi * 0.02 ** 2 / 4.0
    mstar = 0.6 / m_f
    k = (2.0 * math.pi * 12.0) ** 2 * (0.6 + m_f)
    assert k == pytest.approx(5196.9, abs=0.1)
    given = vimpact.cylinder_units(D=0.02, mstar=mstar, k=k, zeta=0.002, rho=1000.0, U=4.0)
    direct = vimpact.cylinder_units(**TUBE, U=4.0)
    assert given.keys() == direct.keys()
    for key, value in direct.items():
        assert given[key] == pytest.approx(value, rel=1e-12), key
    assert given["Ur"] == pytest.approx(4.0 / (12.0 * 0.02), rel=1e-12)
    assert given["mass_ratio"] == pytest.approx(mstar, rel=1e-12)


def test_viscosity_sets_the_reynolds_number():
    d = vimpact.cylinder_units(**TUBE, U=4.0, nu=1.5e-6)
    assert d["Re"] == pytest.approx(4.0 * 0.02 / 1.5e-6, rel=1e-12)


def test_one_of_each_pair_and_a_speed_are_required():
    with pytest.raises(vimpact.InputError, match="mstar"):
        vimpact.cylinder_units(D=0.02, m=0.6, mstar=1.9, fn=12.0, zeta=0.002, rho=1000.0, U=1.0)
    with pytest.raises(vimpact.InputError, match="fn"):
        vimpact.cylinder_units(D=0.02, m=0.6, zeta=0.002, rho=1000.0, U=1.0)
    with pytest.raises(vimpact.InputError, match="U"):
        vimpact.cylinder_units(**TUBE)
    with pytest.raises(vimpact.InputError, match="U"):
        vimpact.cylinder_units(**TUBE, U=-1.0)
