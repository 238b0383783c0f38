"""The Python API itself: documented shapes and dtypes, determinism across thread counts,
the GIL released during long calls, progress reports, Ctrl-C, docstrings."""
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import vimpact

W = vimpact.WakeImpact()
Q = dict(transient=60, record=30)


def check(a, shape, dtype):
    a = np.asarray(a)
    assert a.shape == shape, (a.shape, shape)
    assert a.dtype.kind == np.dtype(dtype).kind and (dtype is str or a.dtype == np.dtype(dtype)), (a.dtype, dtype)


def test_simulation_shapes_and_dtypes():
    s = vimpact.simulate(vimpact.WakeImpact(Ur=21.5), sample_dt=0.1, **Q)
    n, k, m = len(s.section_t), len(s.impact_t), len(s.series_t)
    assert n == Q["record"] and k > 0 and m > 0
    check(s.section, (n, 4), np.float64)
    check(s.section_t, (n,), np.float64)
    check(s.impact_pre, (k, 4), np.float64)
    check(s.impact_post, (k, 4), np.float64)
    check(s.series, (m, 4), np.float64)
    check(s.final_state, (4,), np.float64)
    assert (np.diff(s.section_t) > 0).all() and (np.diff(s.series_t) >= 0).all()
    assert (s.section[:, 1] == 0).all(), "on the section v = 0 exactly"
    # Impacts happen on the barrier and reverse the velocity with the restitution factor.
    np.testing.assert_allclose(s.impact_pre[:, 0], W.sigma, atol=1e-12)
    np.testing.assert_array_equal(s.impact_post[:, 1], -0.8 * s.impact_pre[:, 1])
    assert s.outcome == "ok" and s.stats.steps > 0
    assert vimpact.simulate(vimpact.WakeImpact(Ur=21.5), **Q).series.shape == (0, 4)


def test_period_shapes():
    p = vimpact.period(vimpact.WakeImpact(Ur=19), **Q)
    check(p.section_y, (p.period,), np.float64)
    assert p.label == f"P{p.period}"
    q = vimpact.period(W.with_(sigma=-0.3), **Q)
    assert (q.label, q.period) == ("P0", 0) and q.section_y.shape == (0,)


def test_sweep_shapes_and_dtypes():
    s = vimpact.sweep(W, "Ur", vimpact.grid(15, 16, 3), ic_mode="follow", direction="both", **Q)
    runs = 6
    for name in ("branch", "period", "impacts", "steps"):
        check(getattr(s, name), (runs,), np.int64)
    for name in ("value", "closure", "sigma_graze"):
        check(getattr(s, name), (runs,), np.float64)
    for name in ("label", "outcome"):
        check(getattr(s, name), (runs,), str)
    check(s.final_state, (runs, 4), np.float64)
    P = len(s.points)
    assert P == runs * Q["record"]
    check(s.points, (P, 4), np.float64)
    check(s.point_run, (P,), np.int64)
    check(s.point_value, (P,), np.float64)
    assert np.isnan(s.sigma_graze).all(), "no grazing asked"
    assert sum(s.label_counts.values()) == runs
    assert s.stats["jobs"] == runs and s.stats["wall_time"] > 0


def test_map_and_basins_shapes():
    m = vimpact.map(W, x=("Ur", [16, 20, 24]), y=("sigma", [-0.15, -0.1]), **Q)
    for name in ("label", "outcome"):
        check(getattr(m, name), (2, 3), str)
    for name in ("period", "impacts", "steps"):
        check(getattr(m, name), (2, 3), np.int64)
    check(m.closure, (2, 3), np.float64)
    assert m.grazing is None
    b = vimpact.basins(vimpact.WakeImpact(Ur=14.9), x=("y", [-0.2, 0.0, 0.2]), y=("ydot", [0.0, 0.1]), **Q)
    check(b.attractor, (2, 3), np.int64)
    check(b.label, (2, 3), str)
    assert (b.attractor[:, 0] == -1).all() and (b.label[:, 0] == "inadmissible").all()
    assert sum(a.cells for a in b.attractors) == b.attractor.size - b.inadmissible_cells
    for a in b.attractors:
        assert a.cycle.ndim == 2 and a.cycle.shape[1] == 3 and a.box.shape == (2, 3)


