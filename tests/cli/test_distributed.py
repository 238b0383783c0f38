# Many-job runs across MPI ranks (docs/distributed.md): the files equal the threaded run's byte
# for byte whatever the ranks and threads; a rank killed mid-run, or the whole job, loses only
# unfinished jobs and a resume with any number of ranks finishes the run; more ranks than
# jobs; MPI runs as shards of one run; the Slurm scripts, run here with mpirun standing in for
# srun. Skipped (not failed) when this vimpact was built without MPI or mpirun is missing.
import json
import os
import shutil
import signal
import subprocess
import time

import pytest

from conftest import need
from test_sweeps import MAP, journal_file_lines, journal_lines, read, started_paused, with_fault

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
MPIRUN = ["mpirun", "--allow-run-as-root", "--oversubscribe"]
TIMEOUT = 600


@pytest.fixture(scope="module")
def mpi(vimpact):
    need("mpi", shutil.which("mpirun") is not None, "mpirun is not installed")
    p = subprocess.run(MPIRUN + ["-n", "2", vimpact, "sweep", "--param", "Ur", "--range", "16:17:2", "--transient",
                                 "20", "--record", "10", "--json"], capture_output=True, text=True, timeout=TIMEOUT)
    need("mpi", not (p.returncode == 2 and "built without MPI" in p.stderr), "this vimpact was built without MPI")
    assert p.returncode == 0, p.stderr
    assert len(p.stdout.splitlines()) == 1, "only rank 0 prints"
    return MPIRUN


def mpirun(mpi, n, vimpact, *args):
    return subprocess.run(mpi + ["-n", str(n), vimpact, *args], capture_output=True, text=True, timeout=TIMEOUT)


def without_out(x):
    """A run record without the output paths it names (they differ between the runs compared)."""
    if isinstance(x, dict):
        return {k: without_out(v) for k, v in x.items() if k != "out"}
    if isinstance(x, list):
        return [without_out(v) for v in x]
    return x


def same_files(a, b):
    names = sorted(os.listdir(a))
    assert names == sorted(os.listdir(b))
    for name in names:
        if name == "run.json":
            ja, jb = (json.load(open(os.path.join(d, name))) for d in (a, b))
            assert without_out(ja) == without_out(jb)
        else:
            assert read(os.path.join(a, name)) == read(os.path.join(b, name)), name


# Each a many-job command with --out: a map, a chained sweep (both directions followed), basins,
# stability sweeps (Floquet and Lyapunov), response curves, a clearance chart, and a Floquet
# sweep of a model with a switch (examples/models/compliant_stop.toml).
CASES = {
    "map": MAP + ["--grazing"],
    "sweep": ["sweep", "--param", "Ur", "--range", "14.5:15.5:7", "--ic-mode", "follow", "--direction", "both",
              "--transient", "200", "--record", "40"],
    "basins": ["basins", "--set", "Ur=14.9", "--x", "y:-0.2:0.25:6", "--y", "ydot:-0.2:0.2:5", "--transient", "200",
               "--record", "40"],
    "floquet": ["floquet", "--param", "Ur", "--range", "15:17:5", "--transient", "200"],
    "lyapunov": ["lyapunov", "--param", "Ur", "--range", "16:24:3", "--transient", "100", "--impacts", "300"],
    "response": ["response", "--param", "Ur", "--range", "4:12:5", "--curves", "A=14,eps=0.35;A=12,eps=0.3"],
    "clearance": ["clearance", "--si", "D=0.02,m=0.6,fn=12,zeta=0.002,rho=1000", "--speeds", "3:5:3",
                  "--transient", "100", "--record", "40"],
    "switches": ["floquet", "--model", os.path.join(ROOT, "examples", "models", "compliant_stop.toml"), "--param",
                 "omega", "--range", "0.6:1.2:5", "--transient", "100", "--record", "20"],
}
_threaded = {}


