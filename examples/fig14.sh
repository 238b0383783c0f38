#!/usr/bin/env bash
# Figure 14: Floquet multipliers against Ur (sigma = -0.150298): each periodic orbit refined by
# Newton shooting, monodromy with saltation matrices; aperiodic points have none.
source "$(dirname "$0")/lib.sh"
"$VIMPACT" floquet --param Ur --range "12:25:$(pick 261 8)" "${PROTO[@]}" --out "$OUT/fig14"
