"""The Python API itself: documented shapes and dtypes, determinism across thread counts,
journals (resume after a stop, shards), the GIL released during long calls, progress reports,
Ctrl-C, docstrings."""
import json
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
    m = vimpact.WakeImpact(Ur=21.5)
    s = vimpact.simulate(m, sample_dt=0.1, **Q)
    n, k, ts = len(s.section_t), len(s.impact_t), len(s.series_t)
    assert n == Q["record"] and k > 0 and ts > 0
    check(s.section, (n, 4), np.float64)
    check(s.section_t, (n,), np.float64)
    check(s.impact_pre, (k, 4), np.float64)
    check(s.impact_post, (k, 4), np.float64)
    check(s.impact_surface, (k,), np.int64)
    check(s.series, (ts, 4), np.float64)
    check(s.final_state, (4,), np.float64)
    assert s.state_names == ("y", "ydot", "x", "xdot") and s.plot_variable == "y" and s.surfaces == ("barrier",)
    assert (np.diff(s.section_t) > 0).all() and (np.diff(s.series_t) >= 0).all()
    assert (s.section[:, 1] == 0).all(), "on the section ydot = 0 exactly"
    # Impacts happen on the barrier and reverse the velocity with the restitution factor.
    np.testing.assert_allclose(s.impact_pre[:, 0], m.sigma, atol=1e-12)
    np.testing.assert_array_equal(s.impact_post[:, 1], -m.r * s.impact_pre[:, 1])
    assert s.outcome == "ok" and s.stats.steps > 0 and s.stats.impacts_by_surface == {"barrier": s.stats.impacts}
    assert vimpact.simulate(m, **Q).series.shape == (0, 4)
    assert vimpact.simulate(m, section="minima", **Q).options["section"] == "minima"


def test_period_shapes():
    p = vimpact.period(vimpact.WakeImpact(Ur=19), **Q)
    check(p.cycle, (p.period, 4), np.float64)
    assert p.label == f"P{p.period}" and p.impacts_by_surface == {"barrier": p.impacts}
    assert p.state_names == ("y", "ydot", "x", "xdot") and p.parameters["Ur"] == 19
    q = vimpact.period(W.with_(sigma=-0.3), **Q)
    assert (q.label, q.period) == ("P0", 0) and q.cycle.shape == (0, 4)


def test_sweep_shapes_and_dtypes():
    s = vimpact.sweep(W, "Ur", vimpact.grid(15, 16, 3), ic_mode="follow", direction="both", **Q)
    runs = 6
    for name in ("branch", "period", "impacts", "steps"):
        check(getattr(s, name), (runs,), np.int64)
    for name in ("value", "closure"):
        check(getattr(s, name), (runs,), np.float64)
    for name in ("label", "outcome"):
        check(getattr(s, name), (runs,), str)
    check(s.impacts_by_surface, (runs, 1), np.int64)
    check(s.grazing, (runs, 1), np.float64)
    check(s.final_state, (runs, 4), np.float64)
    P = len(s.points)
    assert P == runs * Q["record"]
    check(s.points, (P, 4), np.float64)
    check(s.point_run, (P,), np.int64)
    check(s.point_value, (P,), np.float64)
    assert np.isnan(s.grazing).all() and s.grazing_param is None, "no grazing asked"
    assert sum(s.label_counts.values()) == runs
    assert s.jobs.complete and s.jobs.computed == runs and s.stats["wall_time"] > 0
    g = vimpact.sweep(W, "Ur", [16, 17], grazing=True, **Q)
    assert g.grazing_param == "sigma" and np.isfinite(g.grazing).all()


