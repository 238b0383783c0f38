"""The design chart of a clearance computation: gap against flow speed (or the flow
parameter), each chart cell coloured by its regime (no impact P0, periodic PN, aperiodic),
the clearance line (the smallest gap without impact, from the grazing analysis), and
iso-lines of the impact rate and of the dissipated power. In SI when the run had physical
units."""
import numpy as np

from .plot_common import (finish_figure, label_colours, legend_outside, neutral_lines, new_figure, plain_text,
                          suptitle, title)


def _levels(z, n=3):
    """Up to n round contour levels at the quartiles of the positive finite values of z, so
    that the lines spread over the chart whatever the values' distribution."""
    v = z[np.isfinite(z) & (z > 0)]
    if len(v) < 4 or v.max() <= v.min():
        return []
    raw = np.quantile(v, np.linspace(0, 1, n + 2)[1:-1])
    return sorted({float(f"{x:.2g}") for x in raw if v.min() < x < v.max()})


def design_chart(result, path=None, ax=None):
    """Gap against flow speed, coloured by regime, with the clearance line and iso-lines of
    impact rate and dissipated power (the command ``clearance``'s picture).

    Parameters
    ----------
    result : Clearance
        Uses ``x_values``, ``gap`` / ``gap_si``, ``label``, ``clearance`` / ``clearance_si``,
        ``statistics`` / ``statistics_si`` (``impact_rate``, ``power``), ``x``.
    path : str, optional
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.lines import Line2D
    own = ax is None
    fig, ax = new_figure(path, ax, figsize=(10.5, 5.5))
    si = getattr(result, "gap_si", None) is not None
    xs = np.asarray(result.x_values, dtype=float)
    gap = np.asarray(result.gap_si if si else result.gap, dtype=float)
    labels = np.asarray(result.label).astype(str)
    stats = (result.statistics_si if si else result.statistics) or {}
    X = np.repeat(xs[:, None], gap.shape[1] if gap.ndim == 2 else 0, axis=1)
    present = [lab for lab in labels.ravel() if lab]
    order, colours = label_colours(present)
    handles = []
    for lab in order:
        sel = labels == lab
        regime = {"P0": "P0, no impact", "aperiodic": "aperiodic"}.get(lab, f"{lab}, periodic" if lab[1:].isdigit()
                                                                         else lab)
        ax.scatter(X[sel], gap[sel], s=60, marker="s", color=colours[lab], edgecolors="0.3", linewidths=0.4)
        handles.append(Line2D([], [], marker="s", ls="none", ms=8, color=colours[lab], mec="0.3", mew=0.4,
                              label=regime))
    clear = np.asarray(result.clearance_si if si else result.clearance, dtype=float)
    line = neutral_lines()[0]
    ax.plot(xs, clear, **line, marker="o", ms=3)
    handles.append(Line2D([], [], **line, label="clearance: smallest gap without impact (grazing)"))
    # Iso-lines on the chart's structured grid (one column of gaps per flow value).
    ok = gap.ndim == 2 and gap.shape[0] > 1 and gap.shape[1] > 1 and np.isfinite(gap).all()
    for key, colour, ls, name in (("impact_rate", "C0", "-", "impact rate"), ("power", "C3", "--", "dissipated power")):
        z = np.asarray(stats.get(key, np.empty((0, 0))), dtype=float)
        if not ok or z.shape != gap.shape:
            continue
        levels = _levels(z)
        if not levels:
            continue
        cs = ax.contour(X, gap, np.ma.masked_invalid(z), levels=levels, colors=colour, linestyles=ls, linewidths=1.0)
        ax.clabel(cs, fontsize=7, fmt="%.2g")
        unit = (" [Hz]" if key == "impact_rate" else " [W/m]") if si else ""
        handles.append(Line2D([], [], color=colour, ls=ls, label=f"{name}{unit}"))
    if si:
        ax.set_xlabel(plain_text("U, flow speed [m/s]") if result.x == "U" else plain_text(result.x))
        ax.set_ylabel(plain_text(f"gap to the {result.surface or 'surface'} [m]"))
    else:
        ax.set_xlabel(plain_text(result.x))
        ax.set_ylabel(plain_text(f"gap to the {result.surface or 'surface'} (model units)"))
    ax.set_ylim(bottom=0)
    if len(xs):
        pad = 0.04 * (np.nanmax(xs) - np.nanmin(xs)) or 0.04 * max(abs(np.nanmax(xs)), 1.0)
        ax.set_xlim(np.nanmin(xs) - pad, np.nanmax(xs) + pad)
    legend_outside(ax, handles)
    ax.set_title("design chart: regime over gap and flow" + (" (SI)" if si else ""), fontsize=10)
    if own:
        suptitle(fig, title(result, varied=(result.param, result.gap_param)))
    return finish_figure(fig, path, dpi=120, own=own)
