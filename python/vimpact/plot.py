"""Plots of vimpact results (matplotlib), for Python users and the command line alike.

Every function takes a result and returns the matplotlib Figure; given ``path`` it also
writes the picture there. A result is what the analyses return (``vimpact.sweep(...)``), what
``vimpact.Sweep.load(DIR)`` reads from the command line's output, or any object with the same
attribute names::

    s = vimpact.sweep(vimpact.WakeImpact(), "Ur", vimpact.grid(12, 25, 131))
    vimpact.plot.bifurcation(s, "sweep.png")

``phase`` (a Simulation: time series and phase portrait), ``sections`` (section points of a
Period or Simulation), ``bifurcation`` (Sweep), ``map`` (Map), ``basins`` (Basins),
``response`` (Response), ``timeseries_overlay`` (several Simulations).

Command line: ``vimpact COMMAND ... --out DIR`` runs ``python3 -m vimpact.plot KIND DIR``,
which loads DIR into the result object of KIND and draws DIR/plot.png with the same function.
"""
import os
import sys

import numpy as np

from .plot_sweeps import (basins, bifurcation, finish_figure, new_figure, periodicity_map,  # noqa: F401
                          response, section_name, timeseries_overlay, title)
from .results import Basins, Map, Period, Response, Simulation, Sweep, read_csv  # noqa: F401

map = periodicity_map  # vimpact.plot.map(result): the periodicity map


def _simulation(result):
    return result.simulation if hasattr(result, "simulation") else result


def phase(result, path=None, window=200.0):
    """Time series of y with impacts and section points, and the (y, ydot) phase portrait.

    Parameters
    ----------
    result : Simulation (or Period: its simulation)
        Uses ``series_t``, ``series`` (from ``sample_dt > 0``; without them only the section
        points and impacts are drawn), ``section_t``, ``section``, ``impact_t``,
        ``impact_pre``, ``outcome``, ``parameters``.
    path : str, optional
        Write the picture there (PNG at 120 dpi).
    window : float, default 200
        The time series shows the last ``window`` time units, so single oscillations and
        impacts stay visible; the phase portrait shows the whole recorded window.

    Returns
    -------
    matplotlib.figure.Figure
    """
    r = _simulation(result)
    sigma = (r.parameters or {}).get("sigma")
    fig, (ax1, ax2) = new_figure(path, None, figsize=(12, 4.5), nrows=1, ncols=2,
                                 gridspec_kw={"width_ratios": [1.6, 1]})
    ts_t, ts = np.asarray(r.series_t), np.asarray(r.series)
    sec_t, sec = np.asarray(r.section_t), np.asarray(r.section)
    imp_t, imp = np.asarray(r.impact_t), np.asarray(r.impact_pre)
    ends = [a[-1] for a in (ts_t, sec_t, imp_t) if len(a)]
    t_end = max(ends) if ends else 0.0
    keep = ts_t >= t_end - window
    ax1.plot(ts_t[keep], ts[keep, 0] if len(ts) else [], lw=0.8, color="C0", label="y")
    if sigma is not None:
        ax1.axhline(sigma, color="k", lw=1.0, ls="--", label=f"barrier sigma = {sigma:g}")
    ki = imp_t >= t_end - window
    if ki.any():
        ax1.plot(imp_t[ki], imp[ki, 0], "rv", ms=3, label="impacts")
    ks = sec_t >= t_end - window
    if ks.any():
        ax1.plot(sec_t[ks], sec[ks, 0], "g^", ms=4, label="section points")
    ax1.set_xlabel("t")
    ax1.set_ylabel("y")
    ax1.legend(loc="upper right", fontsize=8)
    ax1.set_title(f"time series, last {window:g} time units (outcome {r.outcome})", fontsize=10)

    if len(ts):
        ax2.plot(ts[:, 0], ts[:, 1], lw=0.6, color="C0")
    if sigma is not None:
        ax2.axvline(sigma, color="k", lw=1.0, ls="--")
    if len(sec):
        ax2.plot(sec[:, 0], sec[:, 1], "g^", ms=4)
    ax2.set_xlabel("y")
    ax2.set_ylabel("dy/dt")
    ax2.set_title("phase portrait", fontsize=10)
    fig.suptitle(title(r), fontsize=10)
    return finish_figure(fig, path, dpi=120)


def sections(result, path=None, ax=None):
    """The recorded section points in the (y, x) plane, titled with the period label.

    Parameters
    ----------
    result : Period or Simulation
        Uses ``section`` (and ``label`` for a Period).
    path, ax : see ``vimpact.plot.bifurcation``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    own = ax is None
    r = _simulation(result)
    fig, ax = new_figure(path, ax, figsize=(6, 4.5))
    sec = np.asarray(r.section)
    names = getattr(r, "state_names", ("y", "ydot", "x", "xdot"))
    if len(sec):
        ax.plot(sec[:, 0], sec[:, 2], "o", ms=3)
    ax.set_xlabel(f"{names[0]} at section ({section_name(r)})")
    ax.set_ylabel(f"{names[2]} at section")
    label = getattr(result, "label", None)
    ax.set_title(f"{label + ': ' if label else ''}{len(sec)} section points", fontsize=10)
    if own:
        fig.suptitle(title(r), fontsize=9)
    return finish_figure(fig, path, dpi=120, own=own)


# ---------------------------------------------------------------- the command line's PNGs

def _draw(loader, drawer):
    def from_directory(directory):
        return drawer(loader(directory), os.path.join(directory, "plot.png"))
    from_directory.__doc__ = f"{drawer.__name__}({loader.__qualname__}(DIR)) into DIR/plot.png"
    return from_directory


def _kinds():
    """Plot kind (the first argument of ``python3 -m vimpact.plot``) -> function(directory).

    Kinds of other analyses live in their own modules (plot_<topic>.py) and are listed here."""
    from . import plot_dimension, plot_stability

    return {
        "simulate": _draw(Simulation.load, phase),
        "period": _draw(Period.load, sections),
        "sweep": _draw(Sweep.load, bifurcation),
        "map": _draw(Map.load, periodicity_map),
        "basins": _draw(Basins.load, basins),
        "response": _draw(Response.load, response),
        "dimension": plot_dimension.dimension,
        "floquet": plot_stability.floquet,
        "lyapunov": plot_stability.lyapunov,
        "floquet_sweep": plot_stability.floquet_sweep,
        "lyapunov_sweep": plot_stability.lyapunov_sweep,
    }


def main(argv):
    import matplotlib
    matplotlib.use("Agg")
    kinds = _kinds()
    if len(argv) != 3 or argv[1] not in kinds:
        print(f"usage: python3 -m vimpact.plot {'|'.join(sorted(kinds))} DIR", file=sys.stderr)
        return 2
    kinds[argv[1]](argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
