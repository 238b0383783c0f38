"""What every vimpact picture shares: figures in or out of pyplot, titles from a result's
model and parameters, axis labels with the model's units, legends outside the data, label
colours, and the lines of surfaces. Imports results, never the reverse."""
import os
import re
import textwrap

import numpy as np

from .results import label_order


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


def save_in(fig, directory, out_name, dpi=120):
    """Lays out `fig`, writes it to directory/out_name, closes it if pyplot owns it; returns
    the path."""
    fig.tight_layout()
    path = os.path.join(directory, out_name)
    fig.savefig(path, dpi=dpi)
    import matplotlib.pyplot as plt
    plt.close(fig)  # a figure outside pyplot is simply not found
    return path


def title(result, varied=()):
    """The model and its parameters (without those that vary over the picture); ``suptitle``
    wraps it."""
    p = dict(getattr(result, "parameters", {}) or {})
    preset = getattr(result, "preset", None)
    name = getattr(result, "model_name", None)
    text = ", ".join(f"{k} = {v:g}" for k, v in p.items() if k not in varied and isinstance(v, (int, float)))
    head = f"{name}: " if name else ""
    return head + text + (f"  ({preset} preset)" if preset else "")


def suptitle(fig, text, fontsize=9):
    """The figure's title, wrapped to the figure's width (a character of the text is about
    0.55 of its size wide), so that a narrow figure does not cut it."""
    per_line = max(20, int(0.9 * fig.get_figwidth() * 72 / (0.55 * fontsize)))
    return fig.suptitle(plain_text("\n".join(textwrap.wrap(text, per_line))), fontsize=fontsize)


def section_name(result):
    section = (getattr(result, "options", None) or {}).get("section")
    if not section:
        return "section"
    if section == "impacts":
        return "after impacts"
    if section.startswith("impacts:"):
        return f"after impacts on {section[8:]}"
    return section


def plot_index(result):
    names = tuple(getattr(result, "state_names", ()) or ())
    var = getattr(result, "plot_variable", None)
    return names.index(var) if var in names else 0


def state_name(result, i):
    names = tuple(getattr(result, "state_names", ()) or ())
    return names[i] if i < len(names) else f"x{i}"


# Periods in tab20's saturated colours, then their light partners (tab20's own order would put
# P1 and P2 in two blues); its reds and greys are left to the failures and P0.
_PERIOD_COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#bcbd22", "#17becf",
                   "#aec7e8", "#ffbb78", "#98df8a", "#c5b0d5", "#c49c94", "#f7b6d2", "#dbdb8d", "#9edae5")
_FAILURE_COLOURS = ("#d62728", "#7f0000", "#ff9896", "#ff00ff")


def plain_text(text):
    """Text matplotlib draws as it is: a '$' in a model's meaning would start mathtext."""
    return str(text).replace("$", r"\$")


def describe(result, name):
    """(meaning, unit) of a state variable or parameter of the result's model (``state_info``,
    ``parameter_info``); a phase's coordinate NAME_cos or NAME_sin is described as NAME.
    ("", "") when the result does not describe it."""
    state = {e["name"]: e for e in (getattr(result, "state_info", None) or ())}
    params = getattr(result, "parameter_info", None) or {}
    for key in (name, re.sub(r"_(cos|sin)$", "", name)):
        e = state.get(key) or params.get(key)
        if e:
            return e.get("meaning") or "", e.get("unit") or ""
    return "", ""


def quantity_text(result, name, before="", after="", room=None, unit=None):
    """``{before}{name}{after} [unit]``, e.g. "y at the section (maxima) [D]"; without
    ``before`` and ``after``, the meaning too ("Ur, reduced velocity U/(f_n D)") when the whole
    fits in ``room`` characters (a meaning's parenthesised remark dropped first). A quantity
    without a unit is dimensionless: no brackets. ``unit`` replaces the model's (SI units)."""
    meaning, model_unit = describe(result, name)
    unit = model_unit if unit is None else unit
    tail = f" [{unit}]" if unit else ""
    text = f"{before}{name}{after}{tail}"
    short = meaning.split(" (")[0].strip()
    if short and not before and not after:
        full = f"{name}, {short}{tail}"
        if room is None or len(full) <= room:
            text = full
    return plain_text(text)


def label_axis(ax, axis, result, name, before="", after="", unit=None):
    """Sets the x or y label of ``ax`` to ``quantity_text``, the meaning included when the
    label fits along the axis as laid out now (about 9 characters of 10-point text per inch,
    with room for the layout to shrink the axes)."""
    fig = ax.figure
    pos = ax.get_position()
    inches = pos.width * fig.get_figwidth() if axis == "x" else pos.height * fig.get_figheight()
    text = quantity_text(result, name, before, after, room=int(inches * 9), unit=unit)
    (ax.set_xlabel if axis == "x" else ax.set_ylabel)(text)
    return text


def coincident_limits(ax, xs, ys):
    """Widens an axis whose values coincide to within a millionth of their size (the section
    points of a periodic orbit, apart in the last digits): drawn as they are, matplotlib
    magnifies the rounding errors into a cloud under an offset text that covers the labels.
    They then show as one point, in a window a thousandth of their size wide, with few ticks
    (their labels are long)."""
    for axis, values, set_limits in (("x", xs, ax.set_xlim), ("y", ys, ax.set_ylim)):
        v = np.asarray(values, dtype=float)
        v = v[np.isfinite(v)]
        if not len(v):
            continue
        size = max(float(np.abs(v).max()), 1.0)
        if np.ptp(v) < 1e-6 * size:
            centre = 0.5 * (v.min() + v.max())
            set_limits(centre - 1e-3 * size, centre + 1e-3 * size)
            ax.locator_params(axis=axis, nbins=4)


