#!/usr/bin/env bash
# Figure 11e: y at the section against Ur, 12 <= Ur <= 25, A = 10, eps = 0.25, sigma = -0.13181 (as printed).
source "$(dirname "$0")/lib.sh"
"$VIMPACT" sweep --set A=10 --set eps=0.25 --set sigma=-0.13181 --param Ur --range "12:25:$(pick 521 8)" --grazing "${PROTO[@]}" --out "$OUT/fig11e"
