#!/usr/bin/env bash
# Figure 11c: y at the section against Ur, 12 <= Ur <= 25, A = 12, eps = 0.3, sigma = -0.13181 (as printed).
source "$(dirname "$0")/lib.sh"
"$VIMPACT" sweep --set A=12 --set eps=0.3 --set sigma=-0.13181 --param Ur --range "12:25:$(pick 521 8)" --grazing "${PROTO[@]}" --out "$OUT/fig11c"
