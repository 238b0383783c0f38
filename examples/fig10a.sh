#!/usr/bin/env bash
# Figure 10a: barrier-free amplitude against Ur for A = 14, 12, 10 with A/eps = 40.
source "$(dirname "$0")/lib.sh"
"$VIMPACT" response --param Ur --range "2:25:$(pick 231 6)" --curves 'A=14,eps=0.35;A=12,eps=0.3;A=10,eps=0.25' --out "$OUT/fig10a"
