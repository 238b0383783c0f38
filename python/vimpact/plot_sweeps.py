"""Pictures of the job-loop analyses: bifurcation diagrams, periodicity maps, basins of
attraction and lock-in response curves, plus the figure helpers every vimpact plot shares.

Each drawing function takes a result (``vimpact.sweep(...)``, ``vimpact.Sweep.load(DIR)``, or
any object with the same attributes), returns the matplotlib Figure and, given ``path``,
writes the picture there. ``vimpact.plot`` exposes them; the command line reaches them
through ``python3 -m vimpact.plot KIND DIR``.

Command line (examples/fig10c.sh, fig10d.sh)::

    python3 -m vimpact.plot_sweeps timeseries OUT.png DIR [DIR ...]
"""
import re
import sys

import numpy as np

from .results import Simulation, label_order


# ---------------------------------------------------------------- shared figure helpers

def new_figure(path=None, ax=None, figsize=(9, 5), nrows=1, ncols=1, **kw):
    """(figure, axes) to draw on: ``ax``'s figure when given; a figure outside pyplot when the
    picture only goes to ``path`` (nothing to close, nothing shown); else a pyplot figure, so
    that notebooks and interactive sessions show it."""
    if ax is not None:
        return ax.figure, ax
    if path is not None:
        from matplotlib.figure import Figure
        fig = Figure(figsize=figsize)
        return fig, fig.subplots(nrows, ncols, **kw)
    import matplotlib.pyplot as plt
    return plt.subplots(nrows, ncols, figsize=figsize, **kw)


def finish_figure(fig, path=None, dpi=130, own=True):
    if own:
        fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=dpi)
    return fig


def title(result, varied=()):
    """The model's parameters in one line (the main ones for WakeImpact, all otherwise),
    without those that vary over the picture."""
    p = dict(getattr(result, "parameters", {}) or {})
    preset = getattr(result, "preset", None)
    names = ("Ur", "sigma", "r", "A", "eps") if "Ur" in p else tuple(p)
    text = ", ".join(f"{k} = {p[k]:g}" for k in names if k in p and k not in varied)
    return text + (f"  ({preset} preset)" if preset else "")


def section_name(result):
    section = (getattr(result, "options", None) or {}).get("section", "maxima")
    return {"maxima": "maxima of y", "minima": "minima of y", "impacts": "after impacts"}.get(section, section)


def label_colours(labels):
    """One discrete colour per label: P0 light grey, PN from a qualitative map, aperiodic
    black, inadmissible white, failures red."""
    import matplotlib
    order = label_order(labels)
    cyc = matplotlib.colormaps["tab20"].colors
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


def _extent(xs, ys):
    dx = (xs[-1] - xs[0]) / (len(xs) - 1) if len(xs) > 1 else 1.0
    dy = (ys[-1] - ys[0]) / (len(ys) - 1) if len(ys) > 1 else 1.0
    return [xs[0] - dx / 2, xs[-1] + dx / 2, ys[0] - dy / 2, ys[-1] + dy / 2]


# ---------------------------------------------------------------- the pictures

