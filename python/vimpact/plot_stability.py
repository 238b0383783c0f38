"""Pictures of the stability commands (docs/stability.md). Each function reads a
``vimpact floquet|lyapunov ... --out DIR`` directory and writes DIR/plot.png (or ``out_name``).

``floquet(DIR)``: the multipliers in the complex plane with the unit circle (trivial one
marked), and the refined periodic orbit (y, dy/dt) over one period with its impacts.
``lyapunov(DIR)``: the running estimates of the exponents against time (Eq. 13), which show
whether the average has converged.
"""
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .results import read_csv, save_in  # noqa: E402,F401



def _title(record, swept=None):
    """The parameters of the run; a swept one is named as the axis, not given a value."""
    p = record["config"]["parameters"]
    parts = [f"{k} = {p[k]:g}" for k in ("Ur", "sigma", "r", "A", "eps") if k != swept]
    return ", ".join(parts) + f"  ({record['config']['preset']} preset)"


def _record(directory):
    with open(os.path.join(directory, "run.json")) as f:
        return json.load(f)


def floquet(directory, out_name="plot.png"):
    """Multipliers on the unit circle, and the periodic orbit they belong to."""
    record = _record(directory)
    res = record["result"]
    mult = read_csv(os.path.join(directory, "multipliers.csv"))
    orbit = read_csv(os.path.join(directory, "orbit.csv"))
    imp = read_csv(os.path.join(directory, "impacts.csv"))
    sigma = record["config"]["parameters"]["sigma"]

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 5))
    phi = np.linspace(0.0, 2.0 * np.pi, 400)
    ax1.plot(np.cos(phi), np.sin(phi), "k-", lw=0.8, label="unit circle")
    ax1.axhline(0.0, color="0.8", lw=0.6)
    ax1.axvline(0.0, color="0.8", lw=0.6)
    if len(mult["re"]):
        trivial = mult["trivial"] > 0.5
        ax1.plot(mult["re"][~trivial], mult["im"][~trivial], "o", color="C0", ms=7, label="multipliers")
        ax1.plot(mult["re"][trivial], mult["im"][trivial], "s", mfc="none", color="C3", ms=9,
                 label=f"trivial (|mu - 1| = {res['trivial_error']:.1e})")
    ax1.set_aspect("equal")
    ax1.set_xlim(-1.3, 1.3)
    ax1.set_ylim(-1.3, 1.3)
    ax1.set_xlabel("Re mu")
    ax1.set_ylabel("Im mu")
    ax1.legend(loc="lower left", fontsize=8)
    status = res["outcome"]
    if res.get("period") is not None:
        head = (f"{res['label']}: T = {res['period']:.6g}, {res['impacts_per_period']} impact(s), "
                f"{'stable' if res['stable'] else 'unstable'}")
    else:
        head = f"{res['label']}: no multipliers ({status})"
    ax1.set_title(head, fontsize=10)

    if len(orbit["t"]):
        ax2.plot(orbit["y"], orbit["ydot"], lw=1.0, color="C0", label="periodic orbit")
        ax2.plot(orbit["y"][:1], orbit["ydot"][:1], "g^", ms=6, label="start on the section")
    if len(imp["t"]):
        ax2.plot(imp["y"], imp["ydot_before"], "rv", ms=5, label="impact (before)")
        ax2.plot(imp["y"], imp["ydot_after"], "r^", ms=5, label="impact (after)")
    ax2.axvline(sigma, color="k", ls="--", lw=1.0, label=f"barrier sigma = {sigma:g}")
    ax2.set_xlabel("y")
    ax2.set_ylabel("dy/dt")
    ax2.legend(loc="upper right", fontsize=8)
    ax2.set_title("the orbit over one period", fontsize=10)
    fig.suptitle(_title(record), fontsize=10)
    return save_in(fig, directory, out_name)


