#!/usr/bin/python3
"""Work-precision diagrams of the paper's model: error against wall time for rtol = atol =
1e-6 .. 1e-12, every integrator with its own events, on

  periodic  Ur = 16, the protocol (500 impacts discarded, the next 200 maxima of y);
  chaotic   Ur = 22.5, every maximum of y up to t = HORIZON from the model's initial state.

Time: the median CPU time of the run (process time; wall time on a shared machine is noisy).
Errors, against a reference at rtol = atol = 1e-14 (vimpact's DOP853 in double; a second
reference, the plain DOPRI5 loop in long double at 1e-14, is compared with it and their
difference printed as the reference's own uncertainty):
  state error  max over the section points of the max-norm of (y, v, x, w) - reference,
  time error   max over the section points of |t - t_reference|.

Usage: /usr/bin/python3 bench/work_precision.py BUILD_DIR OUT_DIR [--no-scipy] [--repeat N] [--plot-only]
Writes OUT_DIR/work_precision.csv (one row per program, problem and tolerance: wall time,
steps, rejected, rhs calls, errors) and OUT_DIR/work_precision.png (the figure of
docs/performance.md); prints the reference check and the load average.
"""
import argparse
import csv
import json
import os
import subprocess
import sys

import numpy as np

HORIZON = 150.0
TOLS = [1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12]
PROBLEMS = {"periodic": ["--ur", "16"], "chaotic": ["--ur", "22.5", "--horizon", str(HORIZON)]}


def programs(build, scipy):
    p = [("vimpact DOP853", [f"{build}/wp_vimpact", "--method", "dop853"]),
         ("vimpact DOPRI5", [f"{build}/wp_vimpact", "--method", "dopri5"]),
         ("vimpact DOP853, hold 0.1", [f"{build}/wp_vimpact", "--method", "dop853", "--hold", "0.1"]),
         ("vimpact DOPRI5, hold 0 (off)", [f"{build}/wp_vimpact", "--method", "dopri5", "--hold", "0"]),
         ("Odeint DOPRI5", [f"{build}/baseline_odeint", "--method", "dopri5"]),
         ("Odeint RKF78", [f"{build}/baseline_odeint", "--method", "rkf78"]),
         ("plain DOPRI5 loop", [f"{build}/baseline_plain"])]
    if os.path.exists(f"{build}/baseline_sundials"):
        p += [("CVODE Adams", [f"{build}/baseline_sundials", "--method", "cvode-adams"]),
              ("ARKODE ERK (DP5)", [f"{build}/baseline_sundials", "--method", "arkode-erk"])]
    if scipy:
        here = os.path.dirname(os.path.abspath(__file__))
        for m in ("DOP853", "RK45"):
            p.append((f"scipy {m}", ["/usr/bin/python3", os.path.join(here, "baseline_scipy.py"), "--method", m]))
    return p


def run(cmd, points):
    out = subprocess.run(cmd + ["--points", points], check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def load(path):
    d = np.genfromtxt(path, delimiter=",", skip_header=1, ndmin=2)
    return d[:, 0], d[:, 1:5]


def errors(points, ref):
    t, x = load(points)
    tr, xr = ref
    n = min(len(t), len(tr))
    if n == 0:
        return float("nan"), float("nan"), 0
    return float(np.max(np.abs(x[:n] - xr[:n]))), float(np.max(np.abs(t[:n] - tr[:n]))), len(t) - len(tr)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("out")
    ap.add_argument("--no-scipy", action="store_true")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--plot-only", action="store_true", help="redraw OUT/work_precision.png from its CSV")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    if a.plot_only:
        rows = []
        for r in csv.DictReader(open(os.path.join(a.out, "work_precision.csv"))):
            for k in ("tol", "wall_s", "state_error", "time_error"):
                r[k] = float(r[k])
            rows.append(r)
        plot(rows, os.path.join(a.out, "work_precision.png"))
        return 0
    print(f"load average before: {open('/proc/loadavg').read().strip()}")
    refs = {}
    for name, args in PROBLEMS.items():
        f = os.path.join(a.out, f"ref-{name}.csv")
        run([f"{a.build}/wp_vimpact", "--method", "dop853", "--tol", "1e-14"] + args, f)
        refs[name] = load(f)
        g = os.path.join(a.out, f"ref-ld-{name}.csv")
        run([f"{a.build}/baseline_plain", "--long-double", "--tol", "1e-14"] + args, g)
        se, te, dn = errors(g, refs[name])
        print(f"reference check {name}: DOP853 at 1e-14 against long double DOPRI5 at 1e-14: "
              f"state {se:.1e}, time {te:.1e}, point count difference {dn}")
    rows = []
    for label, cmd in programs(a.build, not a.no_scipy):
        for name, args in PROBLEMS.items():
            for tol in TOLS:
                slow = label.startswith("scipy")
                f = os.path.join(a.out, "pts.csv")
                r = run(cmd + ["--tol", str(tol), "--repeat", "1" if slow else str(a.repeat)] + args, f)
                se, te, dn = errors(f, refs[name])
                rows.append({"program": label, "problem": name, "tol": tol, "wall_s": r.get("cpu_s", r["wall_s"]),
                             "steps": r["steps"], "rejected": r.get("rejected"), "rhs_calls": r["rhs_calls"],
                             "points": r["points"], "point_count_diff": dn, "state_error": se, "time_error": te})
                print(f"{label:18s} {name:8s} tol {tol:.0e}: {r['wall_s'] * 1e3:9.2f} ms  state {se:.1e}  "
                      f"time {te:.1e}  steps {r['steps']}", flush=True)
    with open(os.path.join(a.out, "work_precision.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print(f"load average after: {open('/proc/loadavg').read().strip()}")
    plot(rows, os.path.join(a.out, "work_precision.png"))


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, 2, figsize=(12, 9), constrained_layout=True)
    labels = list(dict.fromkeys(r["program"] for r in rows))
    # Twelve markers against ten colours: no two programs share both.
    markers = "os^vD<>ph*XP"
    for col, name in enumerate(PROBLEMS):
        for row, (key, what) in enumerate((("state_error", "state error at the section"),
                                           ("time_error", "time error at the section"))):
            ax = axes[row][col]
            for i, lab in enumerate(labels):
                rs = [r for r in rows if r["program"] == lab and r["problem"] == name and r[key] > 0]
                if rs:
                    ax.loglog([r["wall_s"] for r in rs], [r[key] for r in rs], marker=markers[i % len(markers)],
                              color=f"C{i % 10}", linestyle="--" if "hold" in lab else "-", label=lab)
            title = ("periodic: Ur = 16, 500 impacts discarded, 200 maxima" if name == "periodic"
                     else f"chaotic: Ur = 22.5, maxima up to t = {HORIZON:g}")
            ax.set_title(title)
            ax.set_xlabel("CPU time of the run [s]")
            ax.set_ylabel(f"{what} (max over points)")
            ax.grid(True, which="both", alpha=0.3)
    h, lab = axes[0][0].get_legend_handles_labels()
    fig.legend(h, lab, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=5)
    fig.suptitle("Work-precision, rtol = atol = 1e-6 ... 1e-12 (reference: DOP853 at 1e-14)")
    fig.savefig(path, dpi=110, bbox_inches="tight")


if __name__ == "__main__":
    sys.exit(main())
