#!/usr/bin/env bash
# MPI runs, measured (docs/distributed.md quotes the output): one command re-runs it all.
#  1. Speed-up from 1 to 2 ranks (one thread each) on a map with the paper's protocol, beside
#     1 rank with 2 threads; the three run in turn, REPEATS times, and the medians are compared.
#  2. Memory of rank 0 on a 1000 x 1000 map with a shortened protocol (--transient 5
#     --record 10) on 2 ranks: its resident set sampled every 2 s against the jobs done, for
#     at most MEM_SECONDS (then SIGTERM), and the peak of whole smaller maps.
#  3. The cost (thread CPU time) of every job of a 200 x 200 map (bench/job_costs.cpp, on
#     COST_THREADS threads, default 2; the costs file is kept), and from it the simulated schedule of a 1000 x 1000 map at 64, 256
#     and 1024 ranks (bench/schedule_sim.cpp).
# The machine's load average is printed with each measurement: timings on a busy machine are
# slower and noisier (the per-job costs least, being single-threaded).
# Usage: bash bench/run_mpi_bench.sh [1] [2] [3]   (default: all)
#   BUILD_DIR (build), OUT_DIR (bench/output), REPEATS (3), MEM_SECONDS (240),
#   COSTS=FILE: skip the 200 x 200 measurement and project from FILE.
set -euo pipefail
cd "$(dirname "$0")/.."
# The shared build directory builds the tests too: their packages and the benchmarks'.
bash scripts/install-deps.sh tests bench
build=${BUILD_DIR:-build}
out_dir=${OUT_DIR:-bench/output}
repeats=${REPEATS:-3}
mem_seconds=${MEM_SECONDS:-240}
parts=("$@")
[ ${#parts[@]} -eq 0 ] && parts=(1 2 3)
want() { [[ " ${parts[*]} " == *" $1 "* ]]; }
mkdir -p "$out_dir"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DVIMPACT_BUILD_BENCH=ON > /dev/null
cmake --build "$build" -j2 --target vimpact_cli job_costs schedule_sim > /dev/null
vimpact=$(realpath "$build/vimpact")
mpirun=(mpirun --oversubscribe)
[ "$(id -u)" -eq 0 ] && mpirun+=(--allow-run-as-root)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
load() { cut -d' ' -f1-3 /proc/loadavg; }
echo "# MPI benchmark, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores, git $(git rev-parse --short=12 HEAD)"

if want 1; then
  # 2304 jobs, about 15 s on one core in SIMD lanes: mpirun's start (0.36 s here) stays a small part.
  map=(map --x Ur:14:26:48 --y sigma:-0.16:-0.02:48 --tol 1e-5 --no-plot)
  echo
  echo "## 1. Speed-up: ${map[*]} (2304 jobs, the default protocol)"
  echo
  echo "| layout | run | wall [s] | CPU, all processes [s] | load before (1, 5, 15 min) |"
  echo "|---|---|---|---|---|"
  declare -A walls cpus
  for rep in $(seq 1 "$repeats"); do
    for layout in "1x1" "2x1" "1x2"; do
      ranks=${layout%x*} threads=${layout#*x}
      l=$(load)
      rm -rf "$tmp/s" "$tmp/s.jobs"
      if [ "$ranks" -eq 1 ]; then
        /usr/bin/time -f '%e %U %S' -o "$tmp/t" "$vimpact" "${map[@]}" --threads "$threads" --out "$tmp/s" > /dev/null
      else
        /usr/bin/time -f '%e %U %S' -o "$tmp/t" "${mpirun[@]}" -n "$ranks" "$vimpact" "${map[@]}" --threads "$threads" \
          --out "$tmp/s" > /dev/null
      fi
      read -r w u s < <(tail -1 "$tmp/t")
      c=$(echo "$u + $s" | bc -l)
      walls[$layout]+="$w "
      cpus[$layout]+="$c "
      printf '| %s ranks x %s threads | %d | %.2f | %.2f | %s |\n' "$ranks" "$threads" "$rep" "$w" "$c" "$l"
    done
  done
  /usr/bin/python3 - "${walls[1x1]}" "${walls[2x1]}" "${walls[1x2]}" "${cpus[1x1]}" "${cpus[2x1]}" "${cpus[1x2]}" <<'PY'
import statistics, sys
one, two, thr, c1, c2, ct = (statistics.median(map(float, a.split())) for a in sys.argv[1:7])
print(f"\nmedians: 1 rank {one:.2f} s, 2 ranks {two:.2f} s, 1 rank x 2 threads {thr:.2f} s (wall)")
print(f"speed-up 1 -> 2 ranks: {one / two:.3f} (1 -> 2 threads: {one / thr:.3f}): wall times, meaningful on an idle machine")
# The CPU time of all processes does not depend on how a busy machine shares its cores: the
# extra CPU of 2 ranks over 1 is the cost of distributing, and bounds the idle-machine speed-up.
print(f"CPU of all processes: 1 rank {c1:.2f} s, 2 ranks {c2:.2f} s, 1 rank x 2 threads {ct:.2f} s; "
      f"2 x CPU(1 rank) / CPU(2 ranks) = {2 * c1 / c2:.3f} (the speed-up of 2 ranks on 2 idle cores if "
      f"they were never idle; 2 threads: {2 * c1 / ct:.3f})")
PY
fi

if want 2; then
  echo
  echo "## 2. Memory of rank 0: map 1000 x 1000, --transient 5 --record 10, 2 ranks x 1 thread"
  echo
  big=(map --x Ur:14:26:1000 --y sigma:-0.16:-0.02:1000 --tol 1e-5 --transient 5 --record 10 --no-plot)
  rm -rf "$tmp/m" "$tmp/m.jobs"
  echo "load before: $(load)"
  echo
  echo "| elapsed [s] | jobs done | rank 0 RSS [MiB] |"
  echo "|---|---|---|"
  "${mpirun[@]}" -n 2 "$vimpact" "${big[@]}" --threads 1 --out "$tmp/m" > "$tmp/m.log" 2>&1 &
  launcher=$!
  rank0=""
  start=$(date +%s)
  peak=0
  while kill -0 "$launcher" 2> /dev/null; do
    sleep 2
    if [ -z "$rank0" ]; then
      for p in $(pgrep -P "$launcher" || true); do
        if tr '\0' '\n' < "/proc/$p/environ" 2> /dev/null | grep -qx 'OMPI_COMM_WORLD_RANK=0'; then rank0=$p; fi
      done
    fi
    [ -n "$rank0" ] || continue
    rss=$(awk '/^VmRSS/ {print $2}' "/proc/$rank0/status" 2> /dev/null || echo 0)
    hwm=$(awk '/^VmHWM/ {print $2}' "/proc/$rank0/status" 2> /dev/null || echo 0)
    [ -n "$hwm" ] && [ "$hwm" -gt "$peak" ] && peak=$hwm
    done_jobs=$( (cat "$tmp"/m.jobs/*.jsonl 2> /dev/null || true) | wc -l)
    elapsed=$(( $(date +%s) - start ))
    if [ -n "$rss" ] && [ "$rss" -gt 0 ] && [ $(( elapsed % 10 )) -lt 2 ]; then
      printf '| %d | %d | %.1f |\n' "$elapsed" "$done_jobs" "$(echo "$rss / 1024" | bc -l)"
    fi
    if [ "$elapsed" -ge "$mem_seconds" ]; then kill -TERM "$launcher"; fi
  done
  wait "$launcher" || true
  echo
  printf 'rank 0 peak RSS (VmHWM) %.1f MiB; ' "$(echo "$peak / 1024" | bc -l)"
  if [ -f "$tmp/m/run.json" ]; then echo "the map completed ($(( $(wc -l < "$tmp/m/labels.csv") - 1 )) cells)"
  else echo "stopped after ${mem_seconds} s with $( (cat "$tmp"/m.jobs/*.jsonl 2> /dev/null || true) | wc -l) jobs in the journal"; fi
  echo "load after: $(load)"
  echo
  echo "Whole maps, one process, 2 threads (peak RSS of the process):"
  echo
  echo "| grid | jobs | peak RSS [MiB] |"
  echo "|---|---|---|"
  for n in 50 150 450; do
    rm -rf "$tmp/w"
    /usr/bin/time -f '%M' -o "$tmp/w.time" "$vimpact" map --x "Ur:14:26:$n" --y "sigma:-0.16:-0.02:$n" --tol 1e-5 \
      --transient 5 --record 10 --no-plot --threads 2 --out "$tmp/w" > /dev/null
    printf '| %d x %d | %d | %.1f |\n' "$n" "$n" $(( n * n )) "$(echo "$(tail -1 "$tmp/w.time") / 1024" | bc -l)"
  done
fi

if want 3; then
  echo
  echo "## 3. Job costs (thread CPU time) of a 200 x 200 map and the projected schedule of 1000 x 1000"
  echo
  costs=${COSTS:-}
  if [ -z "$costs" ]; then
    costs="$out_dir/job_costs_200x200.csv"
    echo "measuring: load before $(load)"
    t0=$(date +%s)
    "$build/job_costs" 200 200 500 200 "$costs" "${COST_THREADS:-2}"
    echo "measured in $(( $(date +%s) - t0 )) s; load after $(load)"
  fi
  /usr/bin/python3 - "$costs" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
s = sorted(float(r["seconds"]) for r in rows)
n = len(s)
mean = sum(s) / n
print(f"\n{n} jobs from {sys.argv[1]}: mean {mean * 1e3:.2f} ms, median {s[n // 2] * 1e3:.2f} ms, "
      f"p99 {s[int(0.99 * n)] * 1e3:.2f} ms, max {s[-1] * 1e3:.2f} ms (max / median {s[-1] / s[n // 2]:.1f}); "
      f"total {sum(s):.0f} s")
by = {}
for r in rows:
    by.setdefault(r["label"], []).append(float(r["seconds"]))
print("\n| label | jobs | mean cost [ms] |\n|---|---|---|")
for k, v in sorted(by.items(), key=lambda kv: -len(kv[1]))[:8]:
    print(f"| {k} | {len(v)} | {sum(v) / len(v) * 1e3:.2f} |")
PY
  # Real journal lines of this build for the coordinator's cost per result: half a map's jobs
  # as a shard (the journal stays), and the lanes' throughput on one thread (a map with and
  # without --batch 1), which divides every job's cost in the projection of a run in lanes.
  rm -rf "$tmp/lines" "$tmp/lines.jobs" "$tmp/b1" "$tmp/b8"
  "$vimpact" map --x Ur:14:26:20 --y sigma:-0.16:-0.02:20 --transient 50 --record 20 --threads 2 --no-plot \
    --shard 1/2 --out "$tmp/lines" > /dev/null
  lines=$(ls "$tmp"/lines.jobs/*.jsonl | head -1)
  echo "lanes: load before $(load)"
  cpu() { /usr/bin/time -f '%U' "$@" 2>&1 > /dev/null | tail -1; }
  b1=$(cpu "$vimpact" map --x Ur:12:25:24 --y sigma:-0.2:0:24 --threads 1 --batch 1 --no-plot --out "$tmp/b1")
  bw=$(cpu "$vimpact" map --x Ur:12:25:24 --y sigma:-0.2:0:24 --threads 1 --no-plot --out "$tmp/b8")
  batch=$(grep -o '"batch": *[0-9]*' "$tmp/b8/run.json" | head -1 | grep -o '[0-9]*$')
  speedup=$(echo "$b1 / $bw" | bc -l)
  printf 'map 24 x 24, one thread: --batch 1 %s s CPU, lanes (batch %s) %s s CPU: %.2fx\n' "$b1" "$batch" "$bw" "$speedup"
  echo
  echo "| ranks x threads | jobs | costs | makespan [s] | ideal [s] | efficiency | coordinator messages/s | coordinator busy | largest reorder buffer |"
  echo "|---|---|---|---|---|---|---|---|---|"
  for lanes in 1 "$batch"; do
    sp=1
    [ "$lanes" != 1 ] && sp=$speedup
    for mode in upsampled resampled; do
      for r in 64 256 1024; do
        "$build/schedule_sim" "$costs" 1000 1000 "$r" 1 "$mode" 20 5 "$lines" "$lanes" "$sp" > "$tmp/sim.json"
        /usr/bin/python3 - "$tmp/sim.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
how = "one at a time" if j["batch"] == 1 else f"lanes (batch {j['batch']}, {j['lanes_speedup']:.2f}x)"
print(f"| {j['ranks']} x {j['threads_per_rank']} | {how} | {j['costs']} | {j['makespan_s']:.1f} | {j['ideal_s']:.1f} | "
      f"{100 * j['efficiency']:.2f}% | {j['messages_per_s']:.0f} | {100 * j['coordinator_busy']:.1f}% | "
      f"{j['max_reorder_buffer']} |")
PY
      done
    done
  done
  /usr/bin/python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print(f\"\nmodel constants: latency {j['latency_us']:g} us one way, {j['message_us']:g} us per message, {j['record_us']:.2f} us per result (measured here on this build's journal lines of a map: read the line, decode the cell, format its labels.csv row, append the line to the journal)\")" "$tmp/sim.json"
fi
