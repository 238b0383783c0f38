#!/usr/bin/env bash
# Figure 4: periodicity map sigma against Ur (tolerance 1e-5, initial state (0, 0, 0, 0.1)),
# with the grazing line sigma_graze(Ur): below it the barrier is never reached (P0).
source "$(dirname "$0")/lib.sh"
"$VIMPACT" map --x "Ur:12:25:$(pick 131 8)" --y "sigma:-0.25:0:$(pick 101 6)" --tol 1e-5 --grazing "${PROTO[@]}" --out "$OUT/fig4"
