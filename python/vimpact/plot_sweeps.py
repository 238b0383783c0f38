"""Pictures of the job-loop analyses: bifurcation diagrams, periodicity maps, basins of
attraction and response curves, for any model.

Each drawing function takes a result (``vimpact.sweep(...)``, ``vimpact.Sweep.load(DIR)``, or
any object with the same attributes), returns the matplotlib Figure and, given ``path``,
writes the picture there. ``vimpact.plot`` exposes them; the command line reaches them
through ``python3 -m vimpact.plot KIND DIR``. The variable drawn is the result's
``plot_variable`` (the model's first state variable unless the run said otherwise).

Command line (examples/fig10c.sh, fig10d.sh)::

    python3 -m vimpact.plot_sweeps timeseries OUT.png DIR [DIR ...]
"""
import sys

import numpy as np

from .plot_common import (extent, finish_figure, label_axis, label_colours, legend_entries, legend_outside,
                          neutral_lines, new_figure, plain_text, plot_index, section_name, state_name, suptitle,
                          title)
from .results import Simulation


def _grazing_lines(ax, result, xs, neutral=False):
    """The grazing value of each surface against the swept parameter, on a right-hand axis
    (on the diagram's scale a line far below the section points would squash it); ``neutral``:
    in the colourless ``neutral_lines``, beside points coloured by label."""
    g = np.asarray(getattr(result, "grazing", None) if getattr(result, "grazing", None) is not None
                   else np.empty((0, 0)), dtype=float)
    gparam = getattr(result, "grazing_param", None)
    if g.ndim == 1:
        g = g[:, None]
    if not g.size or not np.isfinite(g).any():
        return
    surfaces = tuple(getattr(result, "surfaces", ()) or ()) or tuple(f"surface {i}" for i in range(g.shape[1]))
    lines = neutral_lines()

    def style(s, **default):
        return lines[s % len(lines)] if neutral else dict(default, color=f"C{s}")

    if gparam == result.param:
        for s in range(g.shape[1]):
            if np.isfinite(g[:, s]).any():
                v = g[np.isfinite(g[:, s]), s][0]
                ax.axvline(v, **style(s, lw=1, ls="--"), label=f"grazing {gparam} = {v:.6g} ({surfaces[s]})")
        return
    order = np.argsort(xs, kind="stable")
    gx = ax.twinx()
    for s in range(g.shape[1]):
        if np.isfinite(g[:, s]).any():
            gx.plot(xs[order], g[order, s], **style(s, lw=1.2), label=f"grazing {gparam} ({surfaces[s]}), right axis")
    current = (getattr(result, "parameters", None) or {}).get(gparam)
    if current is not None:
        gx.axhline(current, color="0.5" if neutral else "C2", lw=1, ls=":", label=f"{gparam} = {current:g}, right axis")
    label_axis(gx, "y", result, gparam, before="grazing value of ")
    gx.yaxis.label.set_color("k" if neutral else "C0")


# bifurcation(color_by=...): how the section points are coloured.
COLOR_BY = ("none", "period")


def _period_points(ax, result, pv, ys):
    """Each run's section points in the colour of its period label (``label_colours``), and a
    legend entry for every label of the result, also those of runs without points (failed
    runs), so that the legend lists the outcomes the sweep met."""
    from matplotlib.lines import Line2D
    labels = np.asarray(result.label).astype(str)
    point_label = labels[np.asarray(result.point_run, dtype=int)] if len(pv) else np.empty(0, dtype=str)
    order, colours = label_colours(labels.tolist())
    for lab in order:
        sel = point_label == lab
        ax.plot(pv[sel], ys[sel], color=colours[lab], marker=".", ms=2.0, ls="none")
    return [Line2D([], [], color=colours[lab], marker="o", ms=5, mec="k", mew=0.3, ls="none", label=lab)
            for lab in order]


