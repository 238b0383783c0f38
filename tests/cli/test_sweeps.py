"""The job-loop commands end to end: determinism across thread counts, shards, resume after a
kill or Ctrl-C, the JSON contract, files written and bad input."""
import json
import os
import signal
import subprocess
import time

import pytest

from conftest import check_png
from test_cli import run, run_json

# Small but real: 60 map cells of the paper's Fig. 4 region with a short protocol.
MAP = ["map", "--x", "Ur:16:25:10", "--y", "sigma:-0.16:-0.02:6", "--transient", "100", "--record", "40",
       "--tol", "1e-5"]

# The impact statistics' columns of every labels table (docs/model.md).
STATISTICS = ["impacts_recorded", "duration", "impact_rate", "impact_velocity_min", "impact_velocity_mean",
              "impact_velocity_rms", "impact_velocity_max", "energy_per_impact", "power", "contact_fraction", "excursion"]


def read(path):
    with open(path) as f:
        return f.read()


def test_sweep_json_contract_and_paper_labels(vimpact):
    j = run_json(vimpact, "sweep", "--param", "Ur", "--range", "16:19:2")
    assert j["labels"] == [[16.0, "P2"], [19.0, "P3"]]
    assert j["section_points"] == 400
    assert j["label_counts"] == {"P2": 1, "P3": 1}


