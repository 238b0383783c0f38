"""What the pictures of output directories draw: each directory is redrawn as the command line
draws it (python3 -m vimpact.plot KIND DIR, KIND from its run.json), and for every axes of the
figure the number of finite data values in its lines, point and mesh collections, images and
bars is printed as JSON: {DIR: [{"label", "title", "values"}, ...]}. A picture whose data is
missing, empty or not finite draws axes with no values.

Usage: PYTHONPATH=python /usr/bin/python3 tests/cli/picture_census.py DIR..."""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402


def finite(values):
    a = np.ma.masked_invalid(np.ma.asarray(values, dtype=float))
    return int(a.count())


def values_drawn(ax):
    n = 0
    for line in ax.lines:
        xy = np.asarray(line.get_xydata(), dtype=float).reshape(-1, 2)
        n += int(np.isfinite(xy).all(axis=1).sum())
    for c in ax.collections:
        array = c.get_array()
        if array is not None and np.size(array) > 0:
            n += finite(array)
        else:
            offsets = np.asarray(c.get_offsets(), dtype=float).reshape(-1, 2)
            n += int(np.isfinite(offsets).all(axis=1).sum()) if len(offsets) > 1 else len(c.get_paths())
    for image in ax.images:
        n += finite(image.get_array())
    n += sum(1 for p in ax.patches if getattr(p, "get_height", lambda: 0)() not in (0, None))
    return n


def census(directories):
    drawn = []
    save = Figure.savefig

    def counting(fig, *args, **kwargs):
        drawn.append([{"label": ax.get_label(), "title": ax.get_title(), "values": values_drawn(ax)}
                      for ax in fig.axes])
        return save(fig, *args, **kwargs)

    Figure.savefig = counting
    from vimpact.plot import _kinds
    kinds = _kinds()
    out = {}
    for d in directories:
        with open(os.path.join(d, "run.json"), encoding="utf-8") as f:
            kind = json.load(f)["plot"]
        kinds[kind](d, "png")
        out[d] = drawn.pop()
    return out


if __name__ == "__main__":
    print(json.dumps(census(sys.argv[1:])))
