#!/usr/bin/env bash
# Figure 16: largest Lyapunov exponent against Ur (sigma = -0.150298), t0 = pi, 800 impacts,
# saltation mapping; the bifurcation diagram underneath.
source "$(dirname "$0")/lib.sh"
IMP=(); if [ "$QUICK" = 1 ]; then IMP=(--impacts 100); fi
"$VIMPACT" lyapunov --param Ur --range "12:25:$(pick 261 8)" "${PROTO[@]}" "${IMP[@]}" --out "$OUT/fig16"
