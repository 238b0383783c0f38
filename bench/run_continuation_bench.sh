#!/usr/bin/env bash
# Cost of continuation against Floquet points (bench/continuation_bench.cpp), medians of 5
# repetitions in one run: the P1 branch over 12 <= Ur <= 15.1 with its period doubling (from the
# attractor, and from a point of the orbit: the continuation alone), its time per point, and the ratios to a Floquet point from a point (Newton and monodromy) and to
# a whole Floquet analysis (the protocol first). Prints the table of docs/continuation.md.
# Usage: bash bench/run_continuation_bench.sh   (BUILD_DIR=DIR, default build)
set -euo pipefail
cd "$(dirname "$0")/.."
# The shared build directory builds the tests too: their packages and the benchmarks'.
bash scripts/install-deps.sh tests bench
build=${BUILD_DIR:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DVIMPACT_BUILD_BENCH=ON > /dev/null
cmake --build "$build" -j"$(nproc)" --target continuation_bench > /dev/null
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
"$build"/continuation_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
    --benchmark_format=json > "$tmp" 2> /dev/null
/usr/bin/python3 - "$tmp" <<'PY'
import json, sys
runs = {b["run_name"].split("/")[0]: b for b in json.load(open(sys.argv[1]))["benchmarks"] if b.get("aggregate_name") == "median"}
branch = runs["p1_branch_with_its_period_doubling"]
alone = runs["p1_branch_from_a_point"]
point = alone["real_time"] / alone["points"]
near = runs["floquet_from_a_point"]["real_time"]
full = runs["floquet_with_its_protocol"]["real_time"]
print(f"| measure (medians of 5, one run) | value |")
print(f"|---|---|")
print(f"| P1 branch, Ur 12 -> 15.1, {branch['points']:.0f} points, period doubling at Ur = {branch['pd_Ur']:.10f} "
      f"| {branch['real_time']:.1f} ms |")
print(f"| section-map evaluations of the branch (with tangent / without) | {branch['tangent_maps']:.0f} / "
      f"{branch['plain_maps']:.0f} |")
print(f"| the same branch from a point of the orbit (no protocol first) | {alone['real_time']:.1f} ms |")
print(f"| one continuation point (that time / points) | {point:.2f} ms |")
print(f"| one Floquet point from a point (Newton + monodromy) | {near:.2f} ms |")
print(f"| one Floquet point with its protocol (a stability sweep's) | {full:.2f} ms |")
print(f"| continuation point / Floquet point from a point | {point / near:.2f} |")
print(f"| continuation point / Floquet point with its protocol | {point / full:.3f} |")
bare = runs["p1_branch_from_a_point_points_only"]
per = bare["real_time"] / bare["points"]
print(f"| without bifurcation tests: {bare['points']:.0f} points, maps with tangent / without "
      f"{bare['tangent_maps']:.0f} / {bare['plain_maps']:.0f} | {bare['real_time']:.1f} ms |")
print(f"| one point of it | {per:.2f} ms |")
print(f"| that point / Floquet point from a point | {per / near:.2f} |")
print(f"| that point / Floquet point with its protocol | {per / full:.3f} |")
PY