def threaded(vimpact, tmp_path_factory, case):
    if case not in _threaded:
        d = tmp_path_factory.mktemp("threaded") / case
        p = subprocess.run([vimpact, *CASES[case], "--no-plot", "--threads", "2", "--out", str(d)],
                           capture_output=True, text=True, timeout=TIMEOUT)
        assert p.returncode == 0, p.stderr
        _threaded[case] = d
    return _threaded[case]


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("ranks,threads", [(2, 1), (2, 2)])
def test_ranks_write_the_threaded_runs_files(vimpact, mpi, tmp_path, tmp_path_factory, case, ranks, threads):
    out = tmp_path / case
    p = mpirun(mpi, ranks, vimpact, *CASES[case], "--no-plot", "--threads", str(threads), "--out", str(out))
    assert p.returncode == 0, p.stderr
    assert p.stdout.count("output written to") == 1, "rank 0 alone reports"
    same_files(threaded(vimpact, tmp_path_factory, case), out)
    assert not os.path.exists(str(out) + ".jobs")


def test_more_ranks_than_jobs(vimpact, mpi, tmp_path):
    args = ["sweep", "--param", "Ur", "--range", "16:19:2", "--transient", "100", "--record", "40", "--no-plot"]
    one = tmp_path / "one"
    assert subprocess.run([vimpact, *args, "--out", str(one)], capture_output=True).returncode == 0
    out = tmp_path / "three"
    p = mpirun(mpi, 3, vimpact, *args, "--threads", "1", "--out", str(out))
    assert p.returncode == 0, p.stderr
    same_files(one, out)


def rank_pids(launcher_pid):
    """The ranks mpirun started, by rank."""
    out = {}
    for pid in subprocess.run(["pgrep", "-P", str(launcher_pid)], capture_output=True, text=True).stdout.split():
        try:
            env = open(f"/proc/{pid}/environ", "rb").read().split(b"\0")
        except OSError:
            continue
        for e in env:
            if e.startswith(b"OMPI_COMM_WORLD_RANK="):
                out[int(e.split(b"=")[1])] = int(pid)
    return out


LONG_MAP = MAP[:] + ["--no-plot", "--threads", "1"]
LONG_MAP[2] = "Ur:16:25:40"  # 240 cells: no flush of rank 0's journal holds them all
LONG_MAP[LONG_MAP.index("--transient") + 1] = "400"


def start_and_wait(mpi, n, vimpact, out, lines):
    """mpirun started with rank 0's journal pausing after `lines` lines (the library's test hook),
    its n ranks found, and the pause reached: (process, ranks, lines in the journal). The run
    cannot end before the test's signal, however loaded the machine; the journal holds what
    it held at the pause until then."""
    proc, before = started_paused(vimpact, LONG_MAP, out, lines, launcher=[*mpi, "-n", str(n)])
    ranks = {}
    deadline = time.time() + 120
    while len(ranks) < n and proc.poll() is None and time.time() < deadline:
        ranks = rank_pids(proc.pid)
    assert proc.poll() is None and len(ranks) == n, ranks
    assert journal_lines(out) == before, "the journal grew during the pause"
    return proc, ranks, before


@pytest.fixture(scope="module")
def long_whole(vimpact, tmp_path_factory):
    d = tmp_path_factory.mktemp("long") / "whole"
    p = subprocess.run([vimpact, *LONG_MAP, "--out", str(d)], capture_output=True, text=True, timeout=TIMEOUT)
    assert p.returncode == 0, p.stderr
    return d


