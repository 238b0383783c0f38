"""Plots of the correlation dimension (``vimpact dimension --out DIR``; the paper's Figure 6).

``dimension(DIR)`` draws, from the files the command writes:
  (a), (b) the points themselves (two projections of the coordinates used; the paper's
           Figure 6a), with the centres circled for the centres estimator;
  (c) log C vs log r with the fitted line and the scaling region shaded (Figure 6b);
  (d) the local slope d log C / d log r, with the fitted dimension.

``overlay(OUT_PNG, DIR, DIR, ...)`` draws the points of several runs in one projection (the
paper's Figure 6c, d: sections for several Ur or sigma). ``table(DIRS)`` is a Markdown table
of their results; ``divergence(A, B, OUT)`` measures how two runs started 1e-9 apart separate
on the section (examples/fig6.sh). Command line::

    /usr/bin/python3 -m vimpact.plot_dimension overlay OUT.png DIR [DIR ...]
    /usr/bin/python3 -m vimpact.plot_dimension table DIR [DIR ...]
    /usr/bin/python3 -m vimpact.plot_dimension divergence A/sections.csv B/sections.csv OUT.csv
    /usr/bin/python3 -m vimpact.plot_dimension kaplan-yorke LYAPUNOV.json [...]

``kaplan-yorke`` reads the JSON of ``vimpact lyapunov --json`` and gives the Kaplan-Yorke
dimension of the attractor (Kaplan & Yorke 1979; it bounds the information dimension, and
equals it for typical attractors): a check of the correlation dimension independent of it.
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from types import SimpleNamespace  # noqa: E402

from .plot_common import coincident_limits, label_axis, legend_outside, save_in, suptitle  # noqa: E402
from .results import _context, read_csv  # noqa: E402


def _load(directory):
    record = json.load(open(os.path.join(directory, "run.json")))
    points = read_csv(os.path.join(directory, "points.csv"))
    curve = read_csv(os.path.join(directory, "correlation.csv"))
    return record, points, curve


def _parameters(record):
    return _context(record)["parameters"] if (record.get("model") or record.get("config", {}).get("parameters")) \
        else {}


def _title(record):
    cfg = record.get("config", {})
    p = _parameters(record)
    if p:
        ctx = _context(record)
        text = ", ".join(f"{k} = {v:g}" for k, v in p.items() if isinstance(v, (int, float)))
        head = f"{ctx['model_name']}: " if ctx["model_name"] else ""
        section = f", section {cfg['section']}" if cfg.get("section") else ""
        return head + text + section
    return f"points from {cfg.get('points_file', '?')}"


def _run_label(record, varied=()):
    cfg = record.get("config", {})
    p = _parameters(record)
    if p:
        shown = [k for k in p if k in varied] or list(p)[:2]
        return ", ".join(f"{k} = {p[k]:g}" for k in shown)
    return os.path.basename(cfg.get("points_file", "points"))


def _varied(records):
    """Parameters whose values differ between runs."""
    ps = [_parameters(r) for r in records]
    keys = list(ps[0]) if ps else []
    return tuple(k for k in keys if any(p.get(k) != ps[0].get(k) for p in ps))


def _described(record):
    """What the axis labels need of a run's model (its units; none for a points file)."""
    return SimpleNamespace(**_context(record))


def _varying_first(points):
    """The columns, those that vary first: one a section fixes (ydot = 0 at the maxima) shows
    nothing in a projection."""
    return sorted(points, key=lambda k: len(points[k]) > 0 and np.ptp(points[k]) == 0)


def _projection(ax, points, names, i, j, model, centres=None):
    x, y = points[names[i]], points[names[j]]
    ax.plot(x, y, ",", color="C0", alpha=0.7) if len(x) > 5000 else ax.plot(x, y, ".", ms=2, color="C0")
    coincident_limits(ax, x, y)
    if centres:
        ax.plot(x[centres], y[centres], "o", mfc="none", mec="C3", ms=9, mew=1.2, label="centres")
        legend_outside(ax)
    label_axis(ax, "x", model, names[i])
    label_axis(ax, "y", model, names[j])


