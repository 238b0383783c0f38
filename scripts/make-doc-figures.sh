#!/usr/bin/env bash
# Regenerates the pictures of docs/own-model.md and docs/engineering.md from the commands they
# show (after a build).
# Usage: bash scripts/make-doc-figures.sh [RESULTS_DIR]   (default results)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-results}
rm -rf "$out/pendulum"
build/vimpact sweep --model examples/models/impacting_pendulum.toml --section strobe --set w=1.3 --param a \
    --range 0.8:0.94:141 --out "$out/pendulum" > /dev/null
mkdir -p docs/figures
cp "$out/pendulum/plot.png" docs/figures/own-model-pendulum.png
echo "docs/figures/own-model-pendulum.png"
rm -rf "$out/tube-clearance"
build/vimpact clearance --si D=0.02,m=0.6,fn=12,zeta=0.002,rho=1000 --speeds 3:6:13 --out "$out/tube-clearance" \
    > /dev/null
cp "$out/tube-clearance/plot.png" docs/figures/engineering-clearance.png
echo "docs/figures/engineering-clearance.png"
