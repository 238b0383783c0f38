#!/usr/bin/env bash
# Installs the dependencies, builds vimpact and runs the main job: the paper's Figure 2a, the
# bifurcation diagram of y at the section over 12 <= Ur <= 25 (sigma = -0.150298, r = 0.8,
# paper preset, 521 points, every core), written to results/fig2a/ (plot.png, points.csv,
# labels.csv, run.json).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh main
# Neither the tests nor the benchmarks: their packages are not installed for the main job.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DVIMPACT_BUILD_TESTS=OFF -DVIMPACT_BUILD_BENCH=OFF > build.log 2>&1 || { cat build.log; exit 1; }
# The program first: the picture is drawn by the package's pure-Python part, so the Python
# module (the bindings, for `import vimpact`) is built after the main job has shown it.
cmake --build build -j"$(nproc)" --target vimpact_cli >> build.log 2>&1 || { tail -50 build.log; exit 1; }
OUT=results bash examples/fig2a.sh
echo "main job done: the picture is results/fig2a/plot.png (data: results/fig2a/*.csv, record: results/fig2a/run.json)"
echo "building the Python module (PYTHONPATH=build/python)"
cmake --build build -j"$(nproc)" --target _vimpact >> build.log 2>&1 || { tail -50 build.log; exit 1; }
