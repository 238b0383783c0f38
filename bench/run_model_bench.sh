#!/usr/bin/env bash
# The price of defining a model another way (bench/model_bench.cpp), on the paper's model at
# Ur = 16 with DOP853 (medians of 9 runs):
#  1. the protocol point with the built-in model against the same model as a model file
#     (examples/models/wake_impact.toml); goal: within 1.15x, with the same steps; and as the
#     equations read (bench/models/wake_impact_natural.toml); goal: within 1.1x;
#  2. a Floquet point with hand-written derivatives against automatic ones; goal: within 1.3x;
#  3. the tangent part of that point alone (shooting and monodromy), the same two: the price
#     of automatic derivatives in the tangent runs, undiluted by the protocol (no goal).
# Prints a Markdown table and the ratios.
# Usage: bash bench/run_model_bench.sh
#   BUILD_DIR=DIR (default build): the build directory to configure, build and run.
set -euo pipefail
cd "$(dirname "$0")/.."
# The shared build directory builds the tests too: their packages and the benchmarks'.
bash scripts/install-deps.sh tests bench
build=${BUILD_DIR:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DVIMPACT_BUILD_BENCH=ON > /dev/null
cmake --build "$build" -j"$(nproc)" --target model_bench > /dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# From the repository root: the benchmark loads examples/models/wake_impact.toml.
"$build"/model_bench --benchmark_format=json > "$tmp/model.json" 2> /dev/null
/usr/bin/python3 - "$tmp/model.json" <<'PY'
import json, sys
b = {x["run_name"].split("/repeats:")[0]: x for x in json.load(open(sys.argv[1]))["benchmarks"]
     if x.get("aggregate_name") == "median"}
rows = [("protocol, built-in model", "protocol_Ur16/built-in"),
        ("protocol, model file", "protocol_Ur16/model-file"),
        ("protocol, model file as the equations read", "protocol_Ur16/model-file-natural"),
        ("Floquet point, hand-written derivatives", "floquet_Ur16/hand-written"),
        ("Floquet point, automatic derivatives", "floquet_Ur16/automatic"),
        ("tangent part (shooting + monodromy), hand-written", "floquet_tangent_Ur16/hand-written"),
        ("tangent part (shooting + monodromy), automatic", "floquet_tangent_Ur16/automatic")]
print("| run | median wall [ms] | steps | rhs calls |")
print("|---|---|---|---|")
for label, key in rows:
    r = b[key]
    steps = f"{int(r['steps'])}"
    if "map_evaluations" in r:
        steps += f" (last of {int(r['map_evaluations'])} maps)"
    print(f"| {label} | {r['real_time']:.2f} | {steps} | {int(r['rhs_calls'])} |")

def ratio(slow, fast):
    return b[slow]["real_time"] / b[fast]["real_time"]

print()
print("| ratio | value | goal |")
print("|---|---|---|")
same = int(b["protocol_Ur16/model-file"]["steps"]) == int(b["protocol_Ur16/built-in"]["steps"])
r1 = ratio("protocol_Ur16/model-file", "protocol_Ur16/built-in")
print(f"| model file / built-in, protocol | {r1:.3f} | <= 1.15 with equal steps: "
      f"{'met' if r1 <= 1.15 and same else 'NOT met'}{'' if same else ' (steps differ)'} |")
natural_same = int(b["protocol_Ur16/model-file-natural"]["steps"]) == int(b["protocol_Ur16/built-in"]["steps"])
rn = ratio("protocol_Ur16/model-file-natural", "protocol_Ur16/built-in")
print(f"| model file as the equations read / built-in, protocol | {rn:.3f} | <= 1.1 with equal steps: "
      f"{'met' if rn <= 1.1 and natural_same else 'NOT met'}{'' if natural_same else ' (steps differ)'} |")
r2 = ratio("floquet_Ur16/automatic", "floquet_Ur16/hand-written")
print(f"| automatic / hand-written, Floquet point | {r2:.3f} | <= 1.3: {'met' if r2 <= 1.3 else 'NOT met'} |")
r3 = ratio("floquet_tangent_Ur16/automatic", "floquet_tangent_Ur16/hand-written")
print(f"| automatic / hand-written, tangent part | {r3:.3f} | (none) |")
PY