def bifurcation(result, path=None, ax=None):
    """y at the section against the swept parameter (the paper's Figures 2, 5, 7, 11).

    Parameters
    ----------
    result : Sweep
        Uses ``param``, ``points``, ``point_value``, ``point_branch``, ``ic_mode``,
        ``value``, ``sigma_graze``, ``parameters``.
    path : str, optional
        Write the picture there (PNG at 130 dpi).
    ax : matplotlib Axes, optional
        Draw into it instead of a new figure.

    Returns
    -------
    matplotlib.figure.Figure
    """
    own = ax is None
    fig, ax = new_figure(path, ax, figsize=(9, 5))
    param = result.param
    pv, pb = np.asarray(result.point_value), np.asarray(result.point_branch)
    ys = np.asarray(result.points)[:, 0] if len(pv) else np.empty(0)
    for b in sorted(set(pb.tolist())) or [0]:
        sel = pb == b
        name = {0: "up" if result.ic_mode == "follow" else None, 1: "down"}[b]
        ax.plot(pv[sel], ys[sel], color="k" if b == 0 else "C3", marker=".", ms=1.2, ls="none",
                label=f"sweep {name}" if name else None)
    graze = np.asarray(result.sigma_graze, dtype=float)
    if len(graze) and np.isfinite(graze).all():
        xs = np.asarray(result.value, dtype=float)
        order = np.argsort(xs, kind="stable")
        if param == "sigma":
            ax.axvline(graze[0], color="C0", lw=1, ls="--", label=f"grazing sigma = {graze[0]:.6g}")
        else:
            # On its own (right) axis: on the diagram's scale the line, far below the section
            # points, would squash the diagram.
            gx = ax.twinx()
            gx.plot(xs[order], graze[order], color="C0", lw=1.2, label="grazing value sigma_graze (right axis)")
            sigma = (result.parameters or {}).get("sigma")
            if sigma is not None:
                gx.axhline(sigma, color="C2", lw=1, ls=":", label=f"barrier sigma = {sigma:g} (right axis)")
            gx.set_ylabel("grazing value, barrier", color="C0")
    ax.set_xlabel(param)
    ax.set_ylabel(f"y at the section ({section_name(result)})")
    handles, labels = ax.get_legend_handles_labels()
    for other in ax.figure.axes:
        if other is not ax and other.get_shared_x_axes().joined(ax, other) and other.bbox.bounds == ax.bbox.bounds:
            h, lab = other.get_legend_handles_labels()
            handles, labels = handles + h, labels + lab
    if handles:
        ax.legend(handles, labels, loc="lower left", fontsize=8, markerscale=6)
    if own:
        ax.set_title(f"bifurcation diagram over {param} ({result.ic_mode} starts)", fontsize=10)
        fig.suptitle(title(result, (param,)), fontsize=9)
    return finish_figure(fig, path, own=own)


def periodicity_map(result, path=None, ax=None):
    """The label of every grid point, one discrete colour per label (Figures 4, 8, 9).

    Parameters
    ----------
    result : Map
        Uses ``x``, ``y``, ``x_values``, ``y_values``, ``label`` (ny, nx), ``grazing``.
    path, ax : see ``bifurcation``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    own = ax is None
    fig, ax = new_figure(path, ax, figsize=(9, 6))
    xs, ys = np.asarray(result.x_values, dtype=float), np.asarray(result.y_values, dtype=float)
    cells = np.asarray(result.label)
    order, colours = label_colours(cells.ravel().tolist())
    index = {lab: i for i, lab in enumerate(order)}
    img = np.vectorize(index.get, otypes=[int])(cells) if cells.size else np.zeros((0, 0), dtype=int)
    ax.imshow(img, origin="lower", aspect="auto", extent=_extent(xs, ys),
              cmap=ListedColormap([colours[lab] for lab in order]), vmin=-0.5, vmax=len(order) - 0.5,
              interpolation="nearest")
    handles = [Patch(facecolor=colours[lab], edgecolor="k", lw=0.3, label=lab) for lab in order]
    g = getattr(result, "grazing", None)
    if g is not None and len(g):
        g = np.asarray(g, dtype=float)
        if result.y == "sigma":
            ax.plot(g[:, 0], g[:, 1], color="C3", lw=1.5)
        else:
            ax.plot(g[:, 1], g[:, 0], color="C3", lw=1.5)
        handles.append(Line2D([], [], color="C3", lw=1.5, label="grazing line"))
    ax.set_xlabel(result.x)
    ax.set_ylabel(result.y)
    ax.legend(handles=handles, loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=8, title="label")
    if own:
        ax.set_title(f"periodicity map {result.x} x {result.y} ({len(xs)} x {len(ys)})", fontsize=10)
        fig.suptitle(title(result, (result.x, result.y)), fontsize=9)
    return finish_figure(fig, path, own=own)


def basins(result, path=None, ax=None):
    """The attractor reached from every initial state of the grid (Figure 3).

    Parameters
    ----------
    result : Basins
        Uses ``x``, ``y``, ``x_values``, ``y_values``, ``attractor`` (ny, nx),
        ``attractors``.
    path, ax : see ``bifurcation``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch
    import matplotlib

    own = ax is None
    fig, ax = new_figure(path, ax, figsize=(8, 6))
    xs, ys = np.asarray(result.x_values, dtype=float), np.asarray(result.y_values, dtype=float)
    ids = np.asarray(result.attractor, dtype=int)
    table = list(result.attractors)
    cyc = matplotlib.colormaps["tab10"].colors
    colours = [(1, 1, 1)] + [cyc[i % len(cyc)] for i in range(len(table))]
    ax.imshow(ids + 1, origin="lower", aspect="auto", cmap=ListedColormap(colours), vmin=-0.5,
              vmax=len(colours) - 0.5, interpolation="nearest", extent=_extent(xs, ys))
    handles = [Patch(facecolor=colours[i + 1], edgecolor="k", lw=0.3, label=f"{a.id}: {a.label}")
               for i, a in enumerate(table)]
    if (ids < 0).any():
        handles.append(Patch(facecolor="white", edgecolor="k", lw=0.3, label="below the barrier"))
    ax.legend(handles=handles, loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=8, title="attractor")
    ax.set_xlabel(f"initial {result.x}")
    ax.set_ylabel(f"initial {result.y}")
    if own:
        ax.set_title(f"basins of attraction: {len(table)} attractor(s)", fontsize=10)
        fig.suptitle(title(result), fontsize=9)
    return finish_figure(fig, path, own=own)


