"""Plots of vimpact results (matplotlib), for Python users and the command line alike, for
any model.

Every function takes a result and returns the matplotlib Figure; given ``path`` it also
writes the picture there. A result is what the analyses return (``vimpact.sweep(...)``), what
``vimpact.Sweep.load(DIR)`` reads from the command line's output, or any object with the same
attribute names::

    s = vimpact.sweep(vimpact.Model("wake_impact"), "Ur", vimpact.grid(12, 25, 131))
    vimpact.plot.bifurcation(s, "sweep.png")

``phase`` (a Simulation: time series and phase portrait), ``sections`` (section points of a
Period or Simulation), ``bifurcation`` (Sweep), ``map`` (Map), ``basins`` (Basins),
``response`` (Response), ``timeseries_overlay`` (several Simulations), ``floquet``,
``lyapunov``, ``floquet_sweep``, ``lyapunov_sweep``, ``continuation`` (Continuation: branches,
bifurcations and two-parameter curves; several together), ``curves`` (the two-parameter plane
over a Map), ``design_chart`` (Clearance). The state variable drawn is the result's
``plot_variable`` (the model's first state variable).

Command line: ``vimpact COMMAND ... --out DIR`` runs ``python3 -m vimpact.plot KIND DIR``,
which loads DIR into the result object of KIND and draws DIR/plot.png (or plot.pdf, plot.svg:
a third argument) with the same function, given the options run.json's ``plot_options``
holds (``color_by`` of ``sweep --color-by``).

Axes name their quantity with the model's symbol, its unit in brackets where the model gives
one, and its meaning where that fits (``Ur, reduced velocity U/(f_n D)``, ``y at the section
(maxima) [D]``); legends stand outside the axes.
"""
import os
import sys

import numpy as np

from .plot_common import (coincident_limits, finish_figure, label_axis, legend_outside, new_figure, plot_index,
                          section_name, si_scales, state_name, suptitle, surface_levels, title)
from .plot_continuation import continuation, curves  # noqa: F401
from .plot_clearance import design_chart  # noqa: F401
from .plot_stability import floquet, floquet_sweep, lyapunov, lyapunov_sweep  # noqa: F401
from .plot_sweeps import basins, bifurcation, periodicity_map, response, timeseries_overlay  # noqa: F401
from .results import (Basins, Clearance, Floquet, FloquetSweep, Lyapunov, LyapunovSweep, Map, Period, Response,  # noqa: F401
                      Simulation, Sweep, read_csv, read_record)
from .results_continuation import Continuation  # noqa: F401

map = periodicity_map  # vimpact.plot.map(result): the periodicity map


def _simulation(result):
    return result.simulation if hasattr(result, "simulation") else result


