#!/usr/bin/env bash
# Figure 15: Floquet multipliers against sigma at Ur = 25.
source "$(dirname "$0")/lib.sh"
"$VIMPACT" floquet --set Ur=25 --param sigma --range="-0.150298:0:$(pick 301 8)" "${PROTO[@]}" --out "$OUT/fig15"
