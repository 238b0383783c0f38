#!/usr/bin/env bash
# Regenerates the pictures and facts of docs/reproduction.md: runs every figure script at its
# default size (examples/all.sh, about 15 minutes on 2 cores, plus 2 for Figure 6), copies each plot.png to
# docs/figures/, and writes the quoted numbers to docs/reproduction-facts.txt.
# Usage: bash scripts/make-reproduction.sh [RESULTS_DIR]   (default results/reproduction)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-results/reproduction}
if [ ! -d "$out/fig2a" ]; then OUT="$out" bash examples/all.sh; fi
mkdir -p docs/figures
for d in "$out"/fig*; do
  name=$(basename "$d")
  if [ -f "$d/plot.png" ]; then cp "$d/plot.png" "docs/figures/$name.png"; fi
  for extra in "$d"/fig6?.png; do
    [ -f "$extra" ] && cp "$extra" docs/figures/
  done
  for sub in "$d"/*/; do  # the sub-runs the document shows
    case "$name-$(basename "$sub")" in
      fig2d-h-*|fig6-band-*) [ -f "$sub/plot.png" ] && cp "$sub/plot.png" "docs/figures/$name-$(basename "$sub").png" ;;
    esac
  done
done
/usr/bin/python3 scripts/reproduction_facts.py "$out" > docs/reproduction-facts.txt
echo "pictures in docs/figures/, numbers in docs/reproduction-facts.txt"
