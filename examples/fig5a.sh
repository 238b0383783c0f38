#!/usr/bin/env bash
# Figure 5a: y at the section against sigma near grazing, -0.150298 <= sigma <= -0.142, Ur = 25.
source "$(dirname "$0")/lib.sh"
"$VIMPACT" sweep --set Ur=25 --param sigma --range="-0.150298:-0.142:$(pick 401 6)" "${PROTO[@]}" --out "$OUT/fig5a"
