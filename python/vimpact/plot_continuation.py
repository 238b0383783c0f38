"""Pictures of a continuation: the branches in the parameter against the plot variable at the
section (stable solid, unstable dashed, every section point of an orbit), the largest
nontrivial multiplier along them, the bifurcations marked, over the brute-force diagram when
the result has one; and the curves of bifurcation points in the plane of two parameters over
the brute-force periodicity map when it has one."""
import numpy as np

from .plot_common import (extent, finish_figure, label_axis, label_colours, legend_outside, new_figure, section_name,
                          state_name, suptitle, title)

# Marker per bifurcation type.
MARKERS = {"fold": ("s", "fold"), "period_doubling": ("D", "period doubling"),
           "neimark_sacker": ("*", "Neimark-Sacker"), "grazing": ("^", "grazing")}


def _runs(keys):
    """Index ranges [a, b] of consecutive points with equal keys, each overlapping the next by
    one point (a line without gaps)."""
    runs, a = [], 0
    for i in range(1, len(keys) + 1):
        if i == len(keys) or keys[i] != keys[a]:
            runs.append((a, min(i, len(keys) - 1), keys[a]))
            a = i
    return runs


def _largest_nontrivial(m):
    """The largest modulus among the multipliers after the trivial one (column 0)."""
    m = np.asarray(m)
    return np.nanmax(np.abs(m[:, 1:]), axis=1) if m.shape[1] > 1 else np.full(len(m), np.nan)


def _results(result):
    return list(result) if isinstance(result, (list, tuple)) else [result]


def continuation(result, path=None):
    """The branches and their bifurcations (and, with curves, the two-parameter plane).

    Parameters
    ----------
    result : Continuation, or a list of them (continuations in the same parameter from several
        starts, drawn together)
        Uses ``branches``, ``bifurcations``, ``param``, ``plot_variable``, and when present
        ``diagram`` (drawn underneath in grey), ``curves`` and ``map``.
    path : str, optional
        Write the picture there.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.lines import Line2D

    results = _results(result)
    first = results[0]
    two = any(r.curves or r.map is not None for r in results)
    rows = 3 if two else 2
    fig, axes = new_figure(path, None, figsize=(10, 4.2 * rows - 1.5 * (rows - 1)), nrows=rows, ncols=1,
                           gridspec_kw={"height_ratios": [3, 1.3] + ([3] if two else [])})
    ax, axm = axes[0], axes[1]
    k = first.plot_index
    name = state_name(first, k)
    handles = []
    diagram = next((r.diagram for r in results if r.diagram is not None), None)
    if diagram is not None and len(diagram["value"]):
        ax.plot(diagram["value"], diagram["points"][:, k], ".", ms=2.5, color="0.55", zorder=1)
        handles.append(Line2D([], [], ls="", marker=".", color="0.6", label="brute-force diagram"))
    # A colour per period (returns per period), in order: distinct for up to ten periods.
    colours = {p: f"C{i % 10}" for i, p in enumerate(sorted({b.returns for r in results for b in r.branches}))}
    seen = set()
    for r in results:
        for b in r.branches:
            colour = colours[b.returns]
            for a, e, stable in _runs([bool(v) for v in b.stable]):
                s = slice(a, e + 1)
                for j in range(b.returns):
                    ax.plot(b.param[s], b.sections[s, j, k], ls="-" if stable else "--", color=colour, lw=1.3,
                            zorder=3)
            # Multipliers jump at a grazing (they grow like 1 / v as an impact's velocity v goes
            # to 0): no line across a change of the impacts per period.
            mu = _largest_nontrivial(b.multipliers)
            for a, e, (stable, _) in _runs(list(zip([bool(v) for v in b.stable], b.impacts.tolist()))):
                e = e if e == len(b.param) - 1 or b.impacts[e] == b.impacts[a] else e - 1
                s = slice(a, e + 1)
                axm.plot(b.param[s], mu[s], ls="-" if stable else "--", color=colour, lw=1.1)
        for bf in r.bifurcations:
            marker, text = MARKERS.get(bf.type, ("o", bf.type))
            ys = bf.sections[:, k] if bf.sections is not None and len(bf.sections) else [bf.state[k]]
            ax.plot([bf.param] * len(ys), ys, ls="", marker=marker, ms=6, mfc="w", mec="k", mew=1.2, zorder=5)
            mu = np.abs(bf.multipliers[1:]) if len(bf.multipliers) > 1 else [np.nan]
            axm.plot([bf.param], [np.nanmax(mu)], ls="", marker=marker, ms=5, mfc="w", mec="k", mew=1.1, zorder=5)
            seen.add(bf.type)
    for p, colour in colours.items():
        handles.append(Line2D([], [], color=colour, lw=1.4, label=f"P{p} orbits"))
    handles += [Line2D([], [], color="k", lw=1.2, ls="-", label="stable"),
                Line2D([], [], color="k", lw=1.2, ls="--", label="unstable")]
    for t in MARKERS:
        if t in seen:
            handles.append(Line2D([], [], ls="", marker=MARKERS[t][0], mfc="w", mec="k", label=MARKERS[t][1]))
    axm.axhline(1.0, color="k", lw=0.8, ls=":")
    label_axis(ax, "y", first, name, after=f" at the section ({section_name(first)})")
    label_axis(axm, "x", first, first.param)
    axm.set_ylabel("largest |multiplier|\n(trivial excluded)")
    axm.set_yscale("log")
    lo = min(min(r.range) for r in results)
    hi = max(max(r.range) for r in results)
    ax.set_xlim(lo, hi)
    axm.set_xlim(lo, hi)
    legend_outside(ax, handles)
    nb = sum(len(r.branches) for r in results)
    nf = sum(len(r.bifurcations) for r in results)
    ax.set_title(f"continuation in {first.param}: {nb} branch(es), {nf} bifurcation(s)", fontsize=10)
    if two:
        _plane(axes[2], results)
    suptitle(fig, title(first, (first.param, first.param2) if first.param2 else (first.param,)))
    return finish_figure(fig, path, dpi=120)


def curves(result, path=None, map=None):
    """The curves of bifurcation points in the plane of the two parameters, over a brute-force
    periodicity map: the result's own (``continue --map``) or ``map``, a Map of
    ``vimpact.map`` over the same two parameters.

    Parameters
    ----------
    result : Continuation with curves, or a list of them (the same two parameters)
    path : str, optional
    map : Map, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    results = _results(result)
    fig, ax = new_figure(path, None, figsize=(10, 6))
    grid = None
    if map is not None:
        grid = dict(x=np.asarray(map.x_values, dtype=float), y=np.asarray(map.y_values, dtype=float),
                    label=np.asarray(map.label))
    _plane(ax, results, grid)
    first = results[0]
    suptitle(fig, title(first, (first.param, first.param2)))
    return finish_figure(fig, path, dpi=120)