def lyapunov(directory, out_name="plot.png"):
    """Running estimates of the exponents (cumulative QR growth / elapsed time)."""
    record = _record(directory)
    res = record["result"]
    conv = read_csv(os.path.join(directory, "convergence.csv"))
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 7), sharex=True,
                                   gridspec_kw={"height_ratios": [1, 1.4]})
    names = [k for k in conv if k.startswith("lambda")]
    if len(conv["t"]):
        t = conv["t"] - res["t_start"]
        for i, k in enumerate(names):
            ax2.plot(t, conv[k], lw=1.0, color=f"C{i}", label=k)
        # The largest on its own scale: whether it settles at 0 or above is the question.
        lead = max(names, key=lambda k: conv[k][-1])
        ax1.plot(t, conv[lead], color=f"C{names.index(lead)}", lw=1.0)
        ax1.axhline(0.0, color="k", lw=0.6)
        lle = res.get("lle")
        if lle is not None:
            se = res.get("lle_standard_error") or 0.0
            ax1.axhspan(lle - se, lle + se, color=f"C{names.index(lead)}", alpha=0.15, label=f"LLE = {lle:.4g} +- {se:.1g}")
            ax1.legend(loc="upper right", fontsize=8)
        span = np.abs(conv[lead][len(conv[lead]) // 10:]).max() if len(conv[lead]) > 10 else 1.0
        ax1.set_ylim(-1.5 * span, 1.5 * span)
    ax1.set_ylabel("largest exponent")
    ax1.set_title(f"mapping at impacts: {res['tdm']}; {res['impacts']} impacts, t = {res['time']:.6g} "
                  f"({res['outcome']})", fontsize=10)
    ax2.axhline(0.0, color="k", lw=0.6)
    ax2.set_xlabel("time since the start of the average")
    ax2.set_ylabel("running estimate")
    ax2.legend(loc="lower right", fontsize=8)
    fig.suptitle(_title(record), fontsize=10)
    return save_in(fig, directory, out_name)


def _read_table(path):
    """A CSV with text cells as a dict of column lists of strings."""
    import csv
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return {name: [r[i] for r in rows[1:]] for i, name in enumerate(rows[0])}


def _diagram(ax, directory, param):
    """The bifurcation diagram underneath: y at the section maxima of every run."""
    pts = read_csv(os.path.join(directory, "points.csv"))
    if len(pts[param]):
        ax.plot(pts[param], pts["y"], "k.", ms=1.2)
    ax.set_xlabel(param)
    ax.set_ylabel("y at the section")


def floquet_sweep(directory, out_name="plot.png"):
    """Multipliers against the swept parameter (the paper's Figures 14, 15), the unit-circle
    band -1 <= mu <= 1 shaded, over the bifurcation diagram."""
    record = _record(directory)
    res = record["result"]
    param = res["param"]
    mult = read_csv(os.path.join(directory, "multipliers.csv"))
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 8), sharex=True, gridspec_kw={"height_ratios": [1.2, 1]})
    ax1.axhspan(-1.0, 1.0, color="C2", alpha=0.08, label="|mu| <= 1 (stable)")
    ax1.axhline(1.0, color="k", lw=0.6)
    ax1.axhline(-1.0, color="k", lw=0.6)
    if len(mult[param]):
        trivial = mult["trivial"] > 0.5
        real = np.abs(mult["im"]) <= 1e-12
        sel = ~trivial & real
        ax1.plot(mult[param][sel], mult["re"][sel], ".", color="C0", ms=3, label="real multipliers")
        sel = ~trivial & ~real
        ax1.plot(mult[param][sel], mult["modulus"][sel], "^", color="C1", ms=3, label="|mu| of complex pairs")
        ax1.plot(mult[param][trivial], mult["re"][trivial], "x", color="0.6", ms=3, label="trivial")
    ax1.set_ylim(-1.6, 1.6)
    ax1.set_ylabel("Floquet multipliers")
    counts = ", ".join(f"{k} {v}" for k, v in res["label_counts"].items())
    ax1.set_title(f"multipliers over {param} ({counts}; aperiodic points have none)", fontsize=10)
    ax1.legend(loc="lower left", fontsize=8, markerscale=2)
    _diagram(ax2, directory, param)
    fig.suptitle(_title(record, param), fontsize=10)
    return save_in(fig, directory, out_name)


def lyapunov_sweep(directory, out_name="plot.png"):
    """The largest Lyapunov exponent against the swept parameter (the paper's Figures 16, 17)
    with its standard error, over the bifurcation diagram."""
    record = _record(directory)
    res = record["result"]
    param = res["param"]
    tab = _read_table(os.path.join(directory, "exponents.csv"))
    v = np.array([float(x) for x in tab[param]])
    lle = np.array([float(x) for x in tab["lambda1"]])
    se = np.array([float(x) for x in tab["lle_standard_error"]])
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 8), sharex=True, gridspec_kw={"height_ratios": [1, 1]})
    ax1.axhline(0.0, color="k", lw=0.6)
    ok = np.isfinite(lle)
    ax1.errorbar(v[ok], lle[ok], yerr=np.where(np.isfinite(se[ok]), se[ok], 0.0), fmt=".-", color="C3", ms=4,
                 lw=0.8, elinewidth=0.8, capsize=1.5)
    ax1.set_ylabel("largest Lyapunov exponent")
    ax1.set_title(f"mapping at impacts: {res['tdm']}; {res['positive']} of {res['values']} values above 3 "
                  f"standard errors", fontsize=10)
    _diagram(ax2, directory, param)
    fig.suptitle(_title(record, param), fontsize=10)
    return save_in(fig, directory, out_name)