def phase(result, path=None, window=200.0, units="model"):
    """Time series of the plot variable with impacts and section points, a phase portrait, and
    the histogram of the recorded impacts' normal velocities with the run's impact statistics.

    The portrait shows the plot variable against the next state variable (its velocity in
    the usual order: y and ydot for the paper's model). A surface whose impacts all lie at one
    value of the plot variable (a barrier y = sigma) is drawn as a dashed line.

    Parameters
    ----------
    result : Simulation (or Period: its simulation)
        Uses ``series_t``, ``series`` (from ``sample_dt > 0``; without them only the section
        points and impacts are drawn), ``section_t``, ``section``, ``impact_t``,
        ``impact_pre``, ``impact_surface``, ``outcome``, ``state_names``, ``plot_variable``,
        and for the histogram ``impact_velocity`` and ``statistics`` (where present).
    path : str, optional
        Write the picture there (PNG at 120 dpi).
    window : float, default 200
        The time series shows the last ``window`` time units (of the model), so single
        oscillations and impacts stay visible; the phase portrait shows the whole recorded
        window.
    units : "model" (default) or "si"
        ``"si"`` (the command line's picture of a run with ``--si``): time in seconds, the
        displacements and velocities in m and m/s, the histogram and its statistics in SI, by
        the scales of ``result.si``; the other variables stay in the model's units.

    Returns
    -------
    matplotlib.figure.Figure
    """
    r = _simulation(result)
    k = plot_index(r)
    dim = len(r.state_names)
    j = k + 1 if k + 1 < dim else (0 if k else min(1, dim - 1))
    ft, per = si_scales(r, units)
    (fk, uk), (fj, uj) = per[k], per[j]
    fig, (ax1, ax2, ax3) = new_figure(path, None, figsize=(16, 4.5), nrows=1, ncols=3,
                                      gridspec_kw={"width_ratios": [1.6, 1, 0.9]})
    ts_t, ts = np.asarray(r.series_t), np.asarray(r.series)
    sec_t, sec = np.asarray(r.section_t), np.asarray(r.section)
    imp_t, imp = np.asarray(r.impact_t), np.asarray(r.impact_pre)
    ends = [a[-1] for a in (ts_t, sec_t, imp_t) if len(a)]
    t_end = max(ends) if ends else 0.0
    keep = ts_t >= t_end - window
    name = state_name(r, k)
    ax1.plot(ts_t[keep] * ft, ts[keep, k] * fk if len(ts) else [], lw=0.8, color="C0", label=name)
    levels = {n: level * fk for n, level in surface_levels(r, k).items()}
    for n, level in levels.items():
        ax1.axhline(level, color="k", lw=1.0, ls="--", label=f"{n}: {name} = {level:g}")
    ki = imp_t >= t_end - window
    if ki.any():
        ax1.plot(imp_t[ki] * ft, imp[ki, k] * fk, "rv", ms=3, label="impacts")
    ks = sec_t >= t_end - window
    if ks.any():
        ax1.plot(sec_t[ks] * ft, sec[ks, k] * fk, "g^", ms=4, label="section points")
    ax1.set_xlabel("t [s]" if ft != 1.0 else "t")
    label_axis(ax1, "y", r, name, unit=uk)
    legend_outside(ax1)
    shown = f"{window * ft:.3g} s" if ft != 1.0 else f"{window:g} time units"
    ax1.set_title(f"time series, last {shown} (outcome {r.outcome})", fontsize=10)

    if len(ts):
        ax2.plot(ts[:, k] * fk, ts[:, j] * fj, lw=0.6, color="C0")
    for level in levels.values():
        ax2.axvline(level, color="k", lw=1.0, ls="--")
    if len(sec):
        ax2.plot(sec[:, k] * fk, sec[:, j] * fj, "g^", ms=4)
    if len(imp):
        ax2.plot(imp[:, k] * fk, imp[:, j] * fj, "rv", ms=3)
    label_axis(ax2, "x", r, name, unit=uk)
    label_axis(ax2, "y", r, state_name(r, j), unit=uj)
    ax2.set_title("phase portrait", fontsize=10)
    impact_histogram(ax3, r, units)
    suptitle(fig, title(r))
    return finish_figure(fig, path, dpi=120)


def impact_histogram(ax, result, units="model"):
    """The histogram of a run's impact velocities (the normal velocity -dg/dt before each
    reset, ``impact_velocity``), titled with its impact statistics: rate, mean and largest
    velocity, energy per impact, dissipated power (model units, docs/model.md; SI with
    ``units="si"`` and ``result.si``: m/s, Hz, J, W, per metre of a cylinder)."""
    v = np.asarray(getattr(result, "impact_velocity", None) if getattr(result, "impact_velocity", None) is not None
                   else [], dtype=float)
    v = v[np.isfinite(v)]
    st = getattr(result, "statistics", None) or {}
    si = getattr(result, "si", None) if units == "si" else None
    if si:
        v = v * si["values"]["velocity_scale"]
        st = si.get("impact_statistics_si") or {}
        energy = si.get("columns", {}).get("impacts", {}).get("energy_si", "J")
        u = {"v": " m/s", "rate": " Hz", "e": " " + energy, "p": " " + energy.replace("J", "W"), "per": "",
             "velocity": "impact velocity -dg/dt [m/s]"}
    else:
        u = {"v": "", "rate": "", "e": "", "p": "", "per": " per unit t",
             "velocity": "impact velocity -dg/dt before the reset"}
    if len(v) and v.max() > 0:
        # From zero, so that the bars say how hard next to how often (and velocities equal to
        # rounding, a periodic orbit's, make one bar, not an axis of rounding errors).
        ax.hist(v, bins=np.linspace(0.0, 1.05 * v.max(), 31), color="C3", alpha=0.8)
        ax.set_xlim(0.0, 1.1 * v.max())
    else:
        ax.text(0.5, 0.5, "no impacts in the recorded window", ha="center", va="center", transform=ax.transAxes)
    ax.set_xlabel(u["velocity"])
    ax.set_ylabel("impacts")

    def g(key):
        x = st.get(key)
        return "-" if x is None or not np.isfinite(x) else f"{x:.4g}"

    ax.set_title(f"{len(v)} impacts, rate {g('impact_rate')}{u['rate']}{u['per']}\n"
                 f"velocity mean {g('impact_velocity_mean')}, max {g('impact_velocity_max')}{u['v']}\n"
                 f"energy/impact {g('energy_per_impact')}{u['e']}, power {g('power')}{u['p']}", fontsize=8)


