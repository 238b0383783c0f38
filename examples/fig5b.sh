#!/usr/bin/env bash
# Figure 5b: y at the section against sigma, -0.150298 <= sigma <= 0, Ur = 25.
source "$(dirname "$0")/lib.sh"
"$VIMPACT" sweep --set Ur=25 --param sigma --range="-0.150298:0:$(pick 751 8)" "${PROTO[@]}" --out "$OUT/fig5b"
