#!/usr/bin/env bash
# Figure 10b: barrier-free amplitude against Ur for A = 10 with A/eps = 50, 40, 30.
source "$(dirname "$0")/lib.sh"
"$VIMPACT" response --param Ur --range "2:25:$(pick 231 6)" --curves 'A=10,eps=0.2;A=10,eps=0.25;A=10,eps=0.3333333333333333' --out "$OUT/fig10b"
