#!/usr/bin/env bash
# Figures 2d-h: time series and phase portraits, aperiodic at Ur = 24.4, P2 at 16, P3 at 19,
# P4 at 21.5 and P8 at 24.8 (impacts 500-700 in the paper: 500 discarded, 200 maxima kept).
source "$(dirname "$0")/lib.sh"
for ur in 24.4 16 19 21.5 24.8; do
  "$VIMPACT" simulate --set "Ur=$ur" "${PROTO[@]}" --out "$OUT/fig2d-h/Ur$ur" > /dev/null
done
echo "written: $OUT/fig2d-h/Ur*/plot.png"
