"""What every vimpact picture shares: figures in or out of pyplot, titles from a result's
model and parameters, label colours, and the lines of surfaces. Imports results, never the
reverse."""
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
    """The model and its parameters (without those that vary over the picture), wrapped."""
    p = dict(getattr(result, "parameters", {}) or {})
    preset = getattr(result, "preset", None)
    name = getattr(result, "model_name", None)
    text = ", ".join(f"{k} = {v:g}" for k, v in p.items() if k not in varied and isinstance(v, (int, float)))
    head = f"{name}: " if name else ""
    return "\n".join(textwrap.wrap(head + text + (f"  ({preset} preset)" if preset else ""), 120))


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
