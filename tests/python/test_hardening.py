"""What a hostile user tried from Python: each call below once gave pybind's signature dump, a
MemoryError, an unrelated message or a hang; each must now raise a clear error naming the
argument, or end with an outcome."""
import numpy as np
import pytest

import vimpact

W = vimpact.WakeImpact(Ur=16)
Q = dict(transient=20, record=20)


def test_an_integer_too_large_names_the_argument():
    with pytest.raises(vimpact.InputError, match=r"transient = 1180591620717411303424 does not fit in a 64-bit"):
        vimpact.simulate(W, transient=2 ** 70)


def test_a_grid_too_large_is_refused_before_allocating():
    with pytest.raises(vimpact.InputError, match=r"1 <= n <= 1e8"):
        vimpact.grid(0, 1, 10 ** 12)


def test_an_axis_given_as_a_name_alone():
    with pytest.raises(TypeError, match=r"x must be a pair \(name, values\)"):
        vimpact.map(W, x="Ur", y=("sigma", [-0.1]))


@pytest.mark.parametrize("curves", [[(12,)], "A=12", {"A": 12}, [12]])
def test_curves_that_are_not_dicts(curves):
    with pytest.raises(TypeError, match="curves must be a list of dicts"):
        vimpact.response(W, "Ur", [16], curves=curves)


@pytest.mark.parametrize("call", [
    lambda: vimpact.sweep(W, "Ur", [16, 17], threads=10000, **Q),
    lambda: vimpact.map(W, ("Ur", [16]), ("sigma", [-0.1]), threads=10000, **Q),
    lambda: vimpact.dimension(np.random.default_rng(1).random((100, 2)), threads=10000),
])
def test_one_thread_rule_everywhere(call):
    with pytest.raises(vimpact.InputError, match=r"threads = 10000 is outside its valid range \[0, 1024\]"):
        call()


def test_dimension_needs_as_many_points_as_the_command_line(vimpact_cli, tmp_path):
    """The command line and Python share the library's rule on the smallest point set."""
    import subprocess
    pts = tmp_path / "p.csv"
    pts.write_text("x,y\n0,0\n1,1\n")
    p = subprocess.run([vimpact_cli, "dimension", "--points", str(pts)], capture_output=True, text=True)
    assert p.returncode == 2
    with pytest.raises(vimpact.InputError) as e:
        vimpact.dimension(np.array([[0.0, 0.0], [1.0, 1.0]]))
    assert str(e.value) in p.stderr


def test_a_sampling_interval_below_the_time_resolution_ends():
    s = vimpact.simulate(W, sample_dt=1e-300, **Q)
    assert s.outcome == "sample_limit"
    assert len(s.series_t) < 10


def test_a_huge_number_of_samples_ends_at_the_limit():
    s = vimpact.simulate(W, sample_dt=1e-5, **Q)
    assert s.outcome == "sample_limit"
    assert len(s.series_t) <= 1_000_000 + 2 * Q["record"] * 2


@pytest.mark.parametrize("t0", [1e-300, 1e-6])
def test_a_tiny_lyapunov_interval_is_refused(t0):
    with pytest.raises(vimpact.InputError, match="t0 must be >="):
        vimpact.lyapunov(W, t0=t0)


def test_a_tiny_floquet_sampling_interval_is_refused():
    with pytest.raises(vimpact.InputError, match=r"sample_dt must be 0 .* or in \[1e-6, inf\)"):
        vimpact.floquet(W, sample_dt=1e-300, **Q)


def test_a_subnormal_parameter_is_refused():
    with pytest.raises(vimpact.InputError, match="subnormal"):
        vimpact.WakeImpact(Ur=4.9e-324)