def read_rows(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
        return header, [dict(zip(header, line.strip().split(","))) for line in f]


def test_sweep_files_carry_impacts_by_surface_and_grazing(vimpact, tmp_path):
    out = tmp_path / "s"
    p = run(vimpact, "sweep", "--param", "Ur", "--range", "16:19:2", "--grazing", "--no-plot", "--out", str(out))
    assert p.returncode == 0, p.stderr
    header, rows = read_rows(out / "labels.csv")
    assert header == ["branch", "Ur", "label", "period", "impacts", "closure", "settled", "impacts_barrier",
                      "outcome", "sigma_graze", *STATISTICS, "excursion_barrier"]
    # run.json describes every column: what a reader needs besides the file.
    schema = json.loads((out / "run.json").read_text())["tables"]["labels.csv"]["columns"]
    assert [c["name"] for c in schema] == header
    by = {c["name"]: c for c in schema}
    assert by["Ur"]["field"] == "value" and by["settled"]["type"] == "bool"
    assert by["sigma_graze"]["field"] == "grazing" and by["sigma_graze"]["surface"] == 0
    assert by["power"]["group"] == "statistics" and by["power"]["unit"] == "(g/t)^2/t"
    assert [r["label"] for r in rows] == ["P2", "P3"]
    for r in rows:
        assert int(r["impacts_barrier"]) == int(r["impacts"]) == 1
        assert float(r["sigma_graze"]) < -0.1
    assert read_rows(out / "points.csv")[0] == ["branch", "Ur", "y", "ydot", "x", "xdot"]
    record = json.loads((out / "run.json").read_text())
    assert record["result"]["grazing_param"] == "sigma"
    # Without --grazing the column stays, empty.
    out2 = tmp_path / "s2"
    assert run(vimpact, "sweep", "--param", "Ur", "--range", "16:19:2", "--no-plot", "--out", str(out2)).returncode == 0
    header2, rows2 = read_rows(out2 / "labels.csv")
    assert header2 == header
    assert all(r["sigma_graze"] == "nan" for r in rows2)


@pytest.mark.parametrize("given,stored", [([], "none"), (["--color-by", "none"], "none"),
                                          (["--color-by", "period"], "period")])
def test_sweep_colour_option_and_the_models_quantities_are_in_run_json(vimpact, tmp_path, given, stored):
    """The picture is drawn from run.json: it holds --color-by (python3 -m vimpact.plot sweep DIR
    reads it) and the meaning and unit of every state variable and parameter (the axis labels),
    as the model states them."""
    out = tmp_path / "s"
    p = run(vimpact, "sweep", "--param", "Ur", "--range", "14:20:4", "--transient", "60", "--record", "20",
            *given, "--out", str(out))
    assert p.returncode == 0, p.stderr
    record = json.loads(read(out / "run.json"))
    assert record["plot_options"] == {"color_by": stored}
    model = run_json(vimpact, "models", "wake_impact")["models"][0]
    assert record["model"]["state_info"] == [{k: v[k] for k in ("name", "meaning", "unit")} for v in model["state"]]
    assert record["model"]["parameter_info"] == {v["name"]: {"meaning": v["meaning"], "unit": v["unit"]}
                                                 for v in model["parameters"]}
    assert "plot.png" in record["files"]
    check_png(out / "plot.png")


def test_sweep_is_identical_for_any_thread_count(vimpact, tmp_path):
    args = ["sweep", "--param", "Ur", "--range", "20:25:11", "--transient", "200", "--no-plot"]
    p1 = run(vimpact, *args, "--threads", "1", "--out", str(tmp_path / "t1"))
    p2 = run(vimpact, *args, "--threads", "2", "--out", str(tmp_path / "t2"))
    p5 = run(vimpact, *args, "--threads", "5", "--out", str(tmp_path / "t5"))
    assert p1.returncode == p2.returncode == p5.returncode == 0, p1.stderr + p2.stderr + p5.stderr
    for name in ("points.csv", "labels.csv"):
        assert read(tmp_path / "t1" / name) == read(tmp_path / "t2" / name) == read(tmp_path / "t5" / name)


def test_follow_mode_both_directions(vimpact, tmp_path):
    j = run_json(vimpact, "sweep", "--param", "Ur", "--range", "14.5:15.5:5", "--ic-mode", "follow",
                 "--direction", "both", "--transient", "200")
    assert [v for v, _ in j["labels"]] == [14.5, 14.75, 15.0, 15.25, 15.5]
    assert [v for v, _ in j["labels_down"]] == [15.5, 15.25, 15.0, 14.75, 14.5]
    # Deterministic with two threads running the two branches at once.
    k = run_json(vimpact, "sweep", "--param", "Ur", "--range", "14.5:15.5:5", "--ic-mode", "follow",
                 "--direction", "both", "--transient", "200", "--threads", "1")
    assert j == k


def test_map_shards_combine_to_the_whole(vimpact, tmp_path):
    whole = tmp_path / "whole"
    p = run(vimpact, *MAP, "--no-plot", "--out", str(whole))
    assert p.returncode == 0, p.stderr
    sharded = tmp_path / "sharded"
    for i in range(3):
        q = run(vimpact, *MAP, "--no-plot", "--out", str(sharded), "--shard", f"{i}/3", "--threads", "1")
        assert q.returncode == 0, q.stderr
        # Only the last shard to finish writes the result.
        assert os.path.exists(sharded / "labels.csv") == (i == 2)
    assert read(whole / "labels.csv") == read(sharded / "labels.csv")
    assert not os.path.exists(str(sharded) + ".jobs"), "the journal is removed when the run is complete"


@pytest.mark.parametrize("shards", [2, 3])
def test_shards_started_at_the_same_moment_write_the_result_once(vimpact, tmp_path, shards):
    # Each round starts every shard at once into one directory: the journal must appear once,
    # no shard may call it another run's, and exactly one complete result must be written.
    # (Before the completion lock, 3 of 29 such starts failed and some rounds wrote nothing.)
    whole = tmp_path / "whole"
    assert run(vimpact, *MAP, "--no-plot", "--out", str(whole), "--threads", "1").returncode == 0
    expected = read(whole / "labels.csv")
    for round_ in range(8):
        out = tmp_path / f"o{round_}"
        procs = [subprocess.Popen([vimpact, *MAP, "--no-plot", "--out", str(out), "--shard", f"{i}/{shards}",
                                   "--threads", "1"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                 for i in range(shards)]
        results = [p.communicate(timeout=300) + (p.returncode,) for p in procs]
        assert [r[2] for r in results] == [0] * shards, [r[1] for r in results]
        assert sum("output written to" in r[0] for r in results) == 1, "exactly one shard writes the result"
        assert read(out / "labels.csv") == expected
        assert not os.path.exists(str(out) + ".jobs")
        assert not [f for f in os.listdir(tmp_path) if ".new-" in f], "no journal made aside is left"


def test_rerun_with_resume_combines_shards_and_fills_gaps(vimpact, tmp_path):
    whole = tmp_path / "whole"
    assert run(vimpact, *MAP, "--no-plot", "--out", str(whole)).returncode == 0
    out = tmp_path / "partial"
    q = run(vimpact, *MAP, "--no-plot", "--out", str(out), "--shard", "1/4")
    assert q.returncode == 0 and not os.path.exists(out)
    r = run(vimpact, *MAP, "--no-plot", "--out", str(out), "--resume")
    assert r.returncode == 0, r.stderr
    assert read(whole / "labels.csv") == read(out / "labels.csv")


def journal_lines(out):
    total = 0
    jdir = str(out) + ".jobs"
    if os.path.isdir(jdir):
        for f in os.listdir(jdir):
            if f.endswith(".jsonl"):
                total += read(os.path.join(jdir, f)).count("\n")
    return total


FAULT = "VIMPACT_TEST_JOURNAL_FAULT"


def with_fault(fault):
    """The environment of a run that interrupts itself at a chosen point of its journal's writing
    (the library's test hook, docs/sweeps.md "Testing interruptions"): "K:pause" waits after
    the K-th line until a signal stops the run, "K:torn" dies by SIGKILL inside the K-th line's
    write, "remove:kill" and "remove:term" strike while a complete run removes its journal."""
    return dict(os.environ, **{FAULT: fault})


def journal_file_lines(out):
    """Every journal file's text split at its newlines: (complete lines, torn tails)."""
    jdir = str(out) + ".jobs"
    complete, torn = [], []
    for f in sorted(os.listdir(jdir)):
        if f.endswith(".jsonl"):
            *whole, tail = read(os.path.join(jdir, f)).split("\n")
            complete += whole
            if tail:
                torn.append(tail)
    return complete, torn


def started_paused(vimpact, args, out, lines, launcher=()):
    """A run started with the journal's pause after `lines` lines, once it waits there: its
    journal holds them and it cannot end before the signal the test sends. (process, lines)"""
    proc = subprocess.Popen([*launcher, vimpact, *args, "--out", str(out)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=with_fault(f"{lines}:pause"),
                            start_new_session=bool(launcher))
    deadline = time.time() + 300
    while journal_lines(out) < lines and proc.poll() is None and time.time() < deadline:
        time.sleep(0.01)
    assert proc.poll() is None, proc.communicate()
    return proc, journal_lines(out)


def interrupt_after(vimpact, args, out, lines, sig):
    proc, before = started_paused(vimpact, args, out, lines)
    assert journal_lines(out) == before, "the journal grew during the pause"
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    return proc.returncode, err


KILL_ARGS = MAP[:] + ["--no-plot", "--threads", "2"]
KILL_ARGS[2] = "Ur:16:25:20"  # 120 cells


@pytest.fixture(scope="module")
def kill_whole(vimpact, tmp_path_factory):
    whole = tmp_path_factory.mktemp("kill") / "whole"
    assert run(vimpact, *KILL_ARGS, "--out", str(whole)).returncode == 0
    return whole


# Stopped after the first line (before any result reached the command: its stop message must
# still name the journal) and after the tenth.
@pytest.mark.parametrize("lines", [1, 10])
@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGINT, signal.SIGTERM])
def test_resume_after_interruption_equals_an_uninterrupted_run(vimpact, tmp_path, kill_whole, sig, lines):
    args = KILL_ARGS
    out = tmp_path / "run"
    code, err = interrupt_after(vimpact, args, out, lines, sig)
    kept = journal_lines(out)
    assert kept >= lines
    assert not os.path.exists(out), "nothing is written to --out before the run is complete"
    if sig == signal.SIGKILL:
        assert code == -signal.SIGKILL
    else:
        assert code == 130
        assert f"jobs done and kept in {out}.jobs" in err and "--resume" in err, err
    # Without --resume the unfinished run is protected.
    p = run(vimpact, *args, "--out", str(out))
    assert p.returncode == 2 and "--resume" in p.stderr
    r = run(vimpact, *args, "--out", str(out), "--resume")
    assert r.returncode == 0, r.stderr
    assert read(kill_whole / "labels.csv") == read(out / "labels.csv")
    assert not os.path.exists(str(out) + ".jobs")


@pytest.mark.parametrize("fault", ["10:kill", "10:torn"])
def test_a_kill_inside_or_after_a_journal_write_keeps_every_whole_line(vimpact, tmp_path, kill_whole, fault):
    # SIGKILL right after the write of the 10th line, or inside it: the lines before stay whole
    # and readable, a torn line is the last, and the resume drops it and finishes the run.
    out = tmp_path / "run"
    p = subprocess.run([vimpact, *KILL_ARGS, "--out", str(out)], capture_output=True, text=True, timeout=600,
                       env=with_fault(fault))
    assert p.returncode == -signal.SIGKILL, p.stderr
    complete, torn = journal_file_lines(out)
    if fault.endswith("torn"):
        assert len(complete) == 9 and len(torn) == 1
        assert 0 < len(torn[0]) and torn[0].startswith('{"job":')
    else:
        assert len(complete) >= 10 and not torn
    jobs = [json.loads(line)["job"] for line in complete]
    assert len(set(jobs)) == len(jobs) and all(0 <= j < 120 for j in jobs)
    r = run(vimpact, *KILL_ARGS, "--out", str(out), "--resume")
    assert r.returncode == 0, r.stderr
    assert read(kill_whole / "labels.csv") == read(out / "labels.csv")
    assert not os.path.exists(str(out) + ".jobs")


def journal_state(out):
    """The journal beside DIR: None when gone, else (has spec.json, whole lines, torn tails)."""
    jdir = str(out) + ".jobs"
    if not os.path.exists(jdir):
        return None
    complete, torn = journal_file_lines(out)
    return os.path.exists(os.path.join(jdir, "spec.json")), len(complete), len(torn)


def left_aside(out):
    return [f for f in os.listdir(os.path.dirname(str(out))) if ".removed-" in f or ".new-" in f]


def test_a_kill_while_a_complete_run_removes_its_journal_leaves_it_whole_or_gone(vimpact, tmp_path, kill_whole):
    # DIR is written, then the journal removed; SIGKILL in the middle of the removal (Open MPI's
    # SIGKILL a second after its SIGTERM, a second Ctrl-C) must not leave part of a journal: one
    # without its lines, or without the spec.json that every later run of DIR then stops at.
    out = tmp_path / "run"
    p = subprocess.run([vimpact, *KILL_ARGS, "--out", str(out)], capture_output=True, text=True, timeout=600,
                       env=with_fault("remove:kill"))
    assert p.returncode == -signal.SIGKILL, p.stderr
    assert read(kill_whole / "labels.csv") == read(out / "labels.csv")
    assert journal_state(out) is None, journal_state(out)  # (killed before the removal began: whole)
    # The same command again, without --resume: nothing stands in its way, nothing is left aside.
    r = run(vimpact, *KILL_ARGS, "--out", str(out))
    assert r.returncode == 0, r.stderr
    assert read(kill_whole / "labels.csv") == read(out / "labels.csv")
    assert journal_state(out) is None and not left_aside(out)


def test_a_signal_after_dir_is_written_is_not_an_interruption(vimpact, tmp_path, kill_whole):
    # SIGTERM once DIR is committed (while the journal is removed): the run is complete and its
    # journal gone, so the command reports what it wrote, exit 0, not "interrupted; nothing
    # written" (exit 130), which would send the user to resume a run that has no journal.
    out = tmp_path / "run"
    p = subprocess.run([vimpact, *KILL_ARGS, "--out", str(out)], capture_output=True, text=True, timeout=600,
                       env=with_fault("remove:term"))
    assert p.returncode == 0, p.stderr
    assert f"output written to {out}" in p.stdout and "interrupted" not in p.stderr
    assert read(kill_whole / "labels.csv") == read(out / "labels.csv")
    assert journal_state(out) is None and not left_aside(out)


def test_one_process_at_a_time_writes_a_shard_of_the_journal(vimpact, tmp_path, kill_whole):
    # A resume started while the interrupted run still runs (or the same command started twice)
    # is refused before it touches the journal: it would cut the other's newest lines as a
    # torn tail and append among its lines.
    out = tmp_path / "run"
    first, before = started_paused(vimpact, KILL_ARGS, out, 10)
    lines = journal_file_lines(out)
    try:
        p = run(vimpact, *KILL_ARGS, "--out", str(out), "--resume")
        assert p.returncode == 2, p.stderr
        assert "is being written by another process" in p.stderr and "shard-0-of-1.jsonl" in p.stderr, p.stderr
        assert journal_file_lines(out) == lines and not os.path.exists(out)
    finally:
        first.send_signal(signal.SIGINT)
        _, err = first.communicate(timeout=120)
    assert first.returncode == 130, err
    r = run(vimpact, *KILL_ARGS, "--out", str(out), "--resume")
    assert r.returncode == 0, r.stderr
    assert read(kill_whole / "labels.csv") == read(out / "labels.csv")


def test_a_malformed_journal_fault_is_refused(vimpact, tmp_path):
    p = subprocess.run([vimpact, *MAP, "--no-plot", "--out", str(tmp_path / "o")], capture_output=True, text=True,
                       timeout=600, env=with_fault("10:explode"))
    assert p.returncode == 2 and FAULT in p.stderr and "K:pause" in p.stderr, p.stderr


def test_resume_refuses_a_different_run(vimpact, tmp_path):
    out = tmp_path / "o"
    assert run(vimpact, *MAP, "--no-plot", "--out", str(out), "--shard", "0/2").returncode == 0
    p = run(vimpact, *MAP, "--set", "r=0.7", "--no-plot", "--out", str(out), "--resume")
    assert p.returncode == 2
    assert "different run" in p.stderr


def test_map_json_rows_and_picture(vimpact, tmp_path):
    out = tmp_path / "m"
    p = run(vimpact, *MAP, "--json", "--grazing", "--out", str(out))
    assert p.returncode == 0, p.stderr
    j = json.loads(p.stdout)
    assert j["shape"] == [6, 10]
    # With --out each cell's label is in labels.csv (run.json and the summary count them).
    assert "labels" not in j and sum(j["label_counts"].values()) == 60
    _, cells = read_rows(out / "labels.csv")
    labels = [[c["label"] for c in cells[10 * k:10 * k + 10]] for k in range(6)]
    assert labels == run_json(vimpact, *MAP, "--grazing")["labels"]  # without --out, in the summary
    assert len(j["grazing"]) == 10
    # Barriers far below the grazing line cannot be hit: P0 there, impacting labels above.
    for (ur, g), col in zip(j["grazing"], zip(*labels)):
        for sigma, lab in zip(j["y_values"], col):
            if sigma < g - 1e-3:
                assert lab == "P0", (ur, sigma, g, lab)
            if sigma > g + 1e-3:
                assert lab != "P0", (ur, sigma, g, lab)
    assert j["grazing_param"] == "sigma" and j["grazing_surfaces"] == ["barrier"]
    for f in ("labels.csv", "grazing.csv", "run.json"):
        assert os.path.exists(out / f)
    check_png(out / "plot.png")
    assert (out / "grazing.csv").read_text().splitlines()[0] == "Ur,sigma_graze"
    header, rows = read_rows(out / "labels.csv")
    assert header == ["Ur", "sigma", "label", "period", "impacts", "closure", "settled", "impacts_barrier", "outcome",
                      *STATISTICS, "excursion_barrier"]
    assert all(r["impacts"] == r["impacts_barrier"] for r in rows)


def test_basins_find_the_coexisting_attractors(vimpact, tmp_path):
    out = tmp_path / "b"
    p = run(vimpact, "basins", "--set", "Ur=14.9", "--x", "y:-0.2:0.25:6", "--y", "ydot:-0.2:0.2:5",
            "--json", "--out", str(out))
    assert p.returncode == 0, p.stderr
    j = json.loads(p.stdout)
    assert sorted(j["attractors"]["labels"]) == ["P1", "P2"]
    assert j["inadmissible_cells"] == 5  # the column y = -0.2 is below the barrier
    header, cells = read_rows(out / "cells.csv")
    assert header == ["y", "ydot", "attractor", "label", "period", "impacts", "closure", "settled", "impacts_barrier",
                      "outcome"]
    assert j["x_values"] == [float(c["y"]) for c in cells[:6]] and j["y_values"] == [float(c["ydot"]) for c in cells[::6]]
    # The same attractor, the same label; its id numbers the attractors in the order of the table.
    for c in cells:
        a = int(c["attractor"])
        assert c["label"] == (j["attractors"]["labels"][a] if a >= 0 else "inadmissible")
    check_png(out / "plot.png")


def test_response_curves(vimpact, tmp_path):
    out = tmp_path / "r"
    p = run(vimpact, "response", "--param", "Ur", "--range", "4:8:3", "--curves", "A=12,eps=0.3;A=10,eps=0.25",
            "--json", "--out", str(out))
    assert p.returncode == 0, p.stderr
    j = json.loads(p.stdout)
    assert len(j["curves"]) == 2
    assert j["variable"] == "y"
    assert [c["parameters"] for c in j["curves"]] == [{"A": 12, "eps": 0.3}, {"A": 10, "eps": 0.25}]
    # With --out the points are in response.csv; without it, in the summary.
    assert all("amplitude" not in c for c in j["curves"])
    j = run_json(vimpact, "response", "--param", "Ur", "--range", "4:8:3", "--curves", "A=12,eps=0.3;A=10,eps=0.25")
    for c in j["curves"]:
        assert len(c["sigma_graze"]) == 3 and len(c["frequency"]) == 3
        assert len(c["amplitude"]) == 3
        assert all(a > 0 for a in c["amplitude"])
    c = j["curves"][0]
    # The lock-in peak: the amplitude at Ur = 6 exceeds both ends (Figure 10a).
    assert c["amplitude"][1] > max(c["amplitude"][0], c["amplitude"][2])
    # The model is odd-symmetric, (y, v, x, w) -> -(y, v, x, w), and so is its limit cycle:
    # the largest maximum of y equals minus the grazing value (the smallest minimum).
    header, text_rows = read_rows(out / "response.csv")
    assert header == ["A", "eps", "curve", "Ur", "amplitude", "y_max", "y_min", "sigma_graze", "margin", "frequency",
                      "converged", "outcome"]
    rows = [{k: float(v) for k, v in r.items() if k != "outcome"} for r in text_rows]
    assert len(rows) == 6 and all(r["outcome"] == "ok" for r in text_rows)
    assert [(r["A"], r["eps"], r["curve"]) for r in rows] == [(12, 0.3, 0)] * 3 + [(10, 0.25, 1)] * 3
    sigma = json.loads((out / "run.json").read_text())["config"]["parameters"]["sigma"]
    for row in rows:
        assert abs(row["y_max"] + row["sigma_graze"]) < 1e-9
        assert row["y_min"] == row["sigma_graze"]  # the barrier's grazing value is the minimum of y
        assert row["amplitude"] == max(row["y_max"], -row["sigma_graze"])
        assert row["margin"] == pytest.approx(row["y_min"] - sigma, abs=1e-15)  # the gap y - sigma at that minimum
    check_png(out / "plot.png")


@pytest.mark.parametrize("args,needle", [
    (["sweep", "--param", "Q", "--range", "1:2:3"], "unknown parameter 'Q'"),
    (["sweep", "--param", "Ur", "--range", "1:2"], "a:b:n"),
    (["sweep", "--param", "Ur", "--range", "1:2:0"], "n must be"),
    (["sweep", "--param", "Ur", "--range", "10:12:3", "--direction", "both"],
     "--direction = both needs ic_mode follow"),
    (["sweep", "--param", "sigma", "--range", "-0.1:0.1:3"], "beyond surface barrier"),
    (["sweep", "--param", "Ur", "--range", "10:12:3", "--grazing", "Ur"], "enters the vector field"),
    (["sweep", "--param", "Ur", "--range", "10:12:3", "--ic-mode", "chase"], "fixed, follow"),
    (["map", "--x", "Ur:10:12:2", "--y", "Ur:1:2:2"], "different parameters"),
    (["map", "--x", "Ur:10:12:2", "--y", "r:0.5:0.8:2", "--grazing"], "moves a surface"),
    (["basins", "--x", "z:0:1:2", "--y", "ydot:0:1:2"], "not one of y, ydot, x, xdot"),
    (["map", "--x", "Ur:10:12:2", "--y", "r:0.5:0.8:2", "--shard", "2/2", "--out", "o"], "--shard"),
    (["map", "--x", "Ur:10:12:2", "--y", "r:0.5:0.8:2", "--resume"], "--resume needs --out"),
    (["response", "--param", "sigma", "--range", "0:1:2"], "does not enter the vector field"),
    (["response", "--param", "Ur", "--range", "4:5:2", "--curves", "12"], "NAME=VALUE"),
    (["response", "--param", "Ur", "--range", "4:5:2", "--curves", "A=12,A=14"], "twice"),
    (["response", "--param", "Ur", "--range", "4:5:2", "--curves", "Ur=12"], "the swept parameter"),
    (["response", "--param", "Ur", "--range", "4:5:2", "--variable", "q"], "not one of y, ydot, x, xdot"),
])
def test_bad_input_is_exit_code_2_and_names_the_input(vimpact, tmp_path, args, needle):
    p = run(vimpact, *args, cwd=tmp_path)
    assert p.returncode == 2, p.stderr
    assert needle in p.stderr
    assert p.stderr.startswith("vimpact: error:")
    assert len(p.stderr.strip().splitlines()) == 1
    assert os.listdir(tmp_path) == []


# ---------------------------------------------------------------- long grids

def _peak_kb(pid):
    """The process's peak resident memory (VmHWM), in kB."""
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1])
    return 0


