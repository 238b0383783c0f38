#!/usr/bin/env bash
# Figure 7: y at the section against the restitution coefficient r; Ur = 25, sigma = -0.021.
# (The paper does not print its r range; 0.5 <= r <= 0.95 is our choice.)
source "$(dirname "$0")/lib.sh"
"$VIMPACT" sweep --set Ur=25 --set sigma=-0.021 --param r --range "0.5:0.95:$(pick 451 6)" "${PROTO[@]}" --out "$OUT/fig7"