def bifurcation(result, path=None, ax=None, color_by="none"):
    """The plot variable at the section against the swept parameter (the paper's Figures 2,
    5, 7, 11), with the grazing values of the surfaces when the sweep computed them.

    Parameters
    ----------
    result : Sweep
        Uses ``param``, ``points``, ``point_value``, ``point_branch``, ``ic_mode``,
        ``value``, ``grazing``, ``grazing_param``, ``state_names``, ``plot_variable``,
        ``parameters`` (and ``label``, ``point_run`` to colour by period; ``state_info``,
        ``parameter_info`` for the units).
    path : str, optional
        Write the picture there (PNG at 130 dpi).
    ax : matplotlib Axes, optional
        Draw into it instead of a new figure.
    color_by : {"none", "period"}, default "none"
        ``"period"``: each value's section points in the colour of its period label (P1, P2,
        ..., aperiodic, and the outcomes of failed runs), with a legend of the labels present;
        ``"none"``: black points (red for the downward branch of ``direction="both"``).

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        ``color_by`` is not one of ``COLOR_BY``.
    """
    if color_by is None:
        color_by = "none"
    if color_by not in COLOR_BY:
        raise ValueError(f"color_by must be one of {', '.join(COLOR_BY)} (got {color_by!r})")
    own = ax is None
    fig, ax = new_figure(path, ax, figsize=(10.5, 5))
    param = result.param
    k = plot_index(result)
    pv, pb = np.asarray(result.point_value), np.asarray(result.point_branch)
    ys = np.asarray(result.points)[:, k] if len(pv) else np.empty(0)
    if color_by == "period":
        label_handles = _period_points(ax, result, pv, ys)
    else:
        label_handles = []
        for b in sorted(set(pb.tolist())) or [0]:
            sel = pb == b
            name = {0: "up" if getattr(result, "ic_mode", "fixed") == "follow" else None, 1: "down"}[b]
            ax.plot(pv[sel], ys[sel], color="k" if b == 0 else "C3", marker=".", ms=1.2, ls="none",
                    label=f"sweep {name}" if name else None)
    _grazing_lines(ax, result, np.asarray(result.value, dtype=float), neutral=color_by == "period")
    label_axis(ax, "x", result, param)
    label_axis(ax, "y", result, state_name(result, k), after=f" at the section ({section_name(result)})")
    # The labels first: with color_by="period" they are what the colours mean.
    legend_outside(ax, label_handles + legend_entries(ax), markerscale=1 if label_handles else 6)
    if own:
        ax.set_title(f"bifurcation diagram over {param} ({getattr(result, 'ic_mode', 'fixed')} starts)", fontsize=10)
        suptitle(fig, title(result, (param,)))
    return finish_figure(fig, path, own=own)