def _plane(ax, results, grid=None):
    """The curves in (param, param2) over the brute-force map (``grid``: x, y, label (ny, nx);
    default the first result's own)."""
    from matplotlib import patheffects
    from matplotlib.colors import ListedColormap
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    first = results[0]
    grid = grid if grid is not None else next((r.map for r in results if r.map is not None), None)
    handles = []
    if grid is not None:
        xs, ys, cells = grid["x"], grid["y"], np.asarray(grid["label"])
        order, colours = label_colours(cells.ravel().tolist())
        index = {lab: i for i, lab in enumerate(order)}
        img = np.vectorize(index.get, otypes=[int])(cells)
        ax.imshow(img, origin="lower", aspect="auto", extent=extent(xs, ys),
                  cmap=ListedColormap([colours[lab] for lab in order]), vmin=-0.5, vmax=len(order) - 0.5,
                  interpolation="nearest", zorder=0)
        handles += [Patch(facecolor=colours[lab], edgecolor="k", lw=0.3, label=lab) for lab in order]
    edge = [patheffects.withStroke(linewidth=3.2, foreground="k")]
    styles = {"fold": dict(color="C3", ls="-"), "period_doubling": dict(color="w", ls="-", path_effects=edge),
              "grazing": dict(color="k", ls="--")}
    drawn = set()
    for r in results:
        for c in r.curves:
            st = styles.get(c.type, dict(color="C4", ls="-"))
            ax.plot(c.param, c.param2, lw=1.6, zorder=3, **st)
            ax.plot([c.param[c.start]], [c.param2[c.start]], ls="", marker=MARKERS[c.type][0], mfc="w", mec="k",
                    zorder=4)
            drawn.add(c.type)
    for t in ("fold", "period_doubling", "grazing"):
        if t in drawn:
            handles.append(Line2D([], [], lw=1.6, label=f"{MARKERS[t][1]} curve", **styles[t]))
    if grid is not None:
        ax.set_xlim(*extent(grid["x"], grid["y"])[:2])
        ax.set_ylim(*extent(grid["x"], grid["y"])[2:])
    else:
        ax.set_xlim(min(min(r.range) for r in results), max(max(r.range) for r in results))
        if first.range2:
            ax.set_ylim(*sorted(first.range2))
    label_axis(ax, "x", first, first.param)
    label_axis(ax, "y", first, first.param2)
    ax.set_title(f"bifurcation curves in ({first.param}, {first.param2})"
                 + (" over the brute-force periodicity map" if grid is not None else ""), fontsize=10)
    legend_outside(ax, handles)
