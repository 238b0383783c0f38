"""The steppable systems from Python: HybridSystem, SectionSystem, TangentSystem against other
paths of the library (simulate's recorded points, vimpact.lyapunov) and finite differences."""
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import vimpact


def wake(Ur):
    return vimpact.WakeImpact(Ur=Ur)


def test_section_steps_are_simulates_points():
    m = wake(19.0)
    s = vimpact.simulate(m, transient=0, record=30)
    sec = vimpact.SectionSystem(m)
    t, x = sec.points(30)
    assert sec.status == "ok"
    assert np.array_equal(t, s.section_t)
    assert np.array_equal(x, s.section)
    imp = vimpact.simulate(m, transient=0, record=10, section="impacts")
    t, x = vimpact.SectionSystem(m, section="impacts").points(10)
    assert np.array_equal(x, imp.section) and np.array_equal(t, imp.section_t)


def test_lyapunov_in_a_few_lines_agrees_with_the_library():
    m, t0, warmup, n = wake(16.0), np.pi, 16, 400
    lib = vimpact.lyapunov(m, time=n * t0, warmup=warmup)
    assert lib.status == "ok"
    # The library's start: the first section point after its transient.
    start = vimpact.simulate(m, record=1)
    ts = vimpact.TangentSystem(m, start.section[0], t=start.section_t[0])
    total = np.zeros(m.dim)
    for k in range(warmup + n):
        assert ts.advance_to(start.section_t[0] + (k + 1) * t0) == "ok"
        q, r = np.linalg.qr(ts.deviations)
        if k >= warmup:
            total += np.log(np.abs(np.diag(r)))
        ts.set_deviations(q * np.sign(np.diag(r)))
    mine = np.sort(total / (n * t0))[::-1]
    assert np.allclose(mine, lib.exponents, atol=2e-3, rtol=0), (mine, lib.exponents)


def test_section_jacobian_is_the_difference_of_section_steps():
    m, h = wake(19.0), 1e-6
    sec = vimpact.SectionSystem(m, rtol=1e-12, atol=1e-12)
    sec.step(40)
    x0 = sec.state
    tan = vimpact.TangentSystem(m, x0, section="maxima", rtol=1e-12, atol=1e-12)
    assert tan.step() == "ok"
    for j in (0, 2, 3):  # along the section ydot = 0
        e = np.zeros(4)
        e[j] = h
        a = vimpact.SectionSystem(m, x0 + e, rtol=1e-12, atol=1e-12)
        b = vimpact.SectionSystem(m, x0 - e, rtol=1e-12, atol=1e-12)
        a.step()
        b.step()
        fd = (a.state - b.state) / (2 * h)
        assert np.allclose(tan.deviations[:, j], fd, atol=1e-5 * max(1.0, np.abs(fd).max()), rtol=0)


def test_hybrid_lands_on_times_and_reinit_repeats_bits():
    m = wake(19.0)
    hs = vimpact.HybridSystem(m)
    ys = []
    for _ in range(200):
        assert hs.step(0.5) == "ok"
        ys.append(hs.state)
    assert hs.time == pytest.approx(100.0, abs=1e-12)
    assert hs.stats.impacts >= 1
    hs.reinit(m.default_ic)
    again = []
    for _ in range(200):
        hs.step(0.5)
        again.append(hs.state)
    assert np.array_equal(np.array(ys), np.array(again))
    # simulate's time series at those times (the samples, not the rows of its impacts) comes
    # from the interpolant of steps the system cuts instead: equal to the integration's accuracy.
    s = vimpact.simulate(m, transient=0, record=1000, sample_dt=0.5, t_max=100.0)
    rows = [np.flatnonzero(s.series_t == 0.5 * k)[-1] for k in range(1, 201)]
    assert np.allclose(s.series[rows], np.array(ys), atol=1e-6, rtol=0)


def test_impacts_of_a_step_and_parameters():
    m = wake(19.0)
    hs = vimpact.HybridSystem(m)
    seen = 0
    while seen == 0:
        hs.step()
        seen = len(hs.impacts["impact_t"])
    pre, post = hs.impacts["impact_pre"][0], hs.impacts["impact_post"][0]
    assert pre[0] == pytest.approx(m.sigma, abs=1e-12) and post[1] == pytest.approx(-m.r * pre[1], rel=1e-12)
    sec = vimpact.SectionSystem(m)
    sec.set_parameter("Ur", 16.0)
    assert sec.parameters["Ur"] == 16.0 and sec.model.Ur == 16.0
    ref = vimpact.SectionSystem(wake(16.0))
    sec.step(5)
    ref.step(5)
    assert np.array_equal(sec.state, ref.state)