def periodicity_map(result, path=None, ax=None):
    """The label of every grid point, one discrete colour per label (Figures 4, 8, 9), with
    the grazing line of each surface when the map computed it.

    Parameters
    ----------
    result : Map
        Uses ``x``, ``y``, ``x_values``, ``y_values``, ``label`` (ny, nx), ``grazing_param``,
        ``grazing_other``, ``grazing``.
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
    ax.imshow(img, origin="lower", aspect="auto", extent=extent(xs, ys),
              cmap=ListedColormap([colours[lab] for lab in order]), vmin=-0.5, vmax=len(order) - 0.5,
              interpolation="nearest")
    handles = [Patch(facecolor=colours[lab], edgecolor="k", lw=0.3, label=lab) for lab in order]
    g = getattr(result, "grazing", None)
    other = getattr(result, "grazing_other", None)
    if g is not None and other is not None and len(other):
        g = np.asarray(g, dtype=float).reshape(len(other), -1)
        surfaces = tuple(getattr(result, "surfaces", ()) or ()) or tuple(f"surface {i}" for i in range(g.shape[1]))
        line = neutral_lines()
        for s in range(g.shape[1]):
            if not np.isfinite(g[:, s]).any():
                continue
            if result.grazing_param == result.y:
                ax.plot(other, g[:, s], **line[s % len(line)])
            else:
                ax.plot(g[:, s], other, **line[s % len(line)])
            handles.append(Line2D([], [], label=f"grazing line ({surfaces[s]})", **line[s % len(line)]))
        ax.set_xlim(extent(xs, ys)[:2])
        ax.set_ylim(extent(xs, ys)[2:])
    label_axis(ax, "x", result, result.x)
    label_axis(ax, "y", result, result.y)
    legend_outside(ax, handles, title="label")
    if own:
        ax.set_title(f"periodicity map {result.x} x {result.y} ({len(xs)} x {len(ys)})", fontsize=10)
        suptitle(fig, title(result, (result.x, result.y)))
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
              vmax=len(colours) - 0.5, interpolation="nearest", extent=extent(xs, ys))
    handles = [Patch(facecolor=colours[i + 1], edgecolor="k", lw=0.3, label=f"{a.id}: {a.label}")
               for i, a in enumerate(table)]
    if (ids < 0).any():
        handles.append(Patch(facecolor="white", edgecolor="k", lw=0.3, label="beyond a surface"))
    label_axis(ax, "x", result, result.x, before="initial ")
    label_axis(ax, "y", result, result.y, before="initial ")
    legend_outside(ax, handles, title="attractor")
    if own:
        ax.set_title(f"basins of attraction: {len(table)} attractor(s)", fontsize=10)
        suptitle(fig, title(result))
    return finish_figure(fig, path, own=own)


def response(result, path=None):
    """Surface-free amplitude and angular frequency of the measured variable against the
    parameter, one line per curve (Figure 10a, b).

    Parameters
    ----------
    result : Response
        Uses ``param``, ``values``, ``curves``, ``variable``, ``amplitude``, ``frequency``.
    path : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (ax1, ax2) = new_figure(path, None, figsize=(8, 7), nrows=2, ncols=1, sharex=True)
    xs = np.asarray(result.values, dtype=float)
    curves = list(result.curves) or [{}]
    for k, c in enumerate(curves):
        lab = ", ".join(f"{n} = {v:g}" for n, v in c.items()) or "the model's values"
        ax1.plot(xs, result.amplitude[k], "-o", ms=2.5, lw=1, color=f"C{k}", label=lab)
        ax2.plot(xs, result.frequency[k], "-o", ms=2.5, lw=1, color=f"C{k}")
    var = getattr(result, "variable", None) or "the variable"
    label_axis(ax1, "y", result, var, before="amplitude max |", after="|")
    legend_outside(ax1)
    # An angle per unit of the model's time, whatever the variable's unit.
    ax2.set_ylabel(plain_text(f"angular frequency of {var} [rad per unit t]"))
    label_axis(ax2, "x", result, result.param)
    ax1.set_title("surface-free response", fontsize=10)
    varied = (result.param,) + tuple(n for c in curves for n in c)
    suptitle(fig, title(result, varied))
    return finish_figure(fig, path)


def timeseries_overlay(results, path=None, window=200.0):
    """The plot variable against time for several simulations in one picture (Figure 10c,
    d): the last ``window`` time units of each (``series_t``, ``series`` of a Simulation made
    with ``sample_dt > 0``), each with the surfaces its impacts show."""
    from .plot_common import surface_levels
    fig, ax = new_figure(path, None, figsize=(10, 4.5))
    first = results[0] if results else None
    for k, r in enumerate(results):
        i = plot_index(r)
        t = np.asarray(r.series_t) - r.series_t[0]
        keep = t >= t[-1] - window
        varied = {n: v for n, v in (r.parameters or {}).items()
                  if any((o.parameters or {}).get(n) != v for o in results)}
        lab = ", ".join(f"{n} = {v:.4g}" for n, v in varied.items()) or f"run {k}"
        ax.plot(t[keep] - t[keep][0], np.asarray(r.series)[keep, i], lw=0.9, color=f"C{k}", label=lab)
        for name, level in surface_levels(r, i).items():
            ax.axhline(level, color=f"C{k}", lw=0.8, ls="--")
    ax.set_xlabel(f"t (last {window:g} time units of the recorded window)")
    if first is not None:
        label_axis(ax, "y", first, state_name(first, plot_index(first)))
    legend_outside(ax)
    ax.set_title("time series, with the surfaces hit (dashed)", fontsize=10)
    return finish_figure(fig, path)


def main(argv):
    if len(argv) < 4 or argv[1] != "timeseries":
        print("usage: python3 -m vimpact.plot_sweeps timeseries OUT.png DIR...", file=sys.stderr)
        return 2
    timeseries_overlay([Simulation.load(d) for d in argv[3:]], argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
