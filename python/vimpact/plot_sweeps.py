"""Pictures of the job-loop commands: bifurcation diagrams, periodicity maps, basins of
attraction and lock-in response curves. Each function reads a ``vimpact ... --out DIR``
directory and writes DIR/plot.png (or ``out_name``)."""
import csv
import json
import os
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from .plot import _title, read_csv  # noqa: E402


def read_table(path):
    """A vimpact CSV with text cells (labels) as a dict of column lists (strings)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    return {name: [r[i] for r in body] for i, name in enumerate(header)}


def _record(directory):
    with open(os.path.join(directory, "run.json")) as f:
        return json.load(f)


def _label_order(labels):
    """P0, P1, P2, ... in numeric order, then aperiodic, then failures and others."""
    def key(lab):
        m = re.fullmatch(r"P(\d+)", lab)
        if m:
            return (0, int(m.group(1)), lab)
        return (1 if lab == "aperiodic" else 2, 0, lab)
    return sorted(set(labels), key=key)


def _label_colours(labels):
    """One discrete colour per label: P0 light grey, PN from a qualitative map, aperiodic
    black, failures red-ish."""
    order = _label_order(labels)
    cyc = plt.get_cmap("tab20").colors
    colours, k = {}, 0
    for lab in order:
        if lab == "P0":
            colours[lab] = (0.85, 0.85, 0.85)
        elif lab == "aperiodic":
            colours[lab] = (0.0, 0.0, 0.0)
        elif lab == "inadmissible":
            colours[lab] = (1.0, 1.0, 1.0)
        elif re.fullmatch(r"P\d+", lab):
            colours[lab] = cyc[k % len(cyc)]
            k += 1
        else:
            colours[lab] = (0.8, 0.1, 0.1)
    return order, colours


def bifurcation(directory, out_name="plot.png", ax=None):
    """y at the section against the swept parameter (the paper's Figures 2, 5, 7, 11)."""
    record = _record(directory)
    res = record["result"]
    param = res["param"]
    pts = read_csv(os.path.join(directory, "points.csv"))
    lab = read_table(os.path.join(directory, "labels.csv"))
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(9, 5))
    branches = sorted(set(pts["branch"].astype(int))) if len(pts["branch"]) else [0]
    for b in branches:
        sel = pts["branch"] == b
        name = {0: "up" if res["ic_mode"] == "follow" else None, 1: "down"}[b]
        ax.plot(pts[param][sel], pts["y"][sel], color="k" if b == 0 else "C3",
                marker=".", ms=1.2, ls="none", label=f"sweep {name}" if name else None)
    params = record["config"]["parameters"]
    graze = [float(g) for g in lab["sigma_graze"] if g not in ("nan", "")]
    if graze and len(graze) == len(lab[param]):
        xs = np.array([float(v) for v in lab[param]])
        order = np.argsort(xs)
        if param == "sigma":
            ax.axvline(graze[0], color="C0", lw=1, ls="--", label=f"grazing sigma = {graze[0]:.6g}")
        else:
            ax.plot(xs[order], np.array(graze)[order], color="C0", lw=1.2, label="grazing value sigma_graze")
            ax.axhline(params["sigma"], color="C2", lw=1, ls=":", label=f"barrier sigma = {params['sigma']:g}")
    ax.set_xlabel(param)
    ax.set_ylabel("y at the section (maxima of y)")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="best", fontsize=8, markerscale=6)
    if own:
        ax.set_title(f"bifurcation diagram over {param} ({res['ic_mode']} starts)", fontsize=10)
        fig.suptitle(_title(record), fontsize=9)
        fig.tight_layout()
        path = os.path.join(directory, out_name)
        fig.savefig(path, dpi=130)
        plt.close(fig)
        return path
    return ax


def _grid_image(ax, xs, ys, cells, order, colours):
    index = {lab: i for i, lab in enumerate(order)}
    img = np.array([[index[c] for c in row] for row in cells])
    cmap = ListedColormap([colours[lab] for lab in order])
    dx = (xs[-1] - xs[0]) / (len(xs) - 1) if len(xs) > 1 else 1.0
    dy = (ys[-1] - ys[0]) / (len(ys) - 1) if len(ys) > 1 else 1.0
    extent = [xs[0] - dx / 2, xs[-1] + dx / 2, ys[0] - dy / 2, ys[-1] + dy / 2]
    ax.imshow(img, origin="lower", aspect="auto", extent=extent, cmap=cmap,
              vmin=-0.5, vmax=len(order) - 0.5, interpolation="nearest")


