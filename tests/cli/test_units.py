"""`vimpact units`: the engineering contract (SI in, the model's Ur, mu, xi out) and its errors."""
import json
import math

from test_cli import run

SI = "D=0.02,m=0.6,fn=12,zeta=0.002,rho=1000"


def test_the_contract_example(vimpact):
    p = run(vimpact, "units", "--si", SI, "--speeds", "3:6:7", "--json")
    assert p.returncode == 0, p.stderr
    rows = json.loads(p.stdout)["dimensionless"]
    assert [r["U"] for r in rows] == [3.0, 3.5, 4.0, 4.5, 5.0, 5.5, 6.0]
    for r in rows:
        assert {"U", "Ur", "mu", "xi"} <= set(r)
        # The model's structure frequency delta = 1/(St Ur), in Hz, is the tube's 12 Hz.
        assert math.isclose(r["frequency_scale"] / (r["St"] * r["Ur"]), 12.0, rel_tol=1e-12)
        assert r["xi"] == 0.002
        # Water's added mass (pi/4 rho D^2 = 0.314 kg/m) on 0.6 kg/m, over rho D^2 = 0.4 kg/m.
        assert math.isclose(r["mu"], (0.6 + math.pi / 4 * 1000 * 0.02 ** 2) / (1000 * 0.02 ** 2), rel_tol=1e-14)


def test_text_output_names_the_model_parameters(vimpact):
    p = run(vimpact, "units", "--si", SI, "--speeds", "3:6:2")
    assert p.returncode == 0, p.stderr
    assert "--set mu=" in p.stdout and "Ur from 12.5 to 25" in p.stdout


def test_bad_si_input_is_refused(vimpact):
    for si, needle in [("D=0.02,m=0.6,fn=12,zeta=0.002", "--si: missing rho"),
                       (SI + ",Q=1", "unknown key 'Q'"),
                       (SI + ",D=0.03", "D is given twice"),
                       ("D=0,m=0.6,fn=12,zeta=0.002,rho=1000", "D (diameter, m) must be")]:
        p = run(vimpact, "units", "--si", si, "--speeds", "3:6:7")
        assert p.returncode == 2, (si, p.stderr)
        assert needle in p.stderr, (si, p.stderr)
    p = run(vimpact, "units", "--si", SI, "--speeds", "-1:6:7")
    assert p.returncode == 2 and "U (flow speed" in p.stderr


def test_inputs_that_give_no_number_together_are_refused(vimpact):
    # Each input is in range; together they give a quantity no double holds (D^2 overflows,
    # mu = inf / inf): refused naming the inputs and the range, never printed as nan.
    for si, names in [("D=1e300,m=0.6,fn=12,zeta=0.002,rho=1000", ["D = 1e+300", "rho = 1000"]),
                      ("D=1e-200,m=0.6,fn=12,zeta=0.002,rho=1000", ["D = 1e-200", "rho = 1000"]),
                      ("D=0.02,m=1e308,fn=12,zeta=0.002,rho=1e-300", ["m = 1e+308", "rho = 1e-300", "D = 0.02"]),
                      ("D=1,mstar=1e306,fn=12,zeta=0.002,rho=1e5", ["mstar = 1e+306", "rho = 1e+05", "D = 1"])]:
        p = run(vimpact, "units", "--si", si, "--speeds", "3:6:7")
        assert p.returncode == 2, (si, p.stdout)
        line = p.stderr.strip()
        assert line.startswith("vimpact: error: --si: ") and len(line.splitlines()) == 1, (si, line)
        assert all(n in line for n in names), (si, line)
        assert "outside the range of a double: the inputs must keep its magnitude in [2.2250738585072014e-308, " \
               "1.7976931348623157e+308]" in line, (si, line)
        assert "nan" not in p.stdout
    # A speed that makes Ur overflow: the speed is named.
    p = run(vimpact, "units", "--si", SI.replace("fn=12", "fn=1e-300"), "--speeds", "1e10:1e10:1")
    assert p.returncode == 2 and "U = 1e+10" in p.stderr and "Ur = U / (fn D)" in p.stderr, p.stderr
