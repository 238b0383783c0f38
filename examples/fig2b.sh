#!/usr/bin/env bash
# Figure 2b: the zoom 24 <= Ur <= 25 of Figure 2a.
source "$(dirname "$0")/lib.sh"
"$VIMPACT" sweep --param Ur --range "24:25:$(pick 401 6)" "${PROTO[@]}" --out "$OUT/fig2b"
