#!/usr/bin/env bash
# Regenerates the pictures of docs/continuation.md (after a build): the P1 and P2 branches
# near Ur = 15 and Figure 5g's neighbourhood from the command line, and Figures 2a, 4 and 5b
# with their skeleton from examples/python/continuation.py (about 4 minutes on 2 cores).
# Usage: bash scripts/make-continuation-figures.sh [RESULTS_DIR]   (default results)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-results}
rm -rf "$out/continuation-p1p2" "$out/continuation-fig5"
build/vimpact continue --param Ur --range 14:16 --switch 1 --diagram 201 --out "$out/continuation-p1p2" > /dev/null
build/vimpact continue --set Ur=25 --set sigma=-0.03 --param sigma --range -0.03:-0.01 --switch 2 --diagram 201 \
    --out "$out/continuation-fig5" > /dev/null
OUT="$out" PYTHONPATH=build/python MPLBACKEND=Agg /usr/bin/python3 examples/python/continuation.py > /dev/null
mkdir -p docs/figures
cp "$out/continuation-p1p2/plot.png" docs/figures/continuation-p1p2.png
cp "$out/continuation-fig5/plot.png" docs/figures/continuation-fig5.png
cp "$out/python/continuation-fig2a.png" docs/figures/continuation-fig2a.png
cp "$out/python/continuation-fig4.png" docs/figures/continuation-fig4.png
cp "$out/python/continuation.png" docs/figures/continuation-fig5b.png
echo "docs/figures/continuation-{p1p2,fig5,fig2a,fig4,fig5b}.png"