TUBE = "D=0.02,m=0.6,fn=12,zeta=0.002,rho=1000"


@pytest.mark.parametrize("args, values", [
    (["sweep", "--param", "Ur", "--range", "12:25:10000000"], {"from": 12.0, "to": 25.0, "n": 10000000}),
    (["clearance", "--si", TUBE, "--speeds", "3:6:10000000"], {"from": 3.0, "to": 6.0, "n": 10000000}),
])
def test_a_long_grid_is_kept_as_its_ends_and_count(vimpact, tmp_path, args, values):
    # Millions of values: the spec of the journal says a:b:n, and memory stays that of a short
    # run while the jobs start (the results stream). Stopped once the jobs run: the run is
    # resumable, nothing else written.
    out = tmp_path / "o"
    spec = tmp_path / "o.jobs" / "spec.json"
    p = subprocess.Popen([vimpact, *args, "--transient", "20", "--record", "10", "--threads", "1", "--no-plot",
                          "--out", str(out)], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    peak = 0
    try:
        deadline = time.time() + 300
        while not spec.exists() and p.poll() is None and time.time() < deadline:
            peak = max(peak, _peak_kb(p.pid))
            time.sleep(0.05)
        assert spec.exists(), p.stderr.read() if p.poll() is not None else "no journal in 300 s"
        time.sleep(1.5)  # the jobs run
        assert p.poll() is None, p.stderr.read()
        peak = max(peak, _peak_kb(p.pid))
        p.send_signal(signal.SIGINT)
        assert p.wait(timeout=120) == 130
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
    j = json.loads(spec.read_text())
    grid = j["values"]
    assert {k: grid[k] for k in ("from", "to", "n")} == values
    assert spec.stat().st_size < 8192, spec.stat().st_size
    assert peak < 150_000, f"peak resident memory {peak} kB"
    assert not out.exists()