def sections(result, path=None, ax=None, units="model"):
    """The recorded section points in the plane of the plot variable and the next state
    variable that varies on the section, titled with the period label.

    Parameters
    ----------
    result : Period or Simulation
        Uses ``section`` (and ``label`` for a Period).
    path : str, optional
    ax : matplotlib Axes, optional
    units : "model" (default) or "si"
        With "si" (a run of ``vimpact period --si ... --out DIR``), displacements in m and
        velocities in m/s, by the scales of ``result.si``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    own = ax is None
    r = _simulation(result)
    fig, ax = new_figure(path, ax, figsize=(6, 4.5))
    sec = np.asarray(r.section)
    k = plot_index(r)
    varying = [i for i in range(sec.shape[1]) if i != k and len(sec) and np.ptp(sec[:, i]) > 0] if sec.ndim == 2 \
        else []
    j = varying[0] if varying else (k + 1) % max(len(r.state_names), 1)
    _, per = si_scales(r, units)
    (fk, uk), (fj, uj) = per[k], per[j]
    if len(sec):
        ax.plot(sec[:, k] * fk, sec[:, j] * fj, "o", ms=3)
        coincident_limits(ax, sec[:, k] * fk, sec[:, j] * fj)
    label_axis(ax, "x", r, state_name(r, k), after=f" at the section ({section_name(r)})", unit=uk)
    label_axis(ax, "y", r, state_name(r, j), after=" at the section", unit=uj)
    label = getattr(result, "label", None)
    ax.set_title(f"{label + ': ' if label else ''}{len(sec)} section points", fontsize=10)
    if own:
        suptitle(fig, title(r))
    return finish_figure(fig, path, dpi=120, own=own)


# ---------------------------------------------------------------- the command line's PNGs

def _draw(loader, drawer):
    def from_directory(directory, fmt="png"):
        # The command's picture options (sweep --color-by), so that DIR redraws as it was drawn.
        options = read_record(directory).get("plot_options") or {}
        return drawer(loader(directory), os.path.join(directory, f"plot.{fmt}"), **options)
    from_directory.__doc__ = f"{drawer.__name__}({loader.__qualname__}(DIR)) into DIR/plot.FORMAT"
    return from_directory


# The formats of the command line's pictures (its --format): matplotlib picks the writer by
# the file's extension.
FORMATS = ("png", "pdf", "svg")


def _kinds():
    """Plot kind (the first argument of ``python3 -m vimpact.plot``) -> function(directory)."""
    from . import plot_dimension

    return {
        "simulate": _draw(Simulation.load, phase),
        "period": _draw(Period.load, sections),
        "sweep": _draw(Sweep.load, bifurcation),
        "map": _draw(Map.load, periodicity_map),
        "basins": _draw(Basins.load, basins),
        "response": _draw(Response.load, response),
        "dimension": lambda directory, fmt="png": plot_dimension.dimension(directory, f"plot.{fmt}"),
        "floquet": _draw(Floquet.load, floquet),
        "lyapunov": _draw(Lyapunov.load, lyapunov),
        "floquet_sweep": _draw(FloquetSweep.load, floquet_sweep),
        "lyapunov_sweep": _draw(LyapunovSweep.load, lyapunov_sweep),
        "continuation": _draw(Continuation.load, continuation),
        "clearance": _draw(Clearance.load, design_chart),
    }


def main(argv):
    import matplotlib
    matplotlib.use("Agg")
    kinds = _kinds()
    if len(argv) not in (3, 4) or argv[1] not in kinds or (len(argv) == 4 and argv[3] not in FORMATS):
        print(f"usage: python3 -m vimpact.plot {'|'.join(sorted(kinds))} DIR [{'|'.join(FORMATS)}]", file=sys.stderr)
        return 2
    kinds[argv[1]](argv[2], *argv[3:])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
