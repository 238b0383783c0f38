#!/usr/bin/env bash
# Every number of docs/performance.md but the job loop's and the model table's, in one command:
#   1. like for like at the paper's protocol point (Ur = 16, rtol = atol = 1e-10): vimpact's
#      DOP853 and DOPRI5 beside Boost.Odeint's DOPRI5 and RKF78, the plain DOPRI5 loop,
#      SUNDIALS' CVODE (Adams) and ARKODE (ERK), medians of 7 runs each, side by side; then
#      one trial step alone, ours against Odeint's (bench/trial_bench.cpp);
#   2. the SIMD lanes: the engine on a 16 x 16 grid (bench/lanes_bench.cpp) built as the
#      library's lanes are, and where AVX-512 is available also with 256-bit lanes and with
#      512-bit lanes moved in halves (GCC's tuning), and for AVX2; and a 64 x 64 map (Ur 12..25 x sigma -0.2..0, the
#      full protocol) on one core, --batch 1 against the default batch (with AVX2_BUILD_DIR
#      set, also a whole build for AVX2, -march=haswell);
#   3. the work-precision diagram (bench/work_precision.py, with scipy unless --no-scipy);
#   4. the step-size controller's table (build/controller_bench);
#   5. with --map-costs: the per-job cost of a 200 x 200 map of the paper's protocol
#      (build/job_costs, the same file the distributed-run projection reads; about 10 minutes on
#      2 quiet cores) and its figure.
# Each part prints the load average before it runs. Outputs go to OUT (default
# bench/output): lanes.csv, like_for_like.md, trial.md, work_precision.{csv,png}, controller.md,
# job_costs_200x200.csv, map_costs.png.
# Usage: bash bench/run_performance.sh [--no-scipy] [--map-costs] [--quick] [--lanes-only]
#   BUILD_DIR (default build), AVX2_BUILD_DIR (optional), OUT (default bench/output)
#   --quick: the lanes on a 32 x 32 map and 3 runs per like-for-like point.
#   --lanes-only: part 2 alone (the other parts' outputs are left as they are).
set -euo pipefail
cd "$(dirname "$0")/.."
# The shared build directory builds the tests too: their packages and the benchmarks'.
bash scripts/install-deps.sh tests bench
build=${BUILD_DIR:-build}
out=${OUT:-bench/output}
scipy=1
costs=0
lanes_only=0
n=64
reps=7
for a in "$@"; do
  case "$a" in
    --no-scipy) scipy=0 ;;
    --map-costs) costs=1 ;;
    --quick) n=32; reps=3 ;;
    --lanes-only) lanes_only=1 ;;
    *) echo "unknown option $a" >&2; exit 2 ;;
  esac
