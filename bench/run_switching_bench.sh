#!/usr/bin/env bash
# A switch's crossing against an impact, like for like (bench/switching_bench.cpp): two forced
# oscillators whose motions are mirror images, one bouncing on a rigid barrier, one crossing a
# switch where its forcing changes sign; the same steps and events per unit time. Medians of
# 9 runs each, interleaved. Goal: the switch's runs no slower than the impact's (<= 1, within
# the noise). The same pair as model files, 16 jobs each, in SIMD lanes and one at a time: the
# lanes' speed-up for a model with switches (goal: at least the impacting model's), and the
# switch's jobs against the impact's in lanes (goal <= 1). And the compliant stop located (a
# switch) against the same law unlocated (a ternary in a C++ definition): error and time.
# Writes the tables to bench/output/switching.md.
# Usage: bash bench/run_switching_bench.sh
#   BUILD_DIR=DIR (default build): the build directory to configure, build and run.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh tests bench
build=${BUILD_DIR:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DVIMPACT_BUILD_BENCH=ON > /dev/null
cmake --build "$build" -j"$(nproc)" --target switching_bench > /dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The model files compile once, into a cache of this run's own, outside the timed loops.
VIMPACT_CACHE_DIR="$tmp/cache" "$build"/switching_bench --benchmark_enable_random_interleaving=true --benchmark_format=json > "$tmp/s.json" 2> /dev/null
/usr/bin/python3 - "$tmp/s.json" <<'PY' | tee bench/output/switching.md
import json, sys
b = {x["run_name"].split("/repeats:")[0]: x for x in json.load(open(sys.argv[1]))["benchmarks"]
     if x.get("aggregate_name") == "median"}
print("| run | median wall [ms] | steps | rhs calls | impacts | crossings |")
print("|---|---|---|---|---|---|")
for run in ("protocol", "lyapunov"):
    for kind in ("impact", "switch"):
        r = b[f"{run}/{kind}"]
        print(f"| {run}, {kind} | {r['real_time']:.2f} | {int(r['steps'])} | {int(r['rhs_calls'])} | "
              f"{int(r['impacts'])} | {int(r['switchings'])} |")


def versus(label, run):
    """A row: the switch's time over the impact's in `run`, goal <= 1 with the same work."""
    s, i = b[f"{run}/switch"], b[f"{run}/impact"]
    q = s["real_time"] / i["real_time"]
    same = int(s["steps"]) == int(i["steps"]) and int(s["switchings"]) == int(i["impacts"])
    print(f"| {label} | {q:.3f} | <= 1 with the same steps and events: "
          f"{'met' if q <= 1.0 and same else 'NOT met'}{'' if same else ' (steps or events differ)'} |")


print()
print("| ratio switch / impact | value | goal |")
print("|---|---|---|")
for run in ("protocol", "lyapunov"):
    versus(run, run)
print()
print("| 16 model-file jobs | median wall [ms] | steps | impacts | crossings |")
print("|---|---|---|---|---|")
for run in ("alone", "lanes"):
    for kind in ("impact", "switch"):
        r = b[f"{run}/{kind}"]
        print(f"| {'one at a time' if run == 'alone' else 'in lanes'}, {kind} | {r['real_time']:.1f} | {int(r['steps'])} | "
              f"{int(r['impacts'])} | {int(r['switchings'])} |")
print()
print("| model-file jobs | value | goal |")
print("|---|---|---|")
gain = {kind: b[f"alone/{kind}"]["real_time"] / b[f"lanes/{kind}"]["real_time"] for kind in ("impact", "switch")}
print(f"| impact: one at a time / in lanes | {gain['impact']:.2f} | |")
print(f"| switch: one at a time / in lanes | {gain['switch']:.2f} | >= the impact's: "
      f"{'met' if gain['switch'] >= gain['impact'] else 'NOT met'} |")
versus("in lanes, switch / impact", "lanes")
print()
print("| compliant stop, 100 strobe points | median wall [ms] | steps | rejected | largest error |")
print("|---|---|---|---|---|")
for kind in ("located", "unlocated"):
    r = b[f"stop/{kind}"]
    name = "a switch (located)" if kind == "located" else "a ternary (unlocated)"
    print(f"| {name} | {r['real_time']:.2f} | {int(r['steps'])} | {int(r['rejected'])} | {r['error']:.2e} |")
PY
