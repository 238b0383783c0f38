#!/usr/bin/env bash
# Figure 17: largest Lyapunov exponent against sigma at Ur = 25, t0 = pi, 800 impacts.
source "$(dirname "$0")/lib.sh"
IMP=(); if [ "$QUICK" = 1 ]; then IMP=(--impacts 100); fi
"$VIMPACT" lyapunov --set Ur=25 --param sigma --range="-0.150298:0:$(pick 301 8)" "${PROTO[@]}" "${IMP[@]}" --out "$OUT/fig17"