def dimension(directory, out_name="plot.png"):
    record, points, curve = _load(directory)
    res = record["result"]
    names = _varying_first(points)
    centres = res.get("centres")
    model = _described(record)

    fig, axes = plt.subplots(2, 2, figsize=(11, 8.5))
    (a1, a2), (a3, a4) = axes
    if len(names) >= 2:
        _projection(a1, points, names, 0, 1, model, centres)
        a1.set_title(f"(a) {len(points[names[0]])} points", fontsize=10)
        if len(names) >= 3:
            _projection(a2, points, names, 1, 2, model, centres)
            a2.set_title("(b) another projection", fontsize=10)
        else:
            a2.axis("off")
    else:
        v = points[names[0]]
        a1.plot(v, np.zeros_like(v), "|", ms=10)
        label_axis(a1, "x", model, names[0])
        a1.set_title(f"(a) {len(v)} points", fontsize=10)
        a2.axis("off")

    r, c, slope, fit = curve["r"], curve["C"], curve["local_slope"], curve["in_fit"] > 0.5
    pos = c > 0
    a3.loglog(r[pos], c[pos], ".", ms=3, color="C0", label="C(r)")
    d = res["dimension"]
    if fit.any() and d is not None:
        rf = r[fit]
        a3.axvspan(rf[0], rf[-1], color="C2", alpha=0.15, label="scaling region")
        # ln C = intercept + d ln r over the fitted radii: draw the fitted line there.
        lr, lc = np.log(rf), np.log(c[fit])
        intercept = np.mean(lc) - d * np.mean(lr)
        rr = np.array([rf[0], rf[-1]])
        a3.loglog(rr, np.exp(intercept) * rr ** d, "-", color="C3", lw=1.5, label=f"slope {d:.3f}")
    # r is a distance in the coordinates' own units (mixed when their units differ).
    a3.set_xlabel("r, distance between points")
    a3.set_ylabel("C(r), fraction of pairs closer")
    legend_outside(a3)
    a3.set_title(f"(c) {res['estimator']}: nu = {d:.3f}" if d is not None else f"(c) {res['estimator']}",
                 fontsize=10)

    ok = np.isfinite(slope)
    a4.semilogx(r[ok], slope[ok], ".", ms=3, color="C0", label="local slope")
    if fit.any() and d is not None:
        a4.axvspan(r[fit][0], r[fit][-1], color="C2", alpha=0.15)
        a4.axhline(d, color="C3", lw=1.0, label=f"fitted {d:.3f}")
    a4.set_xlabel("r, distance between points")
    a4.set_ylabel("d log C / d log r")
    a4.set_title(f"(d) local slope; region {res['scaling_region']}", fontsize=10)
    legend_outside(a4)

    suptitle(fig, _title(record), fontsize=10)
    return save_in(fig, directory, out_name)


def overlay(out_png, directories, columns=None):
    """Points of several runs in one projection (Figure 6c, d): the columns of points.csv at
    the indices ``columns``, by default the first two of the first run that vary."""
    fig, ax = plt.subplots(figsize=(7, 5.5))
    names = None
    loaded = [_load(d) for d in directories]
    varied = _varied([r for r, _, _ in loaded])
    if loaded and columns is None:
        first = list(loaded[0][1])
        columns = tuple(first.index(n) for n in _varying_first(loaded[0][1])[:2])
    for k, (record, points, _) in enumerate(loaded):
        names = list(points.keys())
        i, j = columns
        d = record["result"]["dimension"]
        label = _run_label(record, varied) + (f": nu = {d:.2f}" if d is not None else "")
        ax.plot(points[names[i]], points[names[j]], ",", color=f"C{k % 10}")
        ax.plot([], [], "s", color=f"C{k % 10}", label=label)
    if names:
        model = _described(loaded[0][0])
        label_axis(ax, "x", model, names[columns[0]])
        label_axis(ax, "y", model, names[columns[1]])
    legend_outside(ax)
    ax.set_title("section points", fontsize=10)
    fig.tight_layout()
    fig.savefig(out_png, dpi=120)
    plt.close(fig)
    return out_png


def table(directories):
    """A Markdown table of the results of several ``vimpact dimension --out`` directories."""
    records = [json.load(open(os.path.join(d, "run.json"))) for d in directories]
    varied = _varied(records)
    rows = ["| run | " + "".join(f"{k} | " for k in varied) + "transient | label | points | estimator | nu | "
            "fit range r | r2 | region |",
            "|---|" + "---|" * len(varied) + "---|---|---|---|---|---|---|---|"]
    for directory, record in zip(directories, records):
        res = record["result"]
        cfg = record.get("config", {})
        p = _parameters(record)
        src = res.get("source", {})
        nu = res["dimension"]
        lo, hi = res["fit_range"]
        r2 = res["r2"]
        rows.append("| {} | {}{} | {} | {} | {} | {} | {} | {} | {} |".format(
            os.path.relpath(directory, os.path.dirname(os.path.normpath(directories[0]))),
            "".join(f"{p[k]:g} | " if k in p else "- | " for k in varied),
            cfg.get("transient", "-"), src.get("label", "-"), res["points"], res["estimator"],
            f"{nu:.3f}" if nu is not None else "-",
            f"{lo:.2g} .. {hi:.2g}" if lo is not None else "-",
            f"{r2:.4f}" if r2 is not None else "-", res["scaling_region"]))
    return "\n".join(rows)


