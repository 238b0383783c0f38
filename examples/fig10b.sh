#!/usr/bin/env bash
# Figure 10b: barrier-free amplitude against Ur for A = 10 with A/eps = 50, 40, 30.
source "$(dirname "$0")/lib.sh"
"$VIMPACT" response --param Ur --range "2:25:$(pick 231 6)" --curves 10:0.2,10:0.25,10:0.3333333333333333 --out "$OUT/fig10b"
