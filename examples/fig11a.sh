#!/usr/bin/env bash
# Figure 11a: y at the section against Ur, 12 <= Ur <= 25, A = 14, eps = 0.35, sigma = -0.13181 (as printed).
source "$(dirname "$0")/lib.sh"
"$VIMPACT" sweep --set A=14 --set eps=0.35 --set sigma=-0.13181 --param Ur --range "12:25:$(pick 521 8)" --grazing "${PROTO[@]}" --out "$OUT/fig11a"
