# Shared by the figure scripts (sourced). Usage of every script: figNN.sh [--quick]
#   VIMPACT  the program (default: build/vimpact of this checkout)
#   OUT      where results go (default: results/); each figure writes OUT/figNN/plot.png
#   --quick  a small grid and a short protocol: the CI-sized run of the same command
set -euo pipefail
EXAMPLES_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
VIMPACT=${VIMPACT:-$EXAMPLES_DIR/../build/vimpact}
OUT=${OUT:-results}
PYTHON=${PYTHON:-/usr/bin/python3}
QUICK=0
for arg in "$@"; do
  case $arg in
    --quick) QUICK=1 ;;
    *) echo "usage: $0 [--quick]" >&2; exit 2 ;;
  esac
done
[ -x "$VIMPACT" ] || { echo "$0: $VIMPACT not found: build first (see README)" >&2; exit 1; }
# pick DEFAULT QUICK: the grid size for this run
pick() { if [ "$QUICK" = 1 ]; then echo "$2"; else echo "$1"; fi; }
# The paper's protocol (500 impacts discarded, 200 section points), shortened with --quick.
PROTO=()
if [ "$QUICK" = 1 ]; then PROTO=(--transient 100 --record 40); fi
# The grazing value of the barrier-free system (computed, never copied): grazing_value ARGS...
grazing_value() {
  "$VIMPACT" grazing --json "$@" | "$PYTHON" -c 'import json, sys; print(repr(json.load(sys.stdin)["sigma_graze"]))'
}
# Several run directories drawn together: overlay KIND OUT.png DIR...
overlay() {
  PYTHONPATH="$EXAMPLES_DIR/../python${PYTHONPATH:+:$PYTHONPATH}" "$PYTHON" -m vimpact.plot_sweeps "$@"
}