def test_response_shapes():
    r = vimpact.response(W, "Ur", [5, 6], curves=[(12, 0.3), (10, 0.25), (14, 0.35)], transient_time=300)
    for name in ("amplitude", "y_max", "sigma_graze", "frequency_ratio", "structure_frequency"):
        check(getattr(r, name), (3, 2), np.float64)
    check(r.converged, (3, 2), np.bool_)
    check(r.outcome, (3, 2), str)
    check(r.curves, (3, 2), np.float64)
    np.testing.assert_array_equal(r.structure_frequency[0], [1 / (0.2 * 5), 1 / (0.2 * 6)])
    # amplitude = max(|y_max|, |sigma_graze|), the library's definition.
    np.testing.assert_array_equal(r.amplitude, np.maximum(np.abs(r.y_max), np.abs(r.sigma_graze)))


def test_stability_and_dimension_shapes():
    f = vimpact.floquet(vimpact.WakeImpact(Ur=16), sample_dt=0.05, **Q)
    check(f.multipliers, (4,), np.complex128)
    check(f.monodromy, (4, 4), np.float64)
    check(f.orbit_point, (4,), np.float64)
    assert f.orbit.shape == (len(f.orbit_t), 4) and len(f.orbit_t) > 0
    assert f.impact_pre.shape == (f.impacts_per_period, 4)
    assert abs(f.multipliers[0] - 1) == f.trivial_error < 1e-8
    assert f.det_monodromy == pytest.approx(f.liouville_det, rel=1e-6)
    a = vimpact.floquet(vimpact.WakeImpact(Ur=18.426), **Q)  # the paper's chaotic point (Fig. 6a)
    assert (a.status, a.label) == ("aperiodic", "aperiodic")
    assert a.multipliers.shape == (0,) and a.stable is None and np.isnan(a.period)
    ly = vimpact.lyapunov(vimpact.WakeImpact(Ur=16), impacts=40, transient=60)
    check(ly.exponents, (4,), np.float64)
    h = len(ly.history_t)
    check(ly.history_growth, (h, 4), np.float64)
    assert ly.running_exponents.shape == (h, 4)
    np.testing.assert_allclose(ly.running_exponents[-1], np.sort(ly.exponents)[::-1], rtol=1e-12, atol=1e-15)
    assert ly.exponents.sum() == pytest.approx(ly.sum_rule, abs=1e-6)
    rng = np.random.default_rng(5)
    d = vimpact.dimension(rng.random((3000, 2)))
    k = len(d.r)
    check(d.r, (k,), np.float64)
    check(d.pairs, (k,), np.int64)
    check(d.local_slope, (k,), np.float64)
    assert d.dimension == pytest.approx(2.0, abs=0.1)
    with pytest.raises(ValueError, match="2-D"):
        vimpact.dimension(np.zeros(5))


def test_results_do_not_depend_on_the_thread_count():
    values = vimpact.grid(20, 25, 9)
    runs = [vimpact.sweep(W, "Ur", values, threads=t, grazing=True, **Q) for t in (1, 2, 5)]
    for s in runs[1:]:
        for name in ("label", "closure", "points", "point_run", "sigma_graze", "final_state", "steps"):
            np.testing.assert_array_equal(getattr(s, name), getattr(runs[0], name))
    follow = [vimpact.sweep(W, "Ur", vimpact.grid(14.5, 15.5, 5), ic_mode="follow", direction="both", threads=t, **Q)
              for t in (1, 3)]
    np.testing.assert_array_equal(follow[0].points, follow[1].points)
    b = [vimpact.basins(vimpact.WakeImpact(Ur=14.9), x=("y", [-0.1, 0.0, 0.1, 0.2]), y=("ydot", [-0.1, 0.1]),
                        threads=t, **Q) for t in (1, 4)]
    np.testing.assert_array_equal(b[0].attractor, b[1].attractor)