done
mkdir -p "$out"
targets="vimpact_cli wp_vimpact baseline_odeint baseline_plain controller_bench job_costs lanes_bench lanes_bench_256 lanes_bench_512_split lanes_bench_avx2 fma_throughput trial_bench"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DVIMPACT_BUILD_BENCH=ON > /dev/null
cmake --build "$build" -j2 --target $targets > /dev/null
[ -x "$build/baseline_sundials" ] || cmake --build "$build" -j2 --target baseline_sundials > /dev/null 2>&1 || true
load() { echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"; }

if [ "$lanes_only" = 0 ]; then
echo "== 1. like for like: the protocol point, Ur = 16, rtol = atol = 1e-10"; load
/usr/bin/python3 bench/like_for_like.py "$build" "$reps" | tee "$out/like_for_like.md"
echo "-- one Runge-Kutta trial alone, a serial chain (bench/trial_bench.cpp), medians of 9"
"$build"/trial_bench --benchmark_repetitions=9 --benchmark_report_aggregates_only=true \
  --benchmark_format=json > "$out/trial.json" 2> /dev/null
/usr/bin/python3 - "$out/trial.json" <<'PY' | tee "$out/trial.md"
import json, sys
rows = [b for b in json.load(open(sys.argv[1]))["benchmarks"] if b.get("aggregate_name") == "median"]
print("| trial | stages | CPU ns per trial | ns per stage |")
print("|---|---|---|---|")
for b in rows:
    print(f"| {b['run_name']} | {b['stages']:.0f} | {b['cpu_time']:.1f} | {b['cpu_time'] / b['stages']:.1f} |")
PY
fi

echo "== 2. SIMD lanes: a $n x $n map on one core"; load
lanes_run() {  # build label
  local b=$1 label=$2
  for batch in 1 0; do
    # user CPU time of the one-threaded map: its cost, which the load of a shared machine does not inflate
    /usr/bin/time -f "%e %U" -o "$out/lanes-time" "$b"/vimpact map --x Ur:12:25:$n --y sigma:-0.2:0:$n --threads 1 \
      --batch $batch --no-plot --out "$out/lanes-map" > /dev/null
    read -r wall cpu < "$out/lanes-time"
    used=$(/usr/bin/python3 -c "import json; print(json.load(open('$out/lanes-map/run.json'))['result']['batch'])")
    echo "$label,$batch,$used,$((n * n)),$wall,$cpu" >> "$out/lanes.csv"
    cp "$out/lanes-map/labels.csv" "$out/lanes-labels-$label-$batch.csv"
  done
  cmp "$out/lanes-labels-$label-1.csv" "$out/lanes-labels-$label-0.csv" && echo "$label: labels identical with --batch 1 and lanes"
}
echo "-- multiply-add throughput per register width (bench/fma_throughput.cpp)"
"$build"/fma_throughput | tee "$out/fma_throughput.json"
echo "-- the engine alone, per instruction set (bench/lanes_bench.cpp, a 16 x 16 grid)"
"$build"/lanes_bench 16 | tee "$out/lanes_isa.jsonl"
if grep -q avx512f /proc/cpuinfo; then
  "$build"/lanes_bench_256 16 | tee -a "$out/lanes_isa.jsonl"
  "$build"/lanes_bench_512_split 16 | tee -a "$out/lanes_isa.jsonl"
fi
if grep -q avx2 /proc/cpuinfo; then "$build"/lanes_bench_avx2 16 | tee -a "$out/lanes_isa.jsonl"; fi
echo "-- vimpact map, --batch 1 against the default"
echo "build,batch_asked,batch_used,jobs,wall_s,cpu_s" > "$out/lanes.csv"
lanes_run "$build" native
if [ -n "${AVX2_BUILD_DIR:-}" ]; then
  cmake -S . -B "$AVX2_BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DVIMPACT_NATIVE=OFF -DCMAKE_CXX_FLAGS=-march=haswell \
    -DVIMPACT_BUILD_TESTS=OFF > /dev/null
  cmake --build "$AVX2_BUILD_DIR" -j2 --target vimpact_cli vimpact_modules > /dev/null
  lanes_run "$AVX2_BUILD_DIR" avx2
fi
/usr/bin/python3 - "$out/lanes.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("| build | batch | jobs | CPU time [s] | wall [s] | jobs per CPU second | speed-up (CPU time) |")
print("|---|---|---|---|---|---|---|")
for b in dict.fromkeys(r["build"] for r in rows):
    one = next(float(r["cpu_s"]) for r in rows if r["build"] == b and r["batch_asked"] == "1")
    for r in rows:
        if r["build"] == b:
            c = float(r["cpu_s"])
            print(f"| {b} | {r['batch_used']} | {r['jobs']} | {c:.1f} | {float(r['wall_s']):.1f} | "
                  f"{int(r['jobs']) / c:.1f} | {one / c:.2f} |")
PY
load

echo "-- the cost of a map against its number of jobs: the same region at three densities, one core, lanes"
echo "| grid | jobs | CPU time [s] | CPU ms per job |" | tee "$out/scaling.md"
echo "|---|---|---|---|" | tee -a "$out/scaling.md"
for k in 12 24 48; do
  /usr/bin/time -f "%U" -o "$out/scaling-time" "$build"/vimpact map --x Ur:12:25:$k --y sigma:-0.2:0:$k --threads 1 \
    --no-plot --out "$out/scaling-map" > /dev/null
  cpu=$(tail -1 "$out/scaling-time")
  /usr/bin/python3 -c "import sys; k, c = int(sys.argv[1]), float(sys.argv[2]); print(f'| {k} x {k} | {k * k} | {c:.2f} | {1e3 * c / (k * k):.2f} |')" "$k" "$cpu" | tee -a "$out/scaling.md"
done
rm -rf "$out/scaling-map" "$out/scaling-time"
load
rm -rf "$out"/lanes-labels-*.csv "$out/lanes-map" "$out/lanes-time"
[ "$lanes_only" = 0 ] || exit 0

echo "== 3. work-precision"; load
wp=()
[ "$scipy" = 1 ] || wp+=(--no-scipy)
/usr/bin/python3 bench/work_precision.py "$build" "$out" "${wp[@]}"

echo "== 4. step-size controller"; load
"$build"/controller_bench | tee "$out/controller.md"

if [ "$costs" = 1 ]; then
  echo "== 5. per-job cost of a 200 x 200 map"; load
  "$build"/job_costs 200 200 500 200 "$out/job_costs_200x200.csv" 2
  /usr/bin/python3 bench/plot_map_costs.py "$out/job_costs_200x200.csv" "$out/map_costs.png"
  load
fi
# Intermediate files: the maps' labels (compared above), the work-precision runs' points.
rm -rf "$out"/lanes-labels-*.csv "$out/lanes-map" "$out/lanes-time" "$out/pts.csv" "$out"/ref-*.csv "$out/trial.json"
# The figures docs/performance.md shows.
cp "$out/work_precision.png" docs/figures/work_precision.png
[ -f "$out/map_costs.png" ] && cp "$out/map_costs.png" docs/figures/map_costs.png
exit 0
