#!/usr/bin/env bash
# Figure 2a with CL0 = 0.3 (the facchinetti preset) and the barrier at that model's own
# grazing value at Ur = 25: how much of the story depends on the lift coefficient.
source "$(dirname "$0")/lib.sh"
sigma=$(grazing_value --preset facchinetti --set Ur=25)
"$VIMPACT" sweep --preset facchinetti --set "sigma=$sigma" --param Ur --range "12:25:$(pick 521 14)" "${PROTO[@]}" --out "$OUT/fig2a-facchinetti"
