#!/usr/bin/env bash
# Figure 9: periodicity map r against Ur at sigma = -0.021 (tolerance 1e-5).
source "$(dirname "$0")/lib.sh"
"$VIMPACT" map --set sigma=-0.021 --x "Ur:12:25:$(pick 131 8)" --y "r:0.5:0.95:$(pick 46 4)" --tol 1e-5 "${PROTO[@]}" --out "$OUT/fig9"