def periodicity_map(directory, out_name="plot.png"):
    """The label of every grid point, one discrete colour per label (Figures 4, 8, 9)."""
    record = _record(directory)
    res = record["result"]
    xs, ys = np.array(res["x_values"]), np.array(res["y_values"])
    cells = res["labels"]
    order, colours = _label_colours([c for row in cells for c in row])
    fig, ax = plt.subplots(figsize=(9, 6))
    _grid_image(ax, xs, ys, cells, order, colours)
    handles = [Patch(facecolor=colours[lab], edgecolor="k", lw=0.3, label=lab) for lab in order]
    if res.get("grazing"):
        g = np.array([[np.nan if v is None else v for v in e] for e in res["grazing"]], dtype=float)
        if res["y"] == "sigma":
            ax.plot(g[:, 0], g[:, 1], color="C3", lw=1.5)
        else:
            ax.plot(g[:, 1], g[:, 0], color="C3", lw=1.5)
        handles.append(plt.Line2D([], [], color="C3", lw=1.5, label="grazing line"))
    ax.set_xlabel(res["x"])
    ax.set_ylabel(res["y"])
    ax.legend(handles=handles, loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=8, title="label")
    ax.set_title(f"periodicity map {res['x']} x {res['y']} ({len(xs)} x {len(ys)})", fontsize=10)
    fig.suptitle(_title(record), fontsize=9)
    fig.tight_layout()
    path = os.path.join(directory, out_name)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def basins(directory, out_name="plot.png"):
    """Attractor reached from every initial state of the grid (Figure 3)."""
    record = _record(directory)
    res = record["result"]
    tab = read_table(os.path.join(directory, "cells.csv"))
    sx, sy = res["x"], res["y"]
    xs = np.unique(np.array(tab[sx], dtype=float))
    ys = np.unique(np.array(tab[sy], dtype=float))
    ny, nx = res["shape"]
    ids = np.array(tab["attractor"], dtype=int).reshape(ny, nx)
    table = res["attractors"]["table"]
    names = [f"{t['id']}: {t['label']}" for t in table]
    cyc = plt.get_cmap("tab10").colors
    colours = [(1, 1, 1)] + [cyc[i % len(cyc)] for i in range(len(table))]
    fig, ax = plt.subplots(figsize=(8, 6))
    dx = (xs[-1] - xs[0]) / (len(xs) - 1) if len(xs) > 1 else 1.0
    dy = (ys[-1] - ys[0]) / (len(ys) - 1) if len(ys) > 1 else 1.0
    ax.imshow(ids + 1, origin="lower", aspect="auto", cmap=ListedColormap(colours),
              vmin=-0.5, vmax=len(colours) - 0.5, interpolation="nearest",
              extent=[xs[0] - dx / 2, xs[-1] + dx / 2, ys[0] - dy / 2, ys[-1] + dy / 2])
    handles = [Patch(facecolor=colours[i + 1], edgecolor="k", lw=0.3, label=n) for i, n in enumerate(names)]
    if (ids < 0).any():
        handles.append(Patch(facecolor="white", edgecolor="k", lw=0.3, label="below the barrier"))
    ax.legend(handles=handles, loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=8, title="attractor")
    ax.set_xlabel(f"initial {sx}")
    ax.set_ylabel(f"initial {sy}")
    ax.set_title(f"basins of attraction: {len(table)} attractor(s)", fontsize=10)
    fig.suptitle(_title(record), fontsize=9)
    fig.tight_layout()
    path = os.path.join(directory, out_name)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def response(directory, out_name="plot.png"):
    """Barrier-free amplitude max|y| and frequency ratio against the parameter, one line per
    (A, eps) curve (Figure 10a, b)."""
    record = _record(directory)
    res = record["result"]
    param = res["param"]
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    for k, c in enumerate(res["curves"]):
        xs = np.array(c["values"], dtype=float)
        amp = np.array([np.nan if v is None else v for v in c["amplitude"]], dtype=float)
        fr = np.array([np.nan if v is None else v for v in c["frequency_ratio"]], dtype=float)
        lab = f"A = {c['A']:g}, eps = {c['eps']:g} (A/eps = {c['A'] / c['eps']:.3g})"
        ax1.plot(xs, amp, "-o", ms=2.5, lw=1, color=f"C{k}", label=lab)
        ax2.plot(xs, fr, "-o", ms=2.5, lw=1, color=f"C{k}")
    data = read_csv(os.path.join(directory, "response.csv"))
    if param == "Ur" and len(data["Ur"]):
        order = np.argsort(data["Ur"])
        ax2.plot(data["Ur"][order], data["structure_frequency"][order], "k--", lw=0.8,
                 label="structure natural frequency 1/(St Ur)")
        ax2.axhline(1.0, color="k", lw=0.8, ls=":", label="wake (Strouhal) frequency")
        ax2.legend(fontsize=8)
    ax1.set_ylabel("amplitude max |y|")
    ax1.legend(fontsize=8)
    ax2.set_ylabel("frequency of y / wake frequency")
    ax2.set_xlabel(param)
    ax1.set_title("barrier-free response (lock-in)", fontsize=10)
    fig.suptitle(_title(record), fontsize=9)
    fig.tight_layout()
    path = os.path.join(directory, out_name)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def timeseries_overlay(out_path, directories, window=200.0):
    """y(t) of several ``simulate --out`` runs in one picture (Figure 10c, d): the last
    ``window`` time units of each, labelled by their A and eps, with their barrier."""
    fig, ax = plt.subplots(figsize=(10, 4.5))
    for k, d in enumerate(directories):
        record = _record(d)
        p = record["config"]["parameters"]
        ts = read_csv(os.path.join(d, "timeseries.csv"))
        t = ts["t"] - ts["t"][0]
        keep = t >= t[-1] - window
        ax.plot(t[keep] - t[keep][0], ts["y"][keep], lw=0.9, color=f"C{k}",
                label=f"A = {p['A']:g}, eps = {p['eps']:.4g} (A/eps = {p['A'] / p['eps']:.3g})")
        ax.axhline(p["sigma"], color=f"C{k}", lw=0.8, ls="--")
    ax.set_xlabel(f"t (last {window:g} time units of the recorded window)")
    ax.set_ylabel("y")
    ax.legend(fontsize=8, loc="upper right")
    ax.set_title("structural displacement with the barrier (dashed)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out_path, dpi=130)
    plt.close(fig)
    return out_path


def main(argv):
    if len(argv) < 4 or argv[1] != "timeseries":
        print("usage: python3 -m vimpact.plot_sweeps timeseries OUT.png DIR...", file=__import__("sys").stderr)
        return 2
    timeseries_overlay(argv[2], argv[3:])
    return 0


if __name__ == "__main__":
    import sys

    sys.exit(main(sys.argv))
