"""The numbers quoted in docs/reproduction.md, read from the outputs of examples/all.sh.

Usage: /usr/bin/python3 scripts/reproduction_facts.py RESULTS_DIR
Prints, per figure, the labels at the parameter values the paper names and the extent of
each label's windows, so every statement in the document can be re-derived."""
import csv
import json
import os
import re
import sys


def table(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return rows


def label_at(rows, key, value, branch="0"):
    best = min((r for r in rows if r["branch"] == branch), key=lambda r: abs(float(r[key]) - value))
    return best["label"], float(best[key])


def windows(rows, key, branch="0"):
    """Maximal runs of equal labels along the sweep: [(label, first, last, count)]."""
    out = []
    for r in rows:
        if r["branch"] != branch:
            continue
        v = float(r[key])
        if out and out[-1][0] == r["label"]:
            out[-1][2] = v
            out[-1][3] += 1
        else:
            out.append([r["label"], v, v, 1])
    return out


def first_of(rows, key, label, branch="0"):
    for r in rows:
        if r["branch"] == branch and r["label"] == label:
            return float(r[key])
    return None


def periods_in_order(rows, key):
    """The PN labels in the order they first appear along the sweep."""
    seen = []
    for r in rows:
        if re.fullmatch(r"P\d+", r["label"]) and r["label"] not in seen:
            seen.append(r["label"])
    return seen


def counts(rows):
    c = {}
    for r in rows:
        c[r["label"]] = c.get(r["label"], 0) + 1
    return c


def sweep_facts(d, name, key, points):
    path = os.path.join(d, name, "labels.csv")
    if not os.path.exists(path):
        return
    rows = table(path)
    print(f"### {name}: sweep of {key}, {len(rows)} points")
    print("label counts:", json.dumps(counts(rows), sort_keys=True))
    for v in points:
        lab, at = label_at(rows, key, v)
        print(f"  {key} = {at:.6g}: {lab}")
    w = windows(rows, key)
    aper = [x for x in w if x[0] == "aperiodic"]
    print(f"  {len(w)} windows of equal label; aperiodic windows: {len(aper)}; "
          f"widest aperiodic window: {max((x[2] - x[1] for x in aper), default=0):.4g}")
    print("  periods in order of first appearance:", " ".join(periods_in_order(rows, key)))
    print()


def main(d):
    sweep_facts(d, "fig2a", "Ur", [13, 14.9, 16, 19, 21.5, 24.4, 24.8])
    p = os.path.join(d, "fig2a", "labels.csv")
    if os.path.exists(p):
        rows = table(p)
        print("fig2a first Ur of each label:",
              {lab: first_of(rows, "Ur", lab) for lab in ["P1", "P2", "P3", "P4", "P5", "P6", "aperiodic"]})
        # Is there an aperiodic point between the P1 and the P2 window?
        w = windows(rows, "Ur")
        i2 = next(i for i, x in enumerate(w) if x[0] == "P2")
        print("fig2a windows up to the first P2:", [(x[0], x[1], x[2]) for x in w[: i2 + 1]])
        print()
    sweep_facts(d, "fig2a-facchinetti", "Ur", [16, 19, 21.5, 24.4, 24.8])
    sweep_facts(d, "fig2b", "Ur", [24.4, 24.8])
    p = os.path.join(d, "fig2c", "labels.csv")
    if os.path.exists(p):
        rows = table(p)
        up, down = windows(rows, "Ur", "0"), windows(rows, "Ur", "1")
        print("### fig2c: follow up:", [(x[0], x[1], x[2]) for x in up])
        print("### fig2c: follow down:", [(x[0], x[1], x[2]) for x in down])
        print()
    p = os.path.join(d, "fig3", "run.json")
    if os.path.exists(p):
        res = json.load(open(p))["result"]
        print("### fig3: attractors", [(t["label"], t["cells"]) for t in res["attractors"]["table"]],
              "inadmissible", res["inadmissible_cells"])
        print()
    for name in ("fig4", "fig8", "fig9"):
        p = os.path.join(d, name, "run.json")
        if os.path.exists(p):
            res = json.load(open(p))["result"]
            print(f"### {name}: map {res['x']} x {res['y']} {res['shape']}:", json.dumps(res["label_counts"], sort_keys=True))
            if res.get("grazing"):
                g = res["grazing"]
                print(f"  grazing line from {g[0]} to {g[-1]}")
                # P0 exactly below the line?
                # Each cell's label is in labels.csv (row iy * nx + ix), not in run.json.
                xs, ys = res["x_values"], res["y_values"]
                flat = [r["label"] for r in table(os.path.join(d, name, "labels.csv"))]
                cells = [flat[k * len(xs):(k + 1) * len(xs)] for k in range(len(ys))]
                bad = 0
                for ix, (xv, gv) in enumerate(g):
                    for iy, yv in enumerate(ys):
                        lab = cells[iy][ix]
                        if (yv < gv) != (lab == "P0"):
                            bad += 1
                print(f"  cells on the wrong side of the grazing line (P0 above or impacting below): {bad}")
            print()
    sweep_facts(d, "fig5a", "sigma", [-0.149, -0.146])
    sweep_facts(d, "fig5b", "sigma", [-0.149, -0.146, -0.021, -0.020])
    sweep_facts(d, "fig5g", "sigma", [-0.021, -0.020])
    sweep_facts(d, "fig7", "r", [0.8])
    for name in ("fig10a", "fig10b"):
        p = os.path.join(d, name, "run.json")
        if os.path.exists(p):
            res = json.load(open(p))["result"]
            print(f"### {name}:")
            # Each point's amplitude and frequency are in response.csv, curve by curve.
            rows = table(os.path.join(d, name, "response.csv"))
            for i, c in enumerate(res["curves"]):
                mine = [r for r in rows if int(float(r["curve"])) == i]
                c["amplitude"] = [float(r["amplitude"]) if r["amplitude"] != "nan" else None for r in mine]
                c["frequency"] = [float(r["frequency"]) for r in mine]
                c["values"] = [float(r[res["param"]]) for r in mine]
                amp = [a for a in c["amplitude"] if a is not None]
                k = c["amplitude"].index(max(amp))
                # The paper's model's time unit makes the wake's own angular frequency 1: the
                # response's angular frequency is the ratio to the shedding frequency.
                p = c["parameters"]
                print(f"  A = {p['A']:g}, eps = {p['eps']:.4g}: peak amplitude {max(amp):.4f} at Ur = {c['values'][k]:.4g},"
                      f" frequency ratio there {c['frequency'][k]:.4f}; not converged {c['not_converged']}")
            print()
    for s in "abcdef":
        sweep_facts(d, f"fig11{s}", "Ur", [25])
    for fl, ly, key in (("fig14", "fig16", "Ur"), ("fig15", "fig17", "sigma")):
        stability_facts(d, fl, ly, key)


def stability_facts(d, fl, ly, key):
    pf, pl = os.path.join(d, fl, "labels.csv"), os.path.join(d, ly, "exponents.csv")
    if not (os.path.exists(pf) and os.path.exists(pl)):
        return
    fr = [r for r in table(pf)]
    periodic = [r for r in fr if re.fullmatch(r"P\d+", r["label"])]
    print(f"### {fl}: Floquet over {key}, {len(fr)} values, {len(periodic)} periodic")
    print(f"  largest |mu - 1| of the trivial multiplier: {max(float(r['trivial_error']) for r in periodic):.2g}")
    print(f"  largest nontrivial modulus on any periodic orbit: {max(float(r['max_nontrivial_modulus']) for r in periodic):.4f}")
    # The last periodic value before each aperiodic band, and its largest nontrivial modulus.
    edges = []
    for a, b in zip(fr, fr[1:]):
        if re.fullmatch(r"P\d+", a["label"]) and b["label"] == "aperiodic":
            edges.append((float(a[key]), a["label"], float(a["max_nontrivial_modulus"])))
    print("  before each aperiodic band (value, label, largest nontrivial |mu|):",
          ", ".join(f"({v:g}, {lab}, {m:.3f})" for v, lab, m in edges))
    ex = table(pl)
    label = {r[key]: r["label"] for r in fr}
    pos = [r for r in ex if float(r["lambda1"]) > 3 * float(r["lle_standard_error"])]
    print(f"### {ly}: largest Lyapunov exponent over {key}, {len(ex)} values")
    print(f"  lambda1 above 3 standard errors at {len(pos)} values; largest {max(float(r['lambda1']) for r in ex):.4f}")
    both = [r for r in ex if r[key] in label]
    ap_pos = sum(1 for r in both if label[r[key]] == "aperiodic" and r in pos)
    ap = sum(1 for r in both if label[r[key]] == "aperiodic")
    per_pos = sum(1 for r in both if label[r[key]] != "aperiodic" and r in pos)
    print(f"  aperiodic values with lambda1 > 3 SE: {ap_pos} of {ap}; periodic values with lambda1 > 3 SE: {per_pos}")
    per = [abs(float(r["lambda1"])) for r in both if re.fullmatch(r"P\d+", label[r[key]])]
    print(f"  largest |lambda1| on periodic values: {max(per):.2g}")
    print()


if __name__ == "__main__":
    main(sys.argv[1])
