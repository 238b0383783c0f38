"""What a hostile user tried: each input below once crashed, hung, filled memory or was accepted
silently; each must now end quickly with a clear message (exit 2, nothing written) or with an
outcome in the result."""
import json
import os
import subprocess

import pytest

MAP = ["map", "--x", "Ur:16:25:10", "--y", "sigma:-0.2:-0.1:6", "--transient", "50", "--record", "40"]


def run(vimpact, *args, cwd=None, timeout=120):
    return subprocess.run([vimpact, *args], capture_output=True, text=True, cwd=cwd, timeout=timeout)


def refused(p, needle):
    """Exit 2 with one line naming what is wrong."""
    assert p.returncode == 2, (p.returncode, p.stdout[-300:], p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("vimpact: error: "), p.stderr
    assert needle in lines[0], lines[0]
    assert p.stdout == ""


def no_staging(where):
    assert not [f for f in os.listdir(where) if f.startswith(".vimpact-staging")]


@pytest.mark.parametrize("args,needle", [
    (["period", "--ic", ""], "--ic is given an empty value"),
    (["period", "--set", ""], "--set is given an empty value"),
    (["period", "--section", ""], "--section is given an empty value"),
    (["response", "--param", "Ur", "--range", "16:17:2", "--curves", ""], "--curves is given an empty value"),
    (["period", "--transient", "99999999999999999999"], "--transient = 99999999999999999999 does not fit"),
    (["period", "--transient", "2000000000"], "--transient = 2000000000 is outside its valid range [0, 1e+09]"),
    (["period", "--record", "20000000"], "--record = 20000000 is outside its valid range [1, 1e+07]"),
    (["period", "--set", "Ur=4.9e-324"], "subnormal"),
    (["lyapunov", "--t0", "1e-300"], "t0"),
    (["lyapunov", "--t0", "1e-6"], "t0 must be >= 0.5"),
    (["lyapunov", "--t0", "1e-3", "--time", "1e4"], "t0 must be >= 0.005"),
    (["lyapunov", "--warmup", "99999999"], "--warmup = 99999999 is outside its valid range [0, 1e+06]"),
    (["sweep", "--param", "Ur", "--range", "16:17:2", "--color-by", "periods"], "--color-by: periods not in {none,period}"),
    (["sweep", "--param", "Ur", "--range", "16:17:2", "--color-by", "PERIOD"], "--color-by: PERIOD not in {none,period}"),
])
def test_bad_values_are_refused_before_any_work(vimpact, tmp_path, args, needle):
    out = tmp_path / "out"
    p = run(vimpact, *args, "--out", str(out), timeout=30)
    refused(p, needle)
    assert not out.exists()
    no_staging(tmp_path)


def test_an_empty_out_is_refused(vimpact, tmp_path):
    refused(run(vimpact, "period", "--out", "", cwd=tmp_path), "--out is given an empty value")
    assert os.listdir(tmp_path) == []


def test_a_small_lyapunov_interval_with_a_short_time_runs(vimpact):
    """The bound on t0 follows the averaging time: 0.01 is allowed over 1000 time units."""
    p = run(vimpact, "lyapunov", "--t0", "0.01", "--time", "1000", "--transient", "50", "--json")
    assert p.returncode == 0, p.stderr
    j = json.loads(p.stdout)
    assert j["outcome"] == "ok" and j["t0"] == 0.01


@pytest.mark.parametrize("dt", ["1e-300", "1e-5"])
def test_a_tiny_sampling_interval_ends_with_sample_limit(vimpact, tmp_path, dt):
    """1e-300 cannot advance the time; 1e-5 would need about 1e7 samples: both end with the
    outcome sample_limit and a series of at most a million samples."""
    out = tmp_path / "sim"
    p = run(vimpact, "simulate", "--dt", dt, "--transient", "20", "--record", "20", "--no-plot", "--json",
            "--out", str(out), timeout=60)
    assert p.returncode == 0, p.stderr
    assert json.loads(p.stdout)["outcome"] == "sample_limit"
    with open(out / "timeseries.csv") as f:
        rows = sum(1 for _ in f) - 1
    assert 1 <= rows <= 1_000_000 + 2 * 40  # samples, and the impacts' pre/post states


def test_an_ordinary_sampling_interval_is_untouched(vimpact):
    j = json.loads(run(vimpact, "simulate", "--dt", "0.05", "--transient", "20", "--record", "20", "--json").stdout)
    assert j["outcome"] == "ok"


def test_out_that_holds_a_directory_in_place_of_a_file(vimpact, tmp_path):
    out = tmp_path / "o"
    (out / "plot.png").mkdir(parents=True)
    p = run(vimpact, "period", "--transient", "20", "--record", "20", "--out", str(out))
    refused(p, "plot.png is a directory")
    assert sorted(os.listdir(out)) == ["plot.png"], "nothing of the run is moved in"
    no_staging(tmp_path)


def test_out_with_a_name_too_long(vimpact, tmp_path):
    refused(run(vimpact, "period", "--out", str(tmp_path / ("a" * 300))), "300 characters (at most 255)")
    no_staging(tmp_path)


def test_a_long_out_name_that_is_valid_gets_written(vimpact, tmp_path):
    """250 characters: valid, and its staging directory (a longer name) must not overflow."""
    out = tmp_path / ("b" * 250)
    p = run(vimpact, "period", "--transient", "20", "--record", "20", "--no-plot", "--out", str(out))
    assert p.returncode == 0, p.stderr
    assert (out / "run.json").exists()
    no_staging(tmp_path)


def test_out_at_the_root_is_refused(vimpact):
    refused(run(vimpact, "period", "--out", "/"), "root directory")


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs /proc")
def test_out_where_no_directory_can_be_made(vimpact):
    refused(run(vimpact, "period", "--out", "/proc/vimpact-test"), "cannot create a directory in /proc")


def test_a_killed_runs_staging_directory_is_cleaned_by_the_next_run(vimpact, tmp_path):
    dead = subprocess.Popen(["true"])
    dead.wait()
    stale = tmp_path / f".vimpact-staging-run-{dead.pid}"
    stale.mkdir()
    (stale / "timeseries.csv").write_text("t,y\n")
    p = run(vimpact, "period", "--transient", "20", "--record", "20", "--no-plot", "--out", str(tmp_path / "run"))
    assert p.returncode == 0, p.stderr
    no_staging(tmp_path)


@pytest.mark.parametrize("args", [
    ["simulate", "--transient", "10000000"],
    ["lyapunov", "--impacts", "10000000", "--transient", "20"],
    ["floquet", "--transient", "10000000"],
])
def test_ctrl_c_ends_a_single_run_with_130_and_nothing_written(vimpact, tmp_path, args):
    import signal
    import time
    out = tmp_path / "run"
    proc = subprocess.Popen([vimpact, *args, "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    time.sleep(1.0)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=30)
    assert proc.returncode == 130, err
    assert "interrupted; nothing written" in err
    assert not out.exists()
    no_staging(tmp_path)


def test_a_second_ctrl_c_ends_work_that_does_not_poll(vimpact, tmp_path):
    import signal
    import time
    pts = tmp_path / "p.csv"
    pts.write_text("a,b,c\n" + "".join(f"{(i * 0.618034) % 1},{(i * 0.414214) % 1},{(i * 0.732051) % 1}\n"
                                        for i in range(300000)))
    proc = subprocess.Popen([vimpact, "dimension", "--points", str(pts), "--search", "brute_force",
                             "--max-pairs", "1e12"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    time.sleep(1.5)
    proc.send_signal(signal.SIGINT)
    time.sleep(0.2)
    proc.send_signal(signal.SIGINT)
    proc.communicate(timeout=30)
    assert proc.returncode == -signal.SIGINT


def _journal_file(out):
    jdir = str(out) + ".jobs"
    files = [f for f in os.listdir(jdir) if f.endswith(".jsonl")]
    assert files
    return os.path.join(jdir, files[0])


@pytest.mark.parametrize("line,needle", [
    ('{"job":1}\n', "damaged at line"),
    ('{"job":1,"record":{}}\n', "damaged record of job 1"),
    ('{"job":1,"record":{"label":7}}\n', "damaged record of job 1"),
])
def test_an_edited_journal_is_reported_not_an_internal_error(vimpact, tmp_path, line, needle):
    out = tmp_path / "o"
    assert run(vimpact, *MAP, "--no-plot", "--out", str(out), "--shard", "0/2").returncode == 0
    with open(_journal_file(out), "a") as f:
        f.write(line)
    refused(run(vimpact, *MAP, "--no-plot", "--out", str(out), "--resume"), needle)


def test_a_journal_without_its_spec_is_not_called_a_different_run(vimpact, tmp_path):
    out = tmp_path / "o"
    assert run(vimpact, *MAP, "--no-plot", "--out", str(out), "--shard", "0/2").returncode == 0
    os.remove(os.path.join(str(out) + ".jobs", "spec.json"))
    p = run(vimpact, *MAP, "--no-plot", "--out", str(out), "--resume")
    refused(p, "has no spec.json")
    assert "different run" not in p.stderr


def test_control_bytes_of_a_points_file_are_not_echoed(vimpact, tmp_path):
    bad = tmp_path / "points.bin"
    bad.write_bytes(b"\x1b[2J\x07\x00garbage\x01\x02\n\x1b]0;x\x07\n")
    p = run(vimpact, "dimension", "--points", str(bad))
    assert p.returncode == 2
    assert not any(ord(c) < 0x20 and c != "\n" for c in p.stderr), repr(p.stderr)


@pytest.mark.parametrize("command", [["sweep", "--param", "Ur", "--range", "16:17:2"],
                                     ["dimension", "--set", "Ur=16"]])
def test_one_thread_rule_for_every_command(vimpact, command):
    refused(run(vimpact, *command, "--threads", "10000"), "threads = 10000 is outside its valid range [0, 1024]")


def test_two_points_are_too_few_for_a_dimension(vimpact, tmp_path):
    pts = tmp_path / "p.csv"
    pts.write_text("x,y\n0,0\n1,1\n")
    refused(run(vimpact, "dimension", "--points", str(pts)), "the dimension needs at least 3 points (got 2)")


@pytest.mark.parametrize("fmt,magic", [("svg", b"<?xml"), ("pdf", b"%PDF")])
def test_picture_formats(vimpact, tmp_path, fmt, magic):
    out = tmp_path / "o"
    p = run(vimpact, "period", "--transient", "20", "--record", "20", "--format", fmt, "--out", str(out))
    assert p.returncode == 0, p.stderr
    assert (out / f"plot.{fmt}").read_bytes().startswith(magic)
    assert not (out / "plot.png").exists()
    assert f"plot.{fmt}" in json.loads((out / "run.json").read_text())["files"]


def test_an_unknown_picture_format_is_refused(vimpact, tmp_path):
    refused(run(vimpact, "period", "--format", "gif", "--out", str(tmp_path / "o")), "--format 'gif' is not one of png, pdf, svg")


# ---------------------------------------------------------------- the picture's Python

def test_the_picture_imports_nothing_from_the_working_directory_or_pythonpath(vimpact, tmp_path):
    from conftest import PLOTS, need
    need("plots", PLOTS, "the plotting package cannot run here")
    marker = tmp_path / "marker"
    planted = tmp_path / "planted"
    planted.mkdir()
    for where in (tmp_path, planted):
        for name in ("numpy", "matplotlib", "vimpact"):
            (where / f"{name}.py").write_text(f"open({str(marker)!r}, 'a').write({name!r} + ' ')\n")
    env = dict(os.environ, PYTHONPATH=str(planted))
    p = subprocess.run([vimpact, "period", "--transient", "20", "--record", "20", "--out", "o"], cwd=tmp_path,
                       env=env, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert not marker.exists(), f"planted modules ran: {marker.read_text()}"
    assert (tmp_path / "o" / "plot.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "plot.png" in json.loads((tmp_path / "o" / "run.json").read_text())["files"]


def test_a_failed_picture_is_one_line_and_the_results_are_kept(vimpact, tmp_path):
    from conftest import PLOTS, need
    need("plots", PLOTS, "the plotting package cannot run here")
    # The user's matplotlib configuration asks for LaTeX text with a preamble no TeX accepts
    # (or no TeX at all): every picture fails while it is drawn.
    mpl = tmp_path / "mpl"
    mpl.mkdir()
    (mpl / "matplotlibrc").write_text("text.usetex: True\ntext.latex.preamble: \\undefinedcontrolsequence\n")
    out = tmp_path / "o"
    p = subprocess.run([vimpact, "period", "--transient", "20", "--record", "20", "--out", str(out), "--json"],
                       env=dict(os.environ, MPLCONFIGDIR=str(mpl)), capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr  # the numbers are the result: written, exit 0
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1, p.stderr
    assert lines[0].startswith("vimpact: warning: the picture could not be made (")
    assert "vimpact.plot period failed: " in lines[0] and f"the results are written to {out}" in lines[0]
    assert "Traceback" not in p.stderr
    assert json.loads(p.stdout)["label"]
    files = json.loads((out / "run.json").read_text())["files"]
    assert "plot.png" not in files and not (out / "plot.png").exists()
    assert all((out / f).exists() for f in files)