def test_map_and_basins_shapes():
    m = vimpact.map(W, x=("Ur", [16, 20, 24]), y=("sigma", [-0.15, -0.1]), **Q)
    for name in ("label", "outcome"):
        check(getattr(m, name), (2, 3), str)
    for name in ("period", "impacts", "steps"):
        check(getattr(m, name), (2, 3), np.int64)
    check(m.closure, (2, 3), np.float64)
    check(m.impacts_by_surface, (2, 3, 1), np.int64)
    assert m.grazing is None and m.grazing_param is None
    g = vimpact.map(W, x=("Ur", [16, 20, 24]), y=("sigma", [-0.15, -0.1]), grazing=True, **Q)
    assert g.grazing_param == "sigma"
    check(g.grazing_other, (3,), np.float64)
    check(g.grazing, (3, 1), np.float64)
    b = vimpact.basins(vimpact.WakeImpact(Ur=14.9), x=("y", [-0.2, 0.0, 0.2]), y=("ydot", [0.0, 0.1]), **Q)
    check(b.attractor, (2, 3), np.int64)
    check(b.label, (2, 3), str)
    assert (b.attractor[:, 0] == -1).all() and (b.label[:, 0] == "inadmissible").all()
    assert sum(a.cells for a in b.attractors) == b.attractor.size - b.inadmissible_cells
    for a in b.attractors:
        assert a.cycle.ndim == 2 and a.cycle.shape[1] == 4 and a.box.shape == (2, 4)


def test_response_shapes():
    r = vimpact.response(W, "Ur", [5, 6], curves=[{"A": 12, "eps": 0.3}, {"A": 10, "eps": 0.25}, {"A": 14}],
                         transient_time=300)
    for name in ("amplitude", "maximum", "minimum", "frequency"):
        check(getattr(r, name), (3, 2), np.float64)
    check(r.converged, (3, 2), np.bool_)
    check(r.outcome, (3, 2), str)
    check(r.grazing, (3, 2, 1), np.float64)
    assert r.variable == "y" and r.grazing_param == "sigma" and r.curves[2] == {"A": 14.0}
    # amplitude = max(|maximum|, |minimum|), the library's definition; the grazing value of
    # sigma is the minimum of y.
    np.testing.assert_array_equal(r.amplitude, np.maximum(np.abs(r.maximum), np.abs(r.minimum)))
    np.testing.assert_array_equal(r.grazing[:, :, 0], r.minimum)
    with pytest.raises(vimpact.InputError, match="unknown parameter 'B' for curves"):
        vimpact.response(W, "Ur", [5], curves=[{"B": 1}])


def test_stability_and_dimension_shapes():
    f = vimpact.floquet(vimpact.WakeImpact(Ur=16), sample_dt=0.05, **Q)
    check(f.multipliers, (4,), np.complex128)
    check(f.monodromy, (4, 4), np.float64)
    check(f.orbit_point, (4,), np.float64)
    assert f.orbit.shape == (len(f.orbit_t), 4) and len(f.orbit_t) > 0
    assert f.impact_pre.shape == (f.impacts_per_period, 4) and f.impacts_by_surface == {"barrier": 1}
    assert abs(f.multipliers[0] - 1) < 1e-8  # the flow direction: 1 for an autonomous flow
    assert f.det_monodromy == pytest.approx(f.liouville_det, rel=1e-6)
    a = vimpact.floquet(vimpact.WakeImpact(Ur=18.426), **Q)  # the paper's chaotic point (Fig. 6a)
    assert (a.status, a.label) == ("aperiodic", "aperiodic")
    assert a.multipliers.shape == (0,) and a.stable is None and np.isnan(a.period)
    ly = vimpact.lyapunov(vimpact.WakeImpact(Ur=16), impacts=40, transient=60, record=10)
    check(ly.exponents, (4,), np.float64)
    h = len(ly.history_t)
    check(ly.history_growth, (h, 4), np.float64)
    check(ly.section, (10, 4), np.float64)
    assert ly.running_exponents.shape == (h, 4)
    np.testing.assert_allclose(ly.running_exponents[-1], np.sort(ly.exponents)[::-1], rtol=1e-12, atol=1e-15)
    assert ly.exponents.sum() == pytest.approx(ly.sum_rule, abs=1e-6)
    fs = vimpact.floquet_sweep(W, "Ur", [16, 18.426], **Q)
    check(fs.multipliers, (2, 4), np.complex128)
    assert fs.label.tolist() == ["P2", "aperiodic"] and np.isnan(fs.multipliers[1]).all()
    # The library's verdict, against the multipliers themselves: none without them.
    assert fs.stable.tolist() == [bool(np.all(np.abs(fs.multipliers[0][1:]) < 1)), None]
    assert fs.points.shape == (2 * Q["record"], 4)
    ls = vimpact.lyapunov_sweep(W, "Ur", [16, 17], impacts=30, transient=60, record=5)
    check(ls.exponents, (2, 4), np.float64)
    assert ls.points.shape == (10, 4) and ls.lle.shape == (2,)
    rng = np.random.default_rng(5)
    d = vimpact.dimension(rng.random((3000, 2)))
    k = len(d.r)
    check(d.r, (k,), np.float64)
    check(d.pairs, (k,), np.int64)
    check(d.local_slope, (k,), np.float64)
    assert d.dimension == pytest.approx(2.0, abs=0.1)
    s = vimpact.simulate(vimpact.WakeImpact(Ur=16), **Q)
    # The library's coordinates of a state, as the command line takes them: every variable.
    assert vimpact.dimension(s, min_pairs=1).columns == ("y", "ydot", "x", "xdot")
    assert vimpact.dimension(s, columns=("y", "x"), min_pairs=1).points == len(s.section)
    phases = vimpact.simulate(vimpact.TwoSidedImpactOscillator(), **Q)
    assert vimpact.dimension(phases, min_pairs=1).columns == ("x", "v", "phi_cos", "phi_sin")
    with pytest.raises(ValueError, match="2-D"):
        vimpact.dimension(np.zeros(5))


