#!/usr/bin/env bash
# The job loop's goals, measured side by side in one run:
#  1. jobs per second of the paper's protocol with 1 and 2 threads: the library's sweep over
#     64 values of Ur (bench/jobs_bench.cpp);
#  2. peak memory (max RSS) of `vimpact map` over a 200 x 200 grid, and of the same map at
#     50 x 50: the difference is what grows with the number of jobs.
# The map runs a shortened protocol (--transient 50 --record 50: under a minute on 2 cores
# instead of about half an hour); per-job memory does not depend on the protocol length.
# Usage: bash bench/run_jobs_bench.sh
#   BUILD_DIR=DIR (default build): the build directory to configure, build and run.
set -euo pipefail
cd "$(dirname "$0")/.."
# The shared build directory builds the tests too: their packages and the benchmarks'.
bash scripts/install-deps.sh tests bench
build=${BUILD_DIR:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DVIMPACT_BUILD_BENCH=ON > /dev/null
cmake --build "$build" -j"$(nproc)" --target vimpact_cli jobs_bench > /dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$build"/jobs_bench --benchmark_format=json > "$tmp/jobs.json" 2> /dev/null
/usr/bin/python3 - "$tmp" "$build" <<'PY'
import json, os, resource, subprocess, sys, time
d, build = sys.argv[1], sys.argv[2]
b = {x["run_name"]: x for x in json.load(open(os.path.join(d, "jobs.json")))["benchmarks"]
     if x.get("aggregate_name") == "median"}
one, two = b["sweep_64_jobs/threads/1/repeats:5/real_time"], b["sweep_64_jobs/threads/2/repeats:5/real_time"]
print("| threads | median wall for 64 jobs [ms] | jobs/s |")
print("|---|---|---|")
for n, r in (("1", one), ("2", two)):
    print(f"| {n} | {r['real_time']:.0f} | {r['items_per_second']:.1f} |")
print(f"\nspeed-up 2 vs 1 thread: {two['items_per_second'] / one['items_per_second']:.3f}\n")

# ru_maxrss of the children is the largest of any child so far: the maps run smallest first.
def peak(n):
    t = time.time()
    subprocess.run([os.path.join(build, "vimpact"), "map", "--x", f"Ur:12:25:{n}", "--y", f"sigma:-0.25:0:{n}",
                    "--transient", "50", "--record", "50", "--no-plot", "--out", os.path.join(d, f"map{n}")],
                   check=True, stdout=subprocess.DEVNULL)
    wall = time.time() - t
    return resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0, wall

print("| map grid | jobs | peak RSS [MiB] | wall [s] |")
print("|---|---|---|---|")
for n in (50, 200):
    mib, wall = peak(n)
    print(f"| {n} x {n} | {n * n} | {mib:.1f} | {wall:.0f} |")
PY