def test_the_forced_oscillator_runs_through_every_analysis():
    f = vimpact.ForcedImpactOscillator(omega=0.8)
    s = vimpact.simulate(f, **Q)
    assert s.section.shape == (Q["record"], 3) and s.state_names == ("y", "ydot", "theta")
    sw = vimpact.sweep(f, "omega", [0.7, 0.8], **Q)
    assert sw.points.shape[1] == 3 and len(sw.label) == 2
    b = vimpact.basins(f, x=("y", [0.0, 0.5]), y=("theta", [0.0, 1.0]), **Q)
    assert b.attractor.shape == (2, 2)
    with pytest.raises(TypeError, match="WakeImpact"):
        vimpact.response(f, "omega", [0.5])
    with pytest.raises(TypeError, match="model must be"):
        vimpact.simulate("not a model")


def test_progress_reports_and_exceptions_from_it():
    seen = []
    vimpact.sweep(W, "Ur", vimpact.grid(16, 25, 6), progress=lambda d, t: seen.append((d, t)), threads=2, **Q)
    assert seen[-1] == (6, 6) and all(t == 6 for _, t in seen)
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)

    def fail(done, total):
        raise RuntimeError("stop here")
    with pytest.raises(RuntimeError, match="stop here"):
        vimpact.sweep(W, "Ur", vimpact.grid(12, 25, 40), progress=fail, threads=2)


def test_long_calls_release_the_gil():
    """While a sweep runs in one thread, another Python thread keeps running."""
    done = threading.Event()
    span = {}

    def work():
        t0 = time.perf_counter()
        vimpact.sweep(W, "Ur", vimpact.grid(12, 25, 40), threads=1, transient=300, record=50)
        span["call"] = time.perf_counter() - t0
        done.set()

    th = threading.Thread(target=work)
    ticks = []
    th.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    th.join()
    # Holding the GIL would stall this thread for the whole call; scheduling noise on a
    # loaded machine is far shorter than a quarter of it.
    assert span["call"] > 0.3, "the call must be long enough to tell"
    stall = max(np.diff(ticks))
    assert stall < span["call"] / 4, f"the main thread stalled for {stall:.3f} s of a {span['call']:.3f} s call"


INTERRUPTED = textwrap.dedent("""
    import sys, time, vimpact
    w = vimpact.WakeImpact()
    print("started", flush=True)
    try:
        {call}
    except KeyboardInterrupt:
        print("KeyboardInterrupt", time.perf_counter(), flush=True)
        raise
    print("finished", flush=True)
""")


@pytest.mark.parametrize("call", [
    "vimpact.sweep(w, 'Ur', vimpact.grid(12, 25, 400), threads=2)",
    "vimpact.simulate(w, transient=10**8)",
    "vimpact.grazing(w, t_max=1e9, transient_time=1e9)",
    "vimpact.lyapunov(w, impacts=10**8)",
])
def test_ctrl_c_raises_keyboard_interrupt_quickly(call):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    proc = subprocess.Popen([sys.executable, "-c", INTERRUPTED.format(call=call)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env)
    assert proc.stdout.readline().strip() == "started"
    time.sleep(0.5)  # well inside the call
    assert proc.poll() is None, "the call finished before it could be interrupted"
    sent = time.perf_counter()
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=30)
    latency = time.perf_counter() - sent
    assert "KeyboardInterrupt" in out and "finished" not in out, out + err
    assert err.rstrip().endswith("KeyboardInterrupt"), err
    assert proc.returncode != 0
    assert latency < 1.0, f"{latency:.3f} s from SIGINT to exit"
    print(f"SIGINT to exit: {latency:.3f} s")


def test_docstrings_state_the_defaults():
    for f in (vimpact.simulate, vimpact.period, vimpact.grazing, vimpact.sweep, vimpact.map, vimpact.basins,
              vimpact.response, vimpact.floquet, vimpact.lyapunov, vimpact.dimension):
        doc = f.__doc__
        assert "$" not in doc and "<protocol>" not in doc
        for section in ("Parameters\n    ----------", "Returns\n    -------"):
            assert section in doc, (f.__name__, section)
    assert f"transient : int, default {vimpact._vimpact.defaults['transient']}" in vimpact.sweep.__doc__
    assert "rtol" in vimpact.WakeImpact.__doc__ or "Ur : float, default" in vimpact.WakeImpact.__doc__