@pytest.mark.parametrize("record,run,in_stats", [
    ("floquet", lambda: vimpact.floquet(vimpact.WakeImpact(Ur=16), **Q),
     {"protocol_stats", "tangent_stats", "map_evaluations"}),
    ("lyapunov", lambda: vimpact.lyapunov(vimpact.WakeImpact(Ur=16), impacts=30, transient=60, record=5),
     {"transient_stats", "stats"}),
    ("period", lambda: vimpact.period(vimpact.WakeImpact(Ur=19), **Q), set()),
    ("run_stats", lambda: vimpact.simulate(vimpact.WakeImpact(Ur=19), **Q).stats, set())])
def test_a_single_runs_record_is_the_librarys_description(record, run, in_stats):
    # Every field the library describes (but the counters, which are the result's stats) is
    # in the result's record, an attribute (section points as ``section``, with their times)
    # and documented; a per-surface one is a dict by surface name.
    r = run()
    fields = [f for f in vimpact._vimpact.described[record] if f["name"] not in in_stats]
    series = {f["name"] + "_t" for f in fields if f["span"] == "series"}
    assert set(r.record) == {f["name"] for f in fields} | series
    for f in fields:
        name = "section" if f["name"] == "section_points" else f["name"]
        assert getattr(r, name) is r.record[f["name"]] and f"\n{name} : " in type(r).__doc__, name
        if f["span"] == "per_surface":
            assert set(getattr(r, name)) == {"barrier"}, name
    if series:
        assert len(r.section_t) == len(r.section) > 0 and np.all(np.diff(r.section_t) > 0)


def test_results_do_not_depend_on_the_thread_count():
    values = vimpact.grid(20, 25, 7)
    runs = [vimpact.sweep(W, "Ur", values, threads=t, grazing=True, **Q) for t in (1, 2)]
    for name in ("label", "closure", "points", "point_run", "grazing", "final_state", "steps"):
        np.testing.assert_array_equal(getattr(runs[1], name), getattr(runs[0], name))
    assert (runs[0].stats["threads"], runs[1].stats["threads"]) == (1, 2)
    follow = [vimpact.sweep(W, "Ur", vimpact.grid(14.5, 15.5, 4), ic_mode="follow", direction="both", threads=t, **Q)
              for t in (1, 2)]
    np.testing.assert_array_equal(follow[0].points, follow[1].points)
    two = vimpact.TwoSidedImpactOscillator()
    for call in (lambda t: vimpact.map(two, x=("w", [1.1, 1.3, 1.5]), y=("d", [0.9, 1.5]), grazing=True, threads=t,
                                       **Q),
                 lambda t: vimpact.basins(two, x=("x", [-0.5, 0.0, 0.5]), y=("v", [-0.5, 0.5]), threads=t, **Q),
                 lambda t: vimpact.response(two, "w", [1.1, 1.2, 1.3], threads=t),
                 lambda t: vimpact.floquet_sweep(two, "w", [1.1, 1.2, 1.3], threads=t, **Q),
                 lambda t: vimpact.lyapunov_sweep(two, "w", [1.1, 1.2], impacts=20, transient=40, threads=t)):
        a, b = call(1), call(2)
        for name in ("label", "attractor", "amplitude", "grazing", "multipliers", "exponents"):
            if hasattr(a, name) and getattr(a, name) is not None:
                np.testing.assert_array_equal(getattr(a, name), getattr(b, name))


