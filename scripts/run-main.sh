#!/usr/bin/env bash
# Installs the dependencies, builds vimpact and runs the main job: the paper's Figure 2a, the
# bifurcation diagram of y at the section over 12 <= Ur <= 25 (sigma = -0.150298, r = 0.8,
# paper preset, 521 points, every core), written to results/fig2a/ (plot.png, points.csv,
# labels.csv, run.json).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh main
installed=$SECONDS
# Neither the tests nor the benchmarks: their packages are not installed for the main job.
# A unity build (sources compiled in batches: each header parsed once a batch) takes about
# half the CPU of one source at a time; a new build directory is built with Ninja.
options=(-DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON -DVIMPACT_BUILD_TESTS=OFF -DVIMPACT_BUILD_BENCH=OFF)
[ -f build/CMakeCache.txt ] || options+=(-GNinja)
cmake -S . -B build "${options[@]}" > build.log 2>&1 || { cat build.log; exit 1; }
# The program and its default model's module first (the picture is drawn by the package's
# pure-Python part); the other models' modules (built-in models, model files, loaded when a
# run needs them) and the Python module (the bindings, for `import vimpact`) are built after
# the main job has shown it.
cmake --build build -j"$(nproc)" --target vimpact_cli >> build.log 2>&1 || { tail -50 build.log; exit 1; }
built=$SECONDS
OUT=results bash examples/fig2a.sh
echo "main job done: the picture is results/fig2a/plot.png (data: results/fig2a/*.csv, record: results/fig2a/run.json)"
echo "first picture after $SECONDS s: install $installed s, build $((built - installed)) s, main job $((SECONDS - built)) s"
echo "building the other models' modules and the Python module (PYTHONPATH=build/python)"
cmake --build build -j"$(nproc)" >> build.log 2>&1 || { tail -50 build.log; exit 1; }
