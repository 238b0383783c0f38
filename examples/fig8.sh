#!/usr/bin/env bash
# Figure 8: periodicity map r against sigma at Ur = 25 (tolerance 1e-5).
source "$(dirname "$0")/lib.sh"
"$VIMPACT" map --set Ur=25 --x "sigma:-0.150298:0:$(pick 101 6)" --y "r:0.5:0.95:$(pick 46 4)" --tol 1e-5 "${PROTO[@]}" --out "$OUT/fig8"