def test_a_stopped_sweep_resumes_from_its_journal(tmp_path):
    values = vimpact.grid(14, 25, 12)
    whole = vimpact.sweep(W, "Ur", values, threads=2, grazing=True, **Q)
    journal = tmp_path / "journal"

    def stop_after_four(done, total):
        if done >= 4:
            raise KeyboardInterrupt  # what Ctrl-C raises in the same place
    with pytest.raises(KeyboardInterrupt):
        vimpact.sweep(W, "Ur", values, threads=2, grazing=True, journal=journal, progress=stop_after_four, **Q)
    assert journal.is_dir(), "the finished jobs stay in the journal"
    with pytest.raises(vimpact.InputError, match="journal"):
        vimpact.sweep(W, "Ur", values, threads=2, grazing=True, journal=journal, **Q)  # not resumed by mistake
    with pytest.raises(vimpact.InputError):
        vimpact.sweep(W, "Ur", values, threads=2, grazing=False, journal=journal, resume=True, **Q)  # another run
    resumed = vimpact.sweep(W, "Ur", values, threads=1, grazing=True, journal=journal, resume=True, **Q)
    assert resumed.jobs.resumed >= 4 and resumed.jobs.resumed + resumed.jobs.computed == 12
    assert not journal.exists(), "a complete run removes its journal"
    for name in ("branch", "value", "label", "closure", "grazing", "points", "point_run", "final_state", "steps"):
        np.testing.assert_array_equal(getattr(resumed, name), getattr(whole, name))


@pytest.mark.parametrize("call", [
    lambda **kw: vimpact.floquet_sweep(W, "Ur", [16, 17, 18.426, 19], **Q, **kw),
    lambda **kw: vimpact.lyapunov_sweep(W, "Ur", [16, 17, 18, 19], impacts=30, transient=60, record=5, **kw)],
    ids=["floquet", "lyapunov"])
def test_a_stopped_stability_sweep_resumes_its_records_bit_for_bit(tmp_path, call):
    # The points read back from the journal are the points run: every field of the records.
    whole, journal = call(threads=2), tmp_path / "journal"

    def stop_after_two(done, total):
        if done >= 2:
            raise KeyboardInterrupt
    with pytest.raises(KeyboardInterrupt):
        call(threads=2, journal=journal, progress=stop_after_two)
    resumed = call(threads=1, journal=journal, resume=True)
    assert resumed.jobs.resumed >= 2 and resumed.jobs.resumed + resumed.jobs.computed == 4
    for name, column in whole.records.items():
        if isinstance(column, dict):
            for k in column:
                np.testing.assert_array_equal(resumed.records[name][k], column[k], err_msg=f"{name}.{k}")
        else:
            np.testing.assert_array_equal(resumed.records[name], column, err_msg=name)


def test_shards_meet_in_a_journal(tmp_path):
    two = vimpact.TwoSidedImpactOscillator()
    grid = dict(x=("w", [1.0, 1.1, 1.2, 1.3]), y=("d", [0.9, 1.5]), **Q)
    journal = tmp_path / "map.jobs"
    first = vimpact.map(two, **grid, journal=journal, shard=(0, 2))
    assert isinstance(first, vimpact.JobReport) and not first.complete and first.computed == 4
    second = vimpact.map(two, **grid, journal=journal, shard=(1, 2), keep_journal=True)
    assert second.jobs.complete and second.jobs.computed == 4
    again = vimpact.map(two, **grid, journal=journal, resume=True)
    assert again.jobs.computed == 0 and again.jobs.resumed == 8
    np.testing.assert_array_equal(again.label, vimpact.map(two, **grid).label)
    with pytest.raises(vimpact.InputError, match="shard"):
        vimpact.map(two, **grid, shard=(0, 2))  # a shard without a journal


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
        vimpact.sweep(W, "Ur", vimpact.grid(12, 25, 80), threads=1, transient=500, record=100)
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
    "vimpact.floquet(w, transient=10**8)",
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