def response(result, path=None):
    """Barrier-free amplitude max|y| and frequency ratio against the parameter, one line per
    (A, eps) curve (Figure 10a, b).

    Parameters
    ----------
    result : Response
        Uses ``param``, ``values``, ``curves``, ``amplitude``, ``frequency_ratio``,
        ``structure_frequency``.
    path : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (ax1, ax2) = new_figure(path, None, figsize=(8, 7), nrows=2, ncols=1, sharex=True)
    xs = np.asarray(result.values, dtype=float)
    for k, (a, e) in enumerate(np.asarray(result.curves, dtype=float)):
        lab = f"A = {a:g}, eps = {e:g} (A/eps = {a / e:.3g})" if e else f"A = {a:g}, eps = {e:g}"
        ax1.plot(xs, result.amplitude[k], "-o", ms=2.5, lw=1, color=f"C{k}", label=lab)
        ax2.plot(xs, result.frequency_ratio[k], "-o", ms=2.5, lw=1, color=f"C{k}")
    if result.param == "Ur" and len(xs):
        order = np.argsort(xs, kind="stable")
        ax2.plot(xs[order], np.asarray(result.structure_frequency)[0][order], "k--", lw=0.8,
                 label="structure natural frequency 1/(St Ur)")
        ax2.axhline(1.0, color="k", lw=0.8, ls=":", label="wake (Strouhal) frequency")
        ax2.legend(fontsize=8)
    ax1.set_ylabel("amplitude max |y|")
    ax1.legend(fontsize=8)
    ax2.set_ylabel("frequency of y / wake frequency")
    ax2.set_xlabel(result.param)
    ax1.set_title("barrier-free response (lock-in)", fontsize=10)
    fig.suptitle(title(result, (result.param, "sigma", "A", "eps")), fontsize=9)
    return finish_figure(fig, path)


def timeseries_overlay(results, path=None, window=200.0):
    """y(t) of several simulations in one picture (Figure 10c, d): the last ``window`` time
    units of each (``series_t``, ``series`` of a Simulation made with ``sample_dt > 0``),
    labelled by A and eps, with its barrier."""
    fig, ax = new_figure(path, None, figsize=(10, 4.5))
    for k, r in enumerate(results):
        p = r.parameters
        t = np.asarray(r.series_t) - r.series_t[0]
        keep = t >= t[-1] - window
        ax.plot(t[keep] - t[keep][0], np.asarray(r.series)[keep, 0], lw=0.9, color=f"C{k}",
                label=f"A = {p['A']:g}, eps = {p['eps']:.4g} (A/eps = {p['A'] / p['eps']:.3g})")
        ax.axhline(p["sigma"], color=f"C{k}", lw=0.8, ls="--")
    ax.set_xlabel(f"t (last {window:g} time units of the recorded window)")
    ax.set_ylabel("y")
    ax.legend(fontsize=8, loc="upper right")
    ax.set_title("structural displacement with the barrier (dashed)", fontsize=10)
    return finish_figure(fig, path)


def main(argv):
    if len(argv) < 4 or argv[1] != "timeseries":
        print("usage: python3 -m vimpact.plot_sweeps timeseries OUT.png DIR...", file=sys.stderr)
        return 2
    timeseries_overlay([Simulation.load(d) for d in argv[3:]], argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
