#!/usr/bin/env bash
# Figure 6: Poincare sections (v = 0, maxima of y) of the aperiodic attractors and their
# correlation dimension (the paper: nu = 2.4 at Ur = 18.426 and 18.494, 15 centres, radii
# 1e-4 .. 0.06). Paper preset, sigma = -0.150298 unless set, r = 0.8. See
# docs/reproduction-fig6.md for what the numbers say.
#   1. where the aperiodic bands between P2-P3, P3-P4 (Ur) and P6-P5 (sigma, Ur = 25) are, in
#      the model's own sweeps (long transient: the bands are narrow and transients long);
#   2. the paper's Ur = 18.426 and 18.494, with the paper's protocol (500 impacts discarded)
#      and with a long transient;
#   3. one point inside each band: Grassberger-Procaccia sum and the paper's centre counts;
#   4. two runs started 1e-9 apart at the start of the record: does the separation grow?
#      and, where the lyapunov command exists, the Lyapunov spectrum and Kaplan-Yorke dimension;
#   5. the sections drawn together (Figure 6c: Ur varies; 6d: sigma varies) and a table.
source "$(dirname "$0")/lib.sh"
D="$OUT/fig6"
mkdir -p "$D"
rm -f "$D/divergence.txt"
TR=$(pick 5000 200)     # impacts discarded inside the bands
REC=$(pick 20000 2000)  # section points for a dimension
SWEEP=(--transient "$(pick 5000 100)" --record "$(pick 400 40)")
PYD=(env "PYTHONPATH=$EXAMPLES_DIR/../python${PYTHONPATH:+:$PYTHONPATH}" "$PYTHON" -m vimpact.plot_dimension)

echo "== 1. the aperiodic bands in the model's sweeps (labels.csv in each directory)"
"$VIMPACT" sweep --param Ur --range "18.40:18.50:$(pick 21 3)" "${SWEEP[@]}" --out "$D/sweep-Ur-P2-P3" > /dev/null
"$VIMPACT" sweep --param Ur --range "20.60:21.10:$(pick 11 3)" "${SWEEP[@]}" --out "$D/sweep-Ur-P3-P4" > /dev/null
"$VIMPACT" sweep --set Ur=25 --param sigma --range "-0.1496:-0.1476:$(pick 11 3)" "${SWEEP[@]}" \
  --out "$D/sweep-sigma-P6-P5" > /dev/null
for s in sweep-Ur-P2-P3 sweep-Ur-P3-P4 sweep-sigma-P6-P5; do
  echo "$s: $(cut -d, -f2,3 "$D/$s/labels.csv" | tail -n +2 | tr '\n' ' ')"
done

echo "== 2. the paper's Ur = 18.426 and 18.494"
for ur in 18.426 18.494; do
  "$VIMPACT" dimension --set "Ur=$ur" --transient 500 --record "$REC" --out "$D/paper-protocol-Ur$ur" > /dev/null
  "$VIMPACT" dimension --set "Ur=$ur" --transient "$TR" --record "$REC" --out "$D/long-transient-Ur$ur" > /dev/null
done

echo "== 3. inside the bands"
CASES=("Ur=18.455" "Ur=20.85" "Ur=24.4" "Ur=25 sigma=-0.1484" "Ur=25 sigma=-0.1452")
band_dirs=()
for c in "${CASES[@]}"; do
  name="band-${c// /-}"
  sets=()
  for kv in $c; do sets+=(--set "$kv"); done
  "$VIMPACT" dimension "${sets[@]}" --transient "$TR" --record "$REC" --out "$D/$name" > /dev/null
  # The paper's variant on the same points: 15 centres, radii 1e-4 .. 0.06 in steps of 1e-4.
  "$VIMPACT" dimension --points "$D/$name/points.csv" --estimator centres --out "$D/$name/centres" > /dev/null
  band_dirs+=("$D/$name")
done

echo "== 4. separation of two runs 1e-9 apart (lambda > 0: they separate, sensitive dependence; < 0: they converge)"
for c in "Ur=18.426" "${CASES[@]}"; do
  name="divergence-${c// /-}"
  sets=()
  for kv in $c; do sets+=(--set "$kv"); done
  x0=$("$VIMPACT" simulate "${sets[@]}" --transient "$TR" --record 1 --json |
       "$PYTHON" -c 'import json, sys; print(",".join(repr(v) for v in json.load(sys.stdin)["final_state"]))')
  x1=$("$PYTHON" -c "v = [float(s) for s in '$x0'.split(',')]; v[3] += 1e-9; print(','.join(repr(s) for s in v))")
  "$VIMPACT" simulate "${sets[@]}" --ic "$x0" --transient 0 --record "$(pick 400 100)" --no-plot --out "$D/$name/a" > /dev/null
  "$VIMPACT" simulate "${sets[@]}" --ic "$x1" --transient 0 --record "$(pick 400 100)" --no-plot --out "$D/$name/b" > /dev/null
  echo "$c: $("${PYD[@]}" divergence "$D/$name/a/sections.csv" "$D/$name/b/sections.csv" "$D/$name/divergence.csv")" \
    | tee -a "$D/divergence.txt"
done

if "$VIMPACT" lyapunov --help > /dev/null 2>&1; then
  echo "== 4b. Lyapunov spectrum and Kaplan-Yorke dimension (independent of the point counts)"
  ly=()
  for c in "Ur=18.426" "${CASES[@]}"; do
    sets=()
    for kv in $c; do sets+=(--set "$kv"); done
    "$VIMPACT" lyapunov "${sets[@]}" --transient "$TR" --impacts "$(pick 10000 300)" --json > "$D/lyapunov-${c// /-}.json"
    ly+=("$D/lyapunov-${c// /-}.json")
  done
  "${PYD[@]}" kaplan-yorke "${ly[@]}" | tee "$D/lyapunov.md"
fi

echo "== 5. sections together and the table"
"${PYD[@]}" overlay "$D/fig6c.png" "$D/band-Ur=18.455" "$D/band-Ur=20.85" "$D/band-Ur=24.4"
"${PYD[@]}" overlay "$D/fig6d.png" "$D/band-Ur=25-sigma=-0.1484" "$D/band-Ur=25-sigma=-0.1452"
dirs=("$D"/paper-protocol-Ur* "$D"/long-transient-Ur*)
for b in "${band_dirs[@]}"; do dirs+=("$b" "$b/centres"); done
"${PYD[@]}" table "${dirs[@]}" | tee "$D/table.md"
echo "written: $D/*/plot.png, $D/fig6c.png, $D/fig6d.png, $D/table.md"