def test_docstrings_state_the_defaults():
    for f in (vimpact.simulate, vimpact.period, vimpact.grazing, vimpact.sweep, vimpact.map, vimpact.basins,
              vimpact.response, vimpact.floquet, vimpact.lyapunov, vimpact.floquet_sweep, vimpact.lyapunov_sweep,
              vimpact.dimension):
        doc = f.__doc__
        assert "$" not in doc and "<protocol>" not in doc and "<jobs>" not in doc, f.__name__
        for section in ("Parameters\n    ----------", "Returns\n    -------"):
            assert section in doc, (f.__name__, section)
        assert f.__module__ == "vimpact"
    assert f"transient : int, default {vimpact._vimpact.defaults['transient']}" in vimpact.sweep.__doc__
    assert "journal : str or path" in vimpact.map.__doc__
    assert "Parameters" in vimpact.Model.__doc__


def test_wrong_types_are_type_errors():
    with pytest.raises(TypeError, match="vimpact.Model"):
        vimpact.simulate("not a model")
    with pytest.raises(TypeError, match="pair"):
        vimpact.map(W, x="Ur", y=("sigma", [0]))


def test_without_the_compiled_module_results_and_plots_still_import(tmp_path):
    """The command line draws its PNGs with vimpact.plot where the extension is not built."""
    pkg = tmp_path / "vimpact"
    pkg.mkdir()
    src = os.path.dirname(vimpact.__file__)
    for name in os.listdir(src):
        if name.endswith(".py"):
            (pkg / name).write_text(open(os.path.join(src, name)).read())
    code = ("import vimpact, vimpact.plot, vimpact.results\n"
            "print(vimpact.__version__)\n"
            "try:\n    vimpact.Model\nexcept ImportError as e:\n    print(e)\n"
            "try:\n    from vimpact import simulate\nexcept ImportError as e:\n    print('from-import:', e)\n")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path,
                       env=dict(os.environ, PYTHONPATH=str(tmp_path), MPLBACKEND="Agg"))
    assert p.returncode == 0, p.stderr
    assert "not built" in p.stdout and "cmake --build build --target _vimpact" in p.stdout
    assert "pip install --no-build-isolation ." in p.stdout
    assert "from-import: vimpact.simulate needs the compiled module vimpact._vimpact" in p.stdout


def test_labels_read_in_the_librarys_order():
    # As the command line's summaries print them (label_before in the library): by period,
    # P2 before P10, then aperiodic, then failed runs' outcomes.
    shuffled = ["P10", "non_finite", "aperiodic", "P2", "P32", "P0", "chattering", "P1", "P2"]
    assert vimpact.results.label_order(shuffled) == ["P0", "P1", "P2", "P10", "P32", "aperiodic", "chattering",
                                                     "non_finite"]


def test_an_output_directory_without_a_tables_schema_says_so(tmp_path):
    # A lyapunov sweep written before run.json described its tables (and before the verdict
    # column existed).
    out = tmp_path / "old"
    out.mkdir()
    (out / "run.json").write_text(json.dumps({"command": "lyapunov", "state_names": ["y", "ydot", "x", "xdot"],
                                              "model": {"name": "wake_impact"},
                                              "result": {"param": "Ur", "tdm": "saltation"}}))
    (out / "exponents.csv").write_text("Ur,lambda1,lambda2,lambda3,lambda4,lle_standard_error,settled,outcome\n"
                                       "14,0.1,-0.1,-0.3,-1.3,0.01,1,ok\n")
    with pytest.raises(ValueError, match=r"does not describe its tables: it was written by an older vimpact"):
        vimpact.LyapunovSweep.load(str(out))


