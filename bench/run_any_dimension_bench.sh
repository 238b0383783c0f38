#!/usr/bin/env bash
# A model of a dimension without fixed-size states in the build (6 states: two copies of the
# two-sided impact oscillator, bench/models/two_oscillators.toml) on states sized at run time
# against the same model on fixed-size states compiled for the benchmark: time per step (the
# best of 3 runs) and heap allocations (every malloc of the process) of a protocol run, with
# the stops in reach (impacting) and out of reach (free flight), and of a Floquet point.
# Goal (issue "your own system as fast and as large as a built-in"): no allocation per step
# on states sized at run time. Writes bench/output/any_dimension.md.
# Usage: bash bench/run_any_dimension_bench.sh
#   BUILD_DIR=DIR (default build): the build directory to configure, build and run.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh tests bench
build=${BUILD_DIR:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DVIMPACT_BUILD_BENCH=ON > /dev/null
cmake --build "$build" -j"$(nproc)" --target any_dimension_bench > /dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export VIMPACT_CACHE_DIR="$tmp/cache"
"$build"/any_dimension_bench bench/models/two_oscillators.toml > "$tmp/out.txt"
/usr/bin/python3 - "$tmp/out.txt" > bench/output/any_dimension.md <<'PY'
import re, sys
rows, stops = [], None
for line in open(sys.argv[1]):
    m = re.match(r"stops at d = (\S+)", line)
    if m:
        stops = "impacting" if float(m.group(1)) < 10 else "free flight"
        continue
    m = re.match(r"(\w+)\s+simulate: (\d+) steps, (\d+) impacts, ([\d.]+) ns/step, [\d.]+ allocations/step \((\d+)\); "
                 r"floquet: ([\d.]+) ms, (\d+) allocations", line)
    if m:
        rows.append((stops, m.group(1), *m.groups()[1:]))
print("| run | states | steps | impacts | ns per step | allocations | per step | per impact | Floquet point [ms] | its allocations |")
print("|---|---|---|---|---|---|---|---|---|---|")
for stops, kind, steps, impacts, ns, allocs, fms, fallocs in rows:
    steps, impacts, allocs = int(steps), int(impacts), int(allocs)
    per_impact = f"{allocs / impacts:.2f}" if impacts else "-"
    print(f"| {stops} | {kind} | {steps} | {impacts} | {float(ns):.0f} | {allocs} | {allocs / steps:.3f} | {per_impact} | {fms} | {fallocs} |")
print()
for stops in ("impacting", "free flight"):
    t = {k: float(ns) for s, k, _, _, ns, *_ in rows if s == stops}
    print(f"- {stops}: runtime-sized / fixed-size time per step = {t['dynamic'] / t['fixed']:.2f}")
PY
cat bench/output/any_dimension.md
