#!/usr/bin/env bash
# Figure 5g: zoom -0.024 <= sigma <= -0.010 at Ur = 25 (P4 between two P2 branches).
source "$(dirname "$0")/lib.sh"
"$VIMPACT" sweep --set Ur=25 --param sigma --range="-0.024:-0.010:$(pick 401 6)" "${PROTO[@]}" --out "$OUT/fig5g"
