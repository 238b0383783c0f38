#!/usr/bin/env python3
"""One vimpact command with two builds, in turns: median CPU time (user + system) of each and
their ratio, and whether the outputs are the same. For a change measured against the build
before it (docs/performance.md, "States sized at run time"):

    /usr/bin/python3 bench/compare_builds.py OLD/build/vimpact build/vimpact \\
        lyapunov --model row3.toml --set Ur=14

ROUNDS=N (default 7). The model cache is this run's own, compiled once per build first.
"""
import os
import resource
import statistics
import subprocess
import sys
import tempfile


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    builds = {"before": sys.argv[1], "after": sys.argv[2]}
    args = sys.argv[3:]
    rounds = int(os.environ.get("ROUNDS", "7"))
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, VIMPACT_CACHE_DIR=cache)
        for exe in builds.values():
            subprocess.run([exe, *args], env=env, stdout=subprocess.DEVNULL, check=True)
        times = {k: [] for k in builds}
        outputs = {}
        for _ in range(rounds):
            for k, exe in builds.items():
                r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
                p = subprocess.run([exe, *args], env=env, stdout=subprocess.PIPE, text=True, check=True)
                r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
                times[k].append(r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime)
                outputs[k] = p.stdout
    for k in builds:
        print(f"{k}: median CPU {statistics.median(times[k]):.3f} s of {rounds}", [round(t, 3) for t in times[k]])
    print(f"after / before: {statistics.median(times['after']) / statistics.median(times['before']):.3f}")
    print("same output:", outputs["before"] == outputs["after"])


if __name__ == "__main__":
    main()