def test_bad_input_raises_value_error_naming_it():
    m = wake(19.0)
    with pytest.raises(ValueError, match="ic"):
        vimpact.HybridSystem(m, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="section 'nope'"):
        vimpact.SectionSystem(m, section="nope")
    with pytest.raises(ValueError, match="not impacts"):
        vimpact.TangentSystem(m, section="impacts")
    with pytest.raises(ValueError, match="deviations"):
        vimpact.TangentSystem(m, deviations=7)
    with pytest.raises(ValueError, match="rtol"):
        vimpact.HybridSystem(m, rtol=2.0)
    hs = vimpact.HybridSystem(m)
    hs.step(1.0)
    with pytest.raises(ValueError, match="t = 0.5"):
        hs.advance_to(0.5)
    with pytest.raises(ValueError, match="no parameter 'Uq'"):
        hs.set_parameter("Uq", 1.0)
    with pytest.raises(ValueError, match="outside its valid range"):
        hs.set_parameter("Ur", -1.0)
    ts = vimpact.TangentSystem(m, deviations=2)
    with pytest.raises(ValueError, match="4 x 2"):
        ts.set_deviations(np.eye(4))
    with pytest.raises(ValueError, match="discrete"):
        vimpact.TangentSystem(m, section="maxima").advance_to(1.0)


def test_limits_are_a_status():
    hs = vimpact.HybridSystem(wake(19.0), max_steps=5)
    assert hs.advance_to(100.0) == "step_limit"
    assert hs.status == "step_limit"
    t = hs.time
    assert hs.step() == "step_limit" and hs.time == t


INTERRUPTED = textwrap.dedent("""
    import vimpact
    s = vimpact.{system}(vimpact.WakeImpact(Ur=19))
    print("started", flush=True)
    try:
        s.{call}
    except KeyboardInterrupt:
        print("KeyboardInterrupt", s.status, flush=True)
        raise
    print("finished", flush=True)
""")


@pytest.mark.parametrize("system,call", [("HybridSystem", "advance_to(1e12)"), ("SectionSystem", "step(10**12)"),
                                         ("TangentSystem", "advance_to(1e12)")])
def test_ctrl_c_stops_a_long_call(system, call):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    proc = subprocess.Popen([sys.executable, "-c", INTERRUPTED.format(system=system, call=call)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    assert proc.stdout.readline().strip() == "started"
    time.sleep(0.5)
    assert proc.poll() is None, "the call finished before it could be interrupted"
    sent = time.perf_counter()
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=30)
    assert "KeyboardInterrupt interrupted" in out and "finished" not in out, out + err
    assert time.perf_counter() - sent < 1.0


def test_a_model_file_steps_as_its_builtin_and_as_simulate(two_sided_file):
    """The systems of a model file (the function-table engine) step like the built-in to 1e-9
    (separately compiled code, last bits may differ) and, on the file itself, give simulate's
    section times bit for bit and its states to 1e-12: the systems' and the protocol's
    table-model code are separate translation units, compiled with the compiler free to fuse a
    multiply and an add (only the built-ins' are not), so a last bit can differ."""
    builtin = vimpact.TwoSidedImpactOscillator()
    a, b = vimpact.SectionSystem(builtin), vimpact.SectionSystem(two_sided_file)
    ta, xa = a.points(20)
    tb, xb = b.points(20)
    assert a.status == b.status == "ok"
    np.testing.assert_allclose(tb, ta, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(xb, xa, rtol=1e-9, atol=1e-9)
    s = vimpact.simulate(two_sided_file, transient=0, record=20)
    assert np.array_equal(tb, s.section_t)
    np.testing.assert_allclose(xb, s.section, rtol=1e-12, atol=1e-12)
    h = vimpact.HybridSystem(two_sided_file)
    h.advance_to(5.0)
    g = vimpact.HybridSystem(builtin)
    g.advance_to(5.0)
    assert h.time == g.time == 5.0 and h.status == "ok"
    np.testing.assert_allclose(h.state, g.state, rtol=1e-9, atol=1e-9)
