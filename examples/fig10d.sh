#!/usr/bin/env bash
# Figure 10d: y(t) with the barrier at sigma = -0.130979, Ur = 25, A = 10 with A/eps = 50, 40, 30.
source "$(dirname "$0")/lib.sh"
dirs=()
for eps in 0.2 0.25 0.3333333333333333; do
  d="$OUT/fig10d/eps$eps"
  "$VIMPACT" simulate --set Ur=25 --set sigma=-0.130979 --set A=10 --set "eps=$eps" "${PROTO[@]}" --no-plot --out "$d" > /dev/null
  dirs+=("$d")
done
overlay timeseries "$OUT/fig10d/plot.png" "${dirs[@]}"