def test_a_rank_killed_mid_run_loses_only_unfinished_jobs(vimpact, mpi, tmp_path, long_whole):
    out = tmp_path / "run"
    proc, ranks, before = start_and_wait(mpi, 2, vimpact, out, 10)
    assert sorted(ranks) == [0, 1]
    os.kill(ranks[1], signal.SIGKILL)
    proc.communicate(timeout=120)
    assert proc.returncode != 0
    kept = journal_lines(out)
    assert kept >= before >= 10, "every result rank 0 had is in the journal"
    assert kept < 240 and not os.path.exists(out)
    # Resumed with another number of ranks: the same files as one uninterrupted run.
    p = mpirun(mpi, 3, vimpact, *LONG_MAP, "--out", str(out), "--resume")
    assert p.returncode == 0, p.stderr
    same_files(long_whole, out)


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL])
def test_the_whole_job_killed_then_resumed_by_one_process(vimpact, mpi, tmp_path, long_whole, sig):
    out = tmp_path / "run"
    proc, ranks, before = start_and_wait(mpi, 2, vimpact, out, 10)
    if sig == signal.SIGKILL:
        for pid in ranks.values():
            os.kill(pid, signal.SIGKILL)
        os.kill(proc.pid, signal.SIGKILL)
    else:
        proc.send_signal(sig)  # mpirun passes it to every rank: they stop and keep the journal
    _, err = proc.communicate(timeout=120)
    assert proc.returncode != 0
    if sig == signal.SIGTERM and err:
        # Rank 0 says so (and exits 130; mpirun, signalled itself, exits 1). Open MPI sends the
        # ranks SIGCONT, SIGTERM a second later and SIGKILL a second after that, and its output
        # forwarding may drop a rank's last line when it tears the job down on a loaded machine:
        # the journal and the resume below are what a SIGTERM must leave.
        assert "interrupted" in err and "--resume" in err, err
    assert journal_lines(out) >= before and not os.path.exists(out)
    complete, torn = journal_file_lines(out)
    assert all(json.loads(line)["job"] >= 0 for line in complete) and len(torn) <= 1
    p = subprocess.run([vimpact, *LONG_MAP, "--out", str(out), "--resume"], capture_output=True, text=True,
                       timeout=TIMEOUT)
    assert p.returncode == 0, p.stderr
    same_files(long_whole, out)


@pytest.mark.parametrize("fault", ["remove:term", "remove:kill"])
def test_a_signal_after_rank_0_wrote_dir(vimpact, mpi, tmp_path, long_whole, fault):
    # Open MPI passes mpirun's SIGTERM on a second late, and its SIGKILL a second after that:
    # a run may complete meanwhile, write DIR and remove its journal (what failed the timed
    # version of the test above once: "0 lines" left, DIR written). Here rank 0 is signalled
    # at that point itself. SIGTERM: the run is done, exit 0, one report. SIGKILL: DIR is whole
    # and the journal gone, not half removed.
    out = tmp_path / "run"
    p = subprocess.run(MPIRUN + ["-n", "2", vimpact, *LONG_MAP, "--out", str(out)], capture_output=True, text=True,
                       timeout=TIMEOUT, env=with_fault(fault))
    if fault == "remove:term":
        assert p.returncode == 0, p.stderr
        assert p.stdout.count("output written to") == 1 and "interrupted" not in p.stderr
        assert not [f for f in os.listdir(tmp_path) if ".removed-" in f]
    else:
        assert p.returncode != 0
    same_files(long_whole, out)
    assert not os.path.exists(str(out) + ".jobs")


