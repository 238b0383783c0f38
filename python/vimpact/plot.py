"""Plots of vimpact results, shared by the command line and Python users.

Command-line use (what ``vimpact ... --out DIR`` runs)::

    /usr/bin/python3 -m vimpact.plot simulate DIR
    /usr/bin/python3 -m vimpact.plot period DIR
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_csv(path):
    """Read a vimpact CSV (header line, then numbers) into a dict of column arrays."""
    with open(path) as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if data.size == 0:
        data = np.empty((0, len(header)))
    return {name: data[:, i] for i, name in enumerate(header)}


def _title(record):
    p = record["config"]["parameters"]
    return (f"Ur = {p['Ur']:g}, sigma = {p['sigma']:g}, r = {p['r']:g}, "
            f"A = {p['A']:g}, eps = {p['eps']:g}  ({record['config']['preset']} preset)")


def timeseries_and_phase(directory, out_name="plot.png"):
    """Time series of y with impacts, and the (y, ydot) phase portrait with section points."""
    record = json.load(open(os.path.join(directory, "run.json")))
    ts = read_csv(os.path.join(directory, "timeseries.csv"))
    imp = read_csv(os.path.join(directory, "impacts.csv"))
    sec = read_csv(os.path.join(directory, "sections.csv"))
    sigma = record["config"]["parameters"]["sigma"]

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.5), gridspec_kw={"width_ratios": [1.6, 1]})
    # The last `window` time units, so single oscillations and impacts stay visible.
    window = 200.0
    t_end = ts["t"][-1] if len(ts["t"]) else 0.0
    keep = ts["t"] >= t_end - window
    ts_w = {k: v[keep] for k, v in ts.items()}
    imp = {k: v[imp["t"] >= t_end - window] for k, v in imp.items()}
    sec_w = {k: v[sec["t"] >= t_end - window] for k, v in sec.items()}
    ax1.plot(ts_w["t"], ts_w["y"], lw=0.8, color="C0", label="y")
    ax1.axhline(sigma, color="k", lw=1.0, ls="--", label=f"barrier sigma = {sigma:g}")
    if len(imp["t"]):
        ax1.plot(imp["t"], imp["y"], "rv", ms=3, label="impacts")
    if len(sec_w["t"]):
        ax1.plot(sec_w["t"], sec_w["y"], "g^", ms=4, label="section points")
    ax1.set_xlabel("t")
    ax1.set_ylabel("y")
    ax1.legend(loc="upper right", fontsize=8)
    ax1.set_title(f"time series, last {window:g} time units (outcome {record['result']['outcome']})",
                  fontsize=10)

    ax2.plot(ts["y"], ts["ydot"], lw=0.6, color="C0")
    ax2.axvline(sigma, color="k", lw=1.0, ls="--")
    if len(sec["t"]):
        ax2.plot(sec["y"], sec["ydot"], "g^", ms=4)
    ax2.set_xlabel("y")
    ax2.set_ylabel("dy/dt")
    ax2.set_title("phase portrait", fontsize=10)
    fig.suptitle(_title(record), fontsize=10)
    fig.tight_layout()
    path = os.path.join(directory, out_name)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def section_points(directory, out_name="plot.png"):
    """Section points (y, x) of a period run, labelled with the period."""
    record = json.load(open(os.path.join(directory, "run.json")))
    sec = read_csv(os.path.join(directory, "sections.csv"))
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.plot(sec["y"], sec["x"], "o", ms=3)
    ax.set_xlabel("y at section")
    ax.set_ylabel("x at section")
    ax.set_title(f"{record['result']['label']}: {len(sec['t'])} section points", fontsize=10)
    fig.suptitle(_title(record), fontsize=9)
    fig.tight_layout()
    path = os.path.join(directory, out_name)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _kinds():
    """Plot kind (the first argument of ``python3 -m vimpact.plot``) -> function(directory).

    Kinds of other analyses live in their own modules (plot_<topic>.py) and are listed here."""
    from . import plot_dimension, plot_sweeps

    return {
        "simulate": timeseries_and_phase,
        "period": section_points,
        "sweep": plot_sweeps.bifurcation,
        "map": plot_sweeps.periodicity_map,
        "basins": plot_sweeps.basins,
        "response": plot_sweeps.response,
        "dimension": plot_dimension.dimension,
    }


def main(argv):
    kinds = _kinds()
    if len(argv) != 3 or argv[1] not in kinds:
        print(f"usage: python3 -m vimpact.plot {'|'.join(sorted(kinds))} DIR", file=sys.stderr)
        return 2
    kinds[argv[1]](argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
