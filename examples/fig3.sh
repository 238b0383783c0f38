#!/usr/bin/env bash
# Figure 3: basins of attraction of the coexisting P1 and P2 at Ur = 14.9, sigma = -0.150298,
# over initial (y, ydot) with x = 0, xdot = 0.1.
source "$(dirname "$0")/lib.sh"
n=$(pick 80 6)
"$VIMPACT" basins --set Ur=14.9 --x "y:-0.15:0.25:$n" --y "ydot:-0.3:0.3:$n" "${PROTO[@]}" --out "$OUT/fig3"
