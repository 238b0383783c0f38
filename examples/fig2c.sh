#!/usr/bin/env bash
# Figure 2c: coexisting P1 and P2 near Ur = 14.9. The paper used several initial states; here
# the sweep follows its branch up and down (each point starts from the previous final state),
# which shows both attractors and the hysteresis between them.
source "$(dirname "$0")/lib.sh"
"$VIMPACT" sweep --param Ur --range "14:16:$(pick 81 9)" --ic-mode follow --direction both "${PROTO[@]}" --out "$OUT/fig2c"
