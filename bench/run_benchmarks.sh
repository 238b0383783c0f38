#!/usr/bin/env bash
# Side-by-side benchmark of one point of the paper's protocol (Ur = 16, sigma = -0.150298,
# paper preset, 500 impacts discarded, 200 maxima kept, rtol = atol = 1e-10):
#   vimpact (DOP853 and DOPRI5), Boost.Odeint DOPRI5 + bisection, scipy solve_ivp RK45 and DOP853.
# Accuracy: max |y| difference of the 200 section points against a reference run of vimpact
# at rtol = atol = 1e-13 (`vimpact period --out`, its sections.csv). Prints a Markdown table
# (the documents quote bench/like_for_like.py's table instead: docs/performance.md).
# Usage: bash bench/run_benchmarks.sh [--no-scipy]
#   BUILD_DIR=DIR (default build): the build directory to configure, build and run.
set -euo pipefail
cd "$(dirname "$0")/.."
# The shared build directory builds the tests too: their packages and the benchmarks'.
bash scripts/install-deps.sh tests bench
build=${BUILD_DIR:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DVIMPACT_BUILD_BENCH=ON > /dev/null
cmake --build "$build" -j"$(nproc)" --target vimpact_cli protocol_bench baseline_odeint > /dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$build"/vimpact period --set Ur=16 --rtol 1e-13 --atol 1e-13 --no-plot --out "$tmp/ref" > /dev/null
"$build"/vimpact period --set Ur=16 --no-plot --out "$tmp/dop853" > /dev/null
"$build"/vimpact period --set Ur=16 --method dopri5 --no-plot --out "$tmp/dopri5" > /dev/null
"$build"/protocol_bench --benchmark_format=json > "$tmp/bench.json" 2> /dev/null
"$build"/baseline_odeint --repeat 7 --points "$tmp/odeint.csv" > "$tmp/odeint.json"
if [ "${1:-}" != "--no-scipy" ]; then
  for m in RK45 DOP853; do
    /usr/bin/python3 bench/baseline_scipy.py --method "$m" --repeat 3 --points "$tmp/scipy-$m.csv" > "$tmp/scipy-$m.json"
  done
fi
/usr/bin/python3 bench/summarize.py "$tmp"