def twins(ax):
    """The axes drawn over ``ax`` (twinx): the same box."""
    return [o for o in ax.figure.axes if o is not ax and o.bbox.bounds == ax.bbox.bounds]


def legend_entries(ax):
    """The handles with a label of ``ax`` and of its twins."""
    return [h for a in [ax] + twins(ax) for h in a.get_legend_handles_labels()[0]]


def legend_outside(ax, handles=None, **kw):
    """A legend right of the axes, past the ticks and label of any twin axis, so that it covers
    no data however the data fall; the layout (tight_layout) makes room for it. Without
    ``handles``, the ``legend_entries`` of ``ax``. Returns the legend (None: no entries)."""
    from matplotlib.transforms import ScaledTranslation
    handles = legend_entries(ax) if handles is None else list(handles)
    if not handles:
        return None
    fig = ax.figure
    right = max([o.get_tightbbox().x1 - ax.bbox.x1 for o in twins(ax)] + [0.0])
    shift = ScaledTranslation(right / fig.dpi + 0.08, 0.0, fig.dpi_scale_trans)
    opts = dict(loc="upper left", bbox_to_anchor=(1.0, 1.0), bbox_transform=ax.transAxes + shift, borderaxespad=0.0,
                fontsize=8)
    opts.update(kw)
    return ax.legend(handles=handles, labels=[h.get_label() for h in handles], **opts)


def neutral_lines():
    """Line styles (plot keywords) for lines drawn over label colours, one per surface: black
    with a white edge, a dash pattern each, seen on every label's colour and not read as one."""
    from matplotlib import patheffects
    edge = [patheffects.withStroke(linewidth=3.5, foreground="w")]
    return [dict(color="k", lw=1.5, ls=ls, path_effects=edge) for ls in ("-", "--", ":", "-.")]


def label_colours(labels):
    """A colour per label, distinct for up to 16 periods and 4 kinds of failure: P0 light
    grey, PN from a qualitative map, aperiodic black, inadmissible white, failed runs'
    outcomes in reds and magenta."""
    order = label_order(labels)
    colours, k, f = {}, 0, 0
    for lab in order:
        if lab == "P0":
            colours[lab] = (0.85, 0.85, 0.85)
        elif lab == "aperiodic":
            colours[lab] = (0.0, 0.0, 0.0)
        elif lab == "inadmissible":
            colours[lab] = (1.0, 1.0, 1.0)
        elif re.fullmatch(r"P\d+", lab):
            colours[lab] = _PERIOD_COLOURS[k % len(_PERIOD_COLOURS)]
            k += 1
        else:
            colours[lab] = _FAILURE_COLOURS[f % len(_FAILURE_COLOURS)]
            f += 1
    return order, colours


def extent(xs, ys):
    dx = (xs[-1] - xs[0]) / (len(xs) - 1) if len(xs) > 1 else 1.0
    dy = (ys[-1] - ys[0]) / (len(ys) - 1) if len(ys) > 1 else 1.0
    return [xs[0] - dx / 2, xs[-1] + dx / 2, ys[0] - dy / 2, ys[-1] + dy / 2]


def surface_levels(result, column):
    """Surfaces that sit at one value of a state variable, as seen from the impacts: name ->
    the value of that variable at every impact on it (a barrier y = sigma), when the impacts on
    it all share it."""
    pre = np.asarray(getattr(result, "impact_pre", None) if getattr(result, "impact_pre", None) is not None
                     else np.empty((0, 0)))
    which = np.asarray(getattr(result, "impact_surface", None) if getattr(result, "impact_surface", None) is not None
                       else np.zeros(len(pre), dtype=int))
    names = tuple(getattr(result, "surfaces", ()) or ())
    levels = {}
    if pre.ndim != 2 or not len(pre) or column >= pre.shape[1]:
        return levels
    for i in sorted(set(which.tolist())):
        v = pre[which == i, column]
        if len(v) and np.all(np.isfinite(v)) and np.ptp(v) <= 1e-9 * (1.0 + abs(v[0])):
            levels[names[i] if 0 <= i < len(names) else f"surface {i}"] = float(v[0])
    return levels


def si_scales(result, units):
    """(time factor, per state variable (factor, unit or None)) of the picture: all 1 and the
    model's units, or with ``units="si"`` the SI value of one model unit of time and of each
    variable that has one (``result.si``: its columns' units, whose scales are its values)."""
    names = tuple(result.state_names)
    if units not in ("model", "si"):
        raise ValueError(f"units must be 'model' or 'si' (got {units!r})")
    si = getattr(result, "si", None)
    if units == "model":
        return 1.0, [(1.0, None)] * len(names)
    if not si:
        raise ValueError("units='si' needs a run with its SI scales (the directory of a run with --si and --out "
                         "DIR, loaded by the result's load)")
    values, columns = si.get("values", {}), si.get("columns", {}).get("states", {})
    scale = {"s": values.get("time_scale"), "m": values.get("length_scale"), "m/s": values.get("velocity_scale")}
    per = []
    for n in names:
        u = columns.get(n + "_si")
        per.append((scale[u], u) if u in scale and scale[u] is not None else (1.0, None))
    return scale["s"] or 1.0, per