def test_mpi_runs_as_shards_of_one_run(vimpact, mpi, tmp_path, tmp_path_factory):
    # Two MPI runs started together, each one shard: exactly one writes the complete result.
    out = tmp_path / "o"
    procs = [subprocess.Popen(mpi + ["-n", "2", vimpact, *CASES["map"], "--no-plot", "--threads", "1", "--shard",
                                     f"{i}/2", "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True) for i in range(2)]
    results = [p.communicate(timeout=TIMEOUT) + (p.returncode,) for p in procs]
    assert [r[2] for r in results] == [0, 0], [r[1] for r in results]
    assert sum("output written to" in r[0] for r in results) == 1
    same_files(threaded(vimpact, tmp_path_factory, "map"), out)


def test_a_refused_journal_ends_every_rank_with_one_message(vimpact, mpi, tmp_path):
    out = tmp_path / "o"
    assert subprocess.run([vimpact, *MAP, "--no-plot", "--out", str(out), "--shard", "0/2"]).returncode == 0
    p = mpirun(mpi, 2, vimpact, *MAP, "--set", "r=0.7", "--no-plot", "--out", str(out), "--resume")
    assert p.returncode == 2
    assert p.stderr.count("belongs to a different run") == 1


def test_ranks_started_with_different_options_are_refused(vimpact, mpi, tmp_path):
    # One rank with A = 6: merging its cells with the other's would make a map of no run.
    out = tmp_path / "o"
    args = ["map", "--x", "Ur:16:17:2", "--y", "sigma:-0.16:-0.14:2", "--transient", "20", "--record", "10",
            "--no-plot", "--out", str(out)]
    p = subprocess.run(mpi + ["-n", "1", vimpact, *args, ":", "-n", "1", vimpact, *args, "--set", "A=6"],
                       capture_output=True, text=True, timeout=TIMEOUT)
    assert p.returncode == 2, p.stderr
    assert p.stderr.count("vimpact: error:") == 1, p.stderr
    line = next(l for l in p.stderr.splitlines() if l.startswith("vimpact: error:"))
    assert "MPI rank 1 was started with another run than rank 0 (model/parameters/" in line, line
    assert "12.0 on rank 0, 6.0 on rank 1" in line and "start every rank with the same command and options" in line, line
    # Nothing written: no output, no journal, no staging directory.
    assert sorted(os.listdir(tmp_path)) == [], os.listdir(tmp_path)
    # The same options on both ranks run (the check passes what agrees).
    p = subprocess.run(mpi + ["-n", "1", vimpact, *args, "--set", "A=6", ":", "-n", "1", vimpact, *args, "--set",
                              "A=6"], capture_output=True, text=True, timeout=TIMEOUT)
    assert p.returncode == 0, p.stderr
    assert (out / "labels.csv").exists()


def slurm_env(tmp_path, vimpact, args, out, **extra):
    """The environment of a Slurm task, with an srun that is mpirun (the ranks of --ntasks)."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir(exist_ok=True)
    srun = bin_dir / "srun"
    srun.write_text("#!/bin/sh\nexec " + " ".join(MPIRUN) + ' -n "$SLURM_NTASKS" "$@"\n')
    srun.chmod(0o755)
    env = dict(os.environ, PATH=f"{bin_dir}:{os.environ['PATH']}", VIMPACT=vimpact, VIMPACT_ARGS=" ".join(args),
               OUT=str(out), SLURM_CPUS_PER_TASK="1")
    env.update(extra)
    return env


def test_the_slurm_mpi_script(vimpact, mpi, tmp_path, tmp_path_factory):
    out = tmp_path / "map"
    script = os.path.join(ROOT, "scripts", "slurm", "map-mpi.sbatch")
    p = subprocess.run(["bash", script], env=slurm_env(tmp_path, vimpact, CASES["map"] + ["--no-plot"], out,
                                                       SLURM_NTASKS="2"),
                       capture_output=True, text=True, timeout=TIMEOUT, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    same_files(threaded(vimpact, tmp_path_factory, "map"), out)


def test_the_slurm_job_array_and_its_merge(vimpact, mpi, tmp_path, tmp_path_factory):
    args = CASES["map"] + ["--no-plot"]
    shards = os.path.join(ROOT, "scripts", "slurm", "map-shards.sbatch")
    merge = os.path.join(ROOT, "scripts", "slurm", "map-merge.sbatch")
    # Every task of a 3-task array at once (the last to finish writes), then the merge finds
    # nothing left to do.
    out = tmp_path / "all"
    procs = [subprocess.Popen(["bash", shards], env=slurm_env(tmp_path, vimpact, args, out, SLURM_ARRAY_TASK_ID=str(i),
                                                              SLURM_ARRAY_TASK_COUNT="3"),
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for i in range(3)]
    assert [p.wait(timeout=TIMEOUT) for p in procs] == [0, 0, 0]
    p = subprocess.run(["bash", merge], env=slurm_env(tmp_path, vimpact, args, out), capture_output=True, text=True,
                       timeout=TIMEOUT)
    assert p.returncode == 0, p.stderr
    same_files(threaded(vimpact, tmp_path_factory, "map"), out)
    # A task that never ran (a failed node): the merge computes its cells and writes the map.
    # The other task is an MPI run of two ranks (SHARD_LAUNCHER).
    out = tmp_path / "partial"
    p = subprocess.run(["bash", shards], env=slurm_env(tmp_path, vimpact, args, out, SLURM_ARRAY_TASK_ID="1",
                                                       SLURM_ARRAY_TASK_COUNT="2", SLURM_NTASKS="2",
                                                       SHARD_LAUNCHER="srun"),
                       capture_output=True, text=True, timeout=TIMEOUT)
    assert p.returncode == 0, p.stderr
    assert not os.path.exists(out)
    p = subprocess.run(["bash", merge], env=slurm_env(tmp_path, vimpact, args, out), capture_output=True, text=True,
                       timeout=TIMEOUT)
    assert p.returncode == 0, p.stderr
    same_files(threaded(vimpact, tmp_path_factory, "map"), out)
