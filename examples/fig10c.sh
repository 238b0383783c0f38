#!/usr/bin/env bash
# Figure 10c: y(t) with the barrier at sigma = -0.13181 (as printed), Ur = 25, A = 14, 12, 10
# with A/eps = 40.
source "$(dirname "$0")/lib.sh"
dirs=()
for ae in 14:0.35 12:0.3 10:0.25; do
  d="$OUT/fig10c/A${ae%%:*}"
  "$VIMPACT" simulate --set Ur=25 --set sigma=-0.13181 --set "A=${ae%%:*}" --set "eps=${ae##*:}" "${PROTO[@]}" --no-plot --out "$d" > /dev/null
  dirs+=("$d")
done
overlay timeseries "$OUT/fig10c/plot.png" "${dirs[@]}"
