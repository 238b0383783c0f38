#!/usr/bin/env bash
# Figure 2a: y at the section against Ur, 12 <= Ur <= 25; sigma = -0.150298, r = 0.8,
# paper preset; with the grazing value sigma_graze(Ur) of the barrier-free system.
source "$(dirname "$0")/lib.sh"
"$VIMPACT" sweep --param Ur --range "12:25:$(pick 521 14)" --grazing "${PROTO[@]}" --out "$OUT/fig2a"
