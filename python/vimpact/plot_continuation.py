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


def continuation(result, path=None):
    """The branches and their bifurcations (and, with curves, the two-parameter plane).

    Parameters
    ----------
    result : Continuation
        Uses ``branches``, ``bifurcations``, ``param``, ``plot_variable``, and when present
        ``diagram`` (drawn underneath in grey), ``curves`` and ``map``.
    path : str, optional
        Write the picture there.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.lines import Line2D

    two = bool(result.curves) or result.map is not None
    rows = 3 if two else 2
    fig, axes = new_figure(path, None, figsize=(10, 4.2 * rows - 1.5 * (rows - 1)), nrows=rows, ncols=1,
                           gridspec_kw={"height_ratios": [3, 1.3] + ([3] if two else [])})
    ax, axm = axes[0], axes[1]
    k = result.plot_index
    name = state_name(result, k)
    handles = []
    if result.diagram is not None and len(result.diagram["value"]):
        ax.plot(result.diagram["value"], result.diagram["points"][:, k], ".", ms=2.5, color="0.55", zorder=1)
        handles.append(Line2D([], [], ls="", marker=".", color="0.6", label="brute-force diagram"))
    for b in result.branches:
        colour = f"C{b.returns - 1 if b.returns <= 10 else b.index % 10}"
        for a, e, stable in _runs([bool(v) for v in b.stable]):
            s = slice(a, e + 1)
            for j in range(b.returns):
                ax.plot(b.param[s], b.sections[s, j, k], ls="-" if stable else "--", color=colour, lw=1.4, zorder=3)
        # Multipliers jump at a grazing (they grow like 1 / v as an impact's velocity v goes to
        # 0): no line across a change of the impacts per period.
        mu = _largest_nontrivial(b.multipliers)
        for a, e, (stable, _) in _runs(list(zip([bool(v) for v in b.stable], b.impacts.tolist()))):
            e = e if e == len(b.param) - 1 or b.impacts[e] == b.impacts[a] else e - 1
            s = slice(a, e + 1)
            axm.plot(b.param[s], mu[s], ls="-" if stable else "--", color=colour, lw=1.2)
    for r in sorted({b.returns for b in result.branches}):
        handles.append(Line2D([], [], color=f"C{r - 1 if r <= 10 else 0}", lw=1.4, label=f"P{r} orbits"))
    handles += [Line2D([], [], color="k", lw=1.2, ls="-", label="stable"),
                Line2D([], [], color="k", lw=1.2, ls="--", label="unstable")]
    seen = set()
    for bf in result.bifurcations:
        marker, text = MARKERS.get(bf.type, ("o", bf.type))
        ys = bf.sections[:, k] if bf.sections is not None and len(bf.sections) else [bf.state[k]]
        ax.plot([bf.param] * len(ys), ys, ls="", marker=marker, ms=7, mfc="w", mec="k", mew=1.3, zorder=5)
        mu = np.abs(bf.multipliers[1:]) if len(bf.multipliers) > 1 else [np.nan]
        axm.plot([bf.param], [np.nanmax(mu)], ls="", marker=marker, ms=6, mfc="w", mec="k", mew=1.2, zorder=5)
        if bf.type not in seen:
            seen.add(bf.type)
            handles.append(Line2D([], [], ls="", marker=marker, mfc="w", mec="k", label=text))
    axm.axhline(1.0, color="k", lw=0.8, ls=":")
    label_axis(ax, "y", result, name, after=f" at the section ({section_name(result)})")
    label_axis(axm, "x", result, result.param)
    axm.set_ylabel("largest |multiplier|\n(trivial excluded)")
    axm.set_yscale("log")
    ax.set_xlim(*sorted(result.range))
    axm.set_xlim(*sorted(result.range))
    legend_outside(ax, handles)
    ax.set_title(f"continuation in {result.param}: {len(result.branches)} branch(es), "
                 f"{len(result.bifurcations)} bifurcation(s)", fontsize=10)
    if two:
        _plane(axes[2], result)
    suptitle(fig, title(result, (result.param, result.param2) if result.param2 else (result.param,)))
    return finish_figure(fig, path, dpi=120)


def _plane(ax, result):
    """The curves in (param, param2) over the brute-force map."""
    from matplotlib.colors import ListedColormap
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles = []
    if result.map is not None:
        xs, ys, cells = result.map["x"], result.map["y"], np.asarray(result.map["label"])
        order, colours = label_colours(cells.ravel().tolist())
        index = {lab: i for i, lab in enumerate(order)}
        img = np.vectorize(index.get, otypes=[int])(cells)
        ax.imshow(img, origin="lower", aspect="auto", extent=extent(xs, ys),
                  cmap=ListedColormap([colours[lab] for lab in order]), vmin=-0.5, vmax=len(order) - 0.5,
                  interpolation="nearest", zorder=0)
        handles += [Patch(facecolor=colours[lab], edgecolor="k", lw=0.3, label=lab) for lab in order]
    styles = {"fold": dict(color="C3", ls="-"), "period_doubling": dict(color="w", ls="-"),
              "grazing": dict(color="k", ls="--")}
    from matplotlib import patheffects
    edge = [patheffects.withStroke(linewidth=3.2, foreground="k")]
    for t in ("fold", "period_doubling", "grazing"):
        cs = [c for c in result.curves if c.type == t]
        if not cs:
            continue
        st = styles[t]
        for c in cs:
            ax.plot(c.param, c.param2, lw=1.6, zorder=3, path_effects=edge if st["color"] == "w" else None, **st)
            ax.plot([c.param[c.start]], [c.param2[c.start]], ls="", marker=MARKERS[t][0], mfc="w", mec="k", zorder=4)
        handles.append(Line2D([], [], lw=1.6, path_effects=edge if st["color"] == "w" else None,
                              label=f"{MARKERS[t][1]} curve", **st))
    ax.set_xlim(*sorted(result.range))
    if result.range2:
        ax.set_ylim(*sorted(result.range2))
    label_axis(ax, "x", result, result.param)
    label_axis(ax, "y", result, result.param2)
    ax.set_title(f"bifurcation curves in ({result.param}, {result.param2})"
                 + (" over the brute-force periodicity map" if result.map is not None else ""), fontsize=10)
    legend_outside(ax, handles)