def test_an_output_directory_without_what_this_vimpact_writes_says_so(tmp_path):
    # A lyapunov run written before run.json held the library's verdict on the exponents.
    (tmp_path / "run.json").write_text(json.dumps({"command": "lyapunov", "model": {"name": "wake_impact"},
                                                   "result": {"outcome": "ok", "exponents": [0.1], "t_start": 0}}))
    (tmp_path / "convergence.csv").write_text("t,lambda1\n1,0.1\n")
    with pytest.raises(ValueError, match=r"has no 'positive': it was written by an older vimpact"):
        vimpact.Lyapunov.load(str(tmp_path))


def test_continuation_keywords_are_the_librarys_declaration():
    """vimpact.continuation's step and tolerance keywords come from the library's declaration,
    which refuses a value out of range naming the keyword before any run."""
    import inspect
    declared = {e["key"]: e for e in vimpact._vimpact.declared["continuation"]}
    assert set(declared) >= {"period", "switch", "tol", "ds", "ds_min", "ds_max", "max_points", "closure_tol",
                             "newton_iterations", "locate_tol", "detect"}
    sig = inspect.signature(vimpact.continuation)
    for key, e in declared.items():
        assert sig.parameters[key].default == e["default"] and f"    {key} : " in vimpact.continuation.__doc__
    assert sig.parameters["detect"].default is True
    with pytest.raises(vimpact.InputError, match=r"^max_points = 1 is outside its valid range \[2, 1e\+06\]$"):
        vimpact.continuation(vimpact.WakeImpact(), "Ur", (14, 15), max_points=1)
    with pytest.raises(vimpact.InputError, match=r"^switch = 9 is outside its valid range \[0, 8\]$"):
        vimpact.continuation(vimpact.WakeImpact(), "Ur", (14, 15), switch=9)


def test_lyapunov_keywords_are_the_librarys_declaration():
    """The keyword arguments of vimpact.lyapunov and lyapunov_sweep, their defaults and their
    documentation come from the library's declaration (core/option.hpp), and the library
    refuses a value out of range naming the keyword."""
    import inspect
    declared = vimpact._vimpact.declared["lyapunov"]
    assert {e["key"] for e in declared} >= {"tdm", "r0", "t0", "impacts", "time", "warmup", "p0_time", "max_time",
                                             "divergence"}
    for f in (vimpact.lyapunov, vimpact.lyapunov_sweep):
        sig = inspect.signature(f)
        for e in declared:
            p = sig.parameters[e["key"]]
            assert p.kind == p.KEYWORD_ONLY and p.default == e["default"], e
            assert f"    {e['key']} : " in f.__doc__, e["key"]
        assert "declared" not in sig.parameters
    assert inspect.signature(vimpact.lyapunov).parameters["r0"].default == 1e-4  # the paper's
    with pytest.raises(vimpact.InputError, match=r"^r0 = 2 is outside its valid range \(0, 1\)$"):
        vimpact.lyapunov(vimpact.WakeImpact(), r0=2.0)
    with pytest.raises(vimpact.InputError, match=r"warmup = -1 is outside its valid range \[0, 1e\+06\]"):
        vimpact.lyapunov(vimpact.WakeImpact(), warmup=-1)
    with pytest.raises(TypeError, match="r1"):
        vimpact.lyapunov(vimpact.WakeImpact(), r1=1e-4)



def test_floquet_keywords_are_the_librarys_declaration():
    import inspect
    declared = vimpact._vimpact.declared["floquet"]
    assert {e["key"] for e in declared} == {"tol", "newton_tol", "newton_iterations", "impact_map"}
    for f in (vimpact.floquet, vimpact.floquet_sweep):
        sig = inspect.signature(f)
        for e in declared:
            assert sig.parameters[e["key"]].default == e["default"], e
            assert f"    {e['key']} : " in f.__doc__, e["key"]
    assert inspect.signature(vimpact.floquet).parameters["tol"].default == 1e-8  # the paper's Figures 2, 5
    with pytest.raises(vimpact.InputError, match=r"^newton_iterations = 1001 is outside its valid range \[0, 1000\]$"):
        vimpact.floquet(vimpact.WakeImpact(), newton_iterations=1001)
    with pytest.raises(vimpact.InputError, match=r"impact_map 'none' is not one of saltation, reset-jacobian, identity"):
        vimpact.floquet(vimpact.WakeImpact(), impact_map="none")
