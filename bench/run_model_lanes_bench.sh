#!/usr/bin/env bash
# A model file's SIMD lanes against its jobs one at a time and against the built-in model's
# lanes, like for like: `vimpact map` of the paper's model over Ur 12..25 x sigma -0.2..0
# (32 x 16 cells, the default protocol, DOP853, one thread), the built-in model and
# examples/models/wake_impact.toml, each with the default batch (lanes) and --batch 1. The four
# runs take turns, 5 rounds; the table gives the median CPU time of each (user + system, what a
# loaded machine inflates least) and the ratios. Goals (issue "your own system as fast as a
# built-in"): model file in lanes / --batch 1 >= 2.8, model file in lanes / built-in lanes <= 1.15.
# Every run's labels are checked equal to the others'.
# Usage: bash bench/run_model_lanes_bench.sh
#   BUILD_DIR=DIR (default build): the build directory to configure, build and run.
#   ROUNDS=N (default 5), GRID="32 16" (cells along Ur and sigma).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh main
build=${BUILD_DIR:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$build" -j"$(nproc)" --target vimpact_cli vimpact_modules > /dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The model file compiled once, before the rounds, into a cache of this run's own.
export VIMPACT_CACHE_DIR="$tmp/cache"
/usr/bin/python3 - "$build/vimpact" "${ROUNDS:-5}" ${GRID:-32 16} <<'PY'
import json, resource, statistics, subprocess, sys
exe, rounds, nx, ny = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
grid = ["--x", f"Ur:12:25:{nx}", "--y", f"sigma:-0.2:0:{ny}", "--threads", "1", "--json"]
model = ["--model", "examples/models/wake_impact.toml"]
runs = {"built-in, lanes": ["--batch", "0"], "built-in, --batch 1": ["--batch", "1"],
        "model file, lanes": model + ["--batch", "0"], "model file, --batch 1": model + ["--batch", "1"]}
subprocess.run([exe, "map", *model, "--x", "Ur:12:13:2", "--y", "sigma:-0.2:0:2", "--transient", "1",
                "--record", "1", "--json"], check=True, capture_output=True)


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


cpu = {k: [] for k in runs}
labels, batch = {}, {}
for _ in range(rounds):
    for name, args in runs.items():
        before = children_cpu()
        out = subprocess.run([exe, "map", *args, *grid], check=True, capture_output=True, text=True).stdout
        cpu[name].append(children_cpu() - before)
        summary = json.loads(out)
        labels.setdefault(name, summary["labels"])
        batch[name] = summary["batch"]
first = next(iter(labels.values()))
for name, l in labels.items():
    if l != first:
        sys.exit(f"{name}: labels differ from the built-in model's")
med = {k: statistics.median(v) for k, v in cpu.items()}
print(f"map of {nx} x {ny} cells, one thread, median of {rounds} rounds")
print()
print("| run | batch | median CPU [s] |")
print("|---|---|---|")
for name in runs:
    print(f"| {name} | {batch[name]} | {med[name]:.2f} |")
print()
print(f"model file: --batch 1 / lanes = {med['model file, --batch 1'] / med['model file, lanes']:.2f} (goal >= 2.8)")
print(f"lanes: model file / built-in = {med['model file, lanes'] / med['built-in, lanes']:.2f} (goal <= 1.15)")
print(f"built-in: --batch 1 / lanes = {med['built-in, --batch 1'] / med['built-in, lanes']:.2f}")
print(f"--batch 1: model file / built-in = {med['model file, --batch 1'] / med['built-in, --batch 1']:.2f}")
PY