def divergence(sections_a, sections_b, out_csv):
    """Separation of two runs started 1e-9 apart, section point by section point.

    d_n = |c_n - c'_n| over the section coordinates (every state column that varies: y, x, xdot
    on the wake model's maxima). On a chaotic attractor it
    grows like exp(lambda n) until it reaches the size of the attractor; on a stable periodic
    orbit it shrinks. lambda (per section return) is the least-squares slope of ln d_n from the
    first return up to the last one before d_n first reaches 1e-3 (beyond that the separation
    is no longer small next to the attractor, about 0.03 across). Returns (lambda, number of
    returns fitted, mean return time, d at the first and last fitted return)."""
    a, b = read_csv(sections_a), read_csv(sections_b)
    n = min(len(a["t"]), len(b["t"]))
    cols = [k for k in a if k != "t" and k in b and n and np.ptp(a[k][:n]) > 0]
    d = np.sqrt(sum((a[k][:n] - b[k][:n]) ** 2 for k in cols)) if cols else np.zeros(n)
    with open(out_csv, "w") as f:
        f.write("n,t,d\n")
        for i in range(n):
            f.write(f"{i},{a['t'][i]!r},{d[i]!r}\n")
    m = 0
    while m < n and d[m] < 1e-3:
        m += 1
    dt = float(np.mean(np.diff(a["t"][:n]))) if n > 1 else float("nan")
    if m < 5 or np.any(d[:m] <= 0):
        return float("nan"), m, dt, float("nan"), float("nan")
    slope = np.polyfit(np.arange(m, dtype=float), np.log(d[:m]), 1)[0]
    return float(slope), m, dt, float(d[0]), float(d[m - 1])


def kaplan_yorke(exponents):
    """Kaplan-Yorke dimension j + (l_1 + ... + l_j) / |l_(j+1)|, j the largest with a
    non-negative partial sum (exponents sorted, largest first); len(exponents) if all are."""
    lam = sorted(exponents, reverse=True)
    total, j = 0.0, 0
    while j < len(lam) and total + lam[j] >= 0.0:
        total += lam[j]
        j += 1
    if j == len(lam):
        return float(j)
    return j + total / abs(lam[j])


def lyapunov_rows(files):
    """Markdown rows from ``vimpact lyapunov --json`` outputs: the spectrum and the Kaplan-Yorke
    dimension of the flow's attractor and of its section (one less: the flow direction)."""
    rows = ["| run | exponents (per unit time) | standard error of the largest | D_KY of the attractor |"
            " D_KY - 1 (section) |",
            "|---|---|---|---|---|"]
    for f in files:
        j = json.load(open(f))
        lam = j["exponents"]
        d = kaplan_yorke(lam)
        err = j.get("lle_standard_error")
        rows.append("| {} | {} | {} | {:.3f} | {:.3f} |".format(
            os.path.basename(f)[:-5], ", ".join(f"{v:.4g}" for v in lam),
            f"{err:.2g}" if err is not None else "-", d, max(d - 1.0, 0.0)))
    return "\n".join(rows)


def main(argv):
    if len(argv) >= 3 and argv[1] == "kaplan-yorke":
        print(lyapunov_rows(argv[2:]))
        return 0
    if len(argv) >= 4 and argv[1] == "overlay":
        overlay(argv[2], argv[3:])
        return 0
    if len(argv) >= 3 and argv[1] == "table":
        print(table(argv[2:]))
        return 0
    if len(argv) == 5 and argv[1] == "divergence":
        lam, m, dt, d0, d1 = divergence(argv[2], argv[3], argv[4])
        print(f"lambda = {lam:.3g} per section return ({lam / dt:.3g} per unit time): "
              f"d = {d0:.2g} -> {d1:.2g} over {m} returns (mean return time {dt:.4g})")
        return 0
    if len(argv) == 2:
        dimension(argv[1])
        return 0
    print("usage: python3 -m vimpact.plot_dimension DIR | overlay OUT.png DIR [DIR ...] | table DIR [DIR ...]"
          " | divergence A/sections.csv B/sections.csv OUT.csv | kaplan-yorke LYAPUNOV.json ...", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
