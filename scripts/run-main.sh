#!/usr/bin/env bash
# Installs the dependencies, builds vimpact and runs the main job: the paper's protocol at
# Ur = 16 (paper preset), written to results/main/ (CSV, JSON record, PNG).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > build.log 2>&1 || { cat build.log; exit 1; }
cmake --build build -j"$(nproc)" >> build.log 2>&1 || { tail -50 build.log; exit 1; }
build/vimpact period --set Ur=16
build/vimpact simulate --set Ur=16 --out results/main
echo "main job done: open results/main/plot.png (data: results/main/*.csv, record: results/main/run.json)"
