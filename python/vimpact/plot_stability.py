"""Pictures of the stability analyses (docs/stability.md), for any model: each function takes
a result (``vimpact.floquet(...)``, or ``vimpact.Floquet.load(DIR)`` for the command line's
``--out DIR``), returns the Figure and, given ``path``, writes it there.

``floquet``: the multipliers in the complex plane with the unit circle (trivial one marked),
and the refined periodic orbit over one period with its impacts.
``lyapunov``: the running estimates of the exponents against time (Eq. 13), which show
whether the average has converged.
``floquet_sweep``, ``lyapunov_sweep``: multipliers or the largest exponent against the swept
parameter over the bifurcation diagram (the paper's Figures 14-17).
"""
import numpy as np

from .plot_common import (finish_figure, label_axis, legend_outside, new_figure, plot_index, section_name, si_scales,
                          state_name, suptitle, surface_levels, title)


def floquet(result, path=None, units="model"):
    """Multipliers on the unit circle, and the periodic orbit they belong to.

    Parameters
    ----------
    result : Floquet
        Uses ``multipliers`` (trivial first), ``trivial_error``, ``label``, ``period``,
        ``impacts_per_period``, ``stable``, ``status``, ``orbit`` (from ``sample_dt > 0``),
        ``impact_pre``/``impact_post``, ``state_names``, ``plot_variable``.
    path : str, optional
    units : "model" (default) or "si"
        With "si" (loaded from ``vimpact floquet --si ... --out DIR``): the orbit's
        displacements in m, velocities in m/s and the period in s, by the scales of ``result.si``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (ax1, ax2) = new_figure(path, None, figsize=(13, 5), nrows=1, ncols=2)
    phi = np.linspace(0.0, 2.0 * np.pi, 400)
    ax1.plot(np.cos(phi), np.sin(phi), "k-", lw=0.8, label="unit circle")
    ax1.axhline(0.0, color="0.8", lw=0.6)
    ax1.axvline(0.0, color="0.8", lw=0.6)
    mus = np.asarray(result.multipliers if result.multipliers is not None else [], dtype=complex)
    if len(mus):
        ax1.plot(mus[1:].real, mus[1:].imag, "o", color="C0", ms=7, label="multipliers")
        ax1.plot(mus[:1].real, mus[:1].imag, "s", mfc="none", color="C3", ms=9,
                 label=f"trivial (|mu - 1| = {result.trivial_error:.1e})")
    # Equal scales shrink the box to a square; kept at its left edge, where tight_layout made
    # room for the label (centred, the label slid off the figure).
    ax1.set_aspect("equal", anchor="W")
    lim = max(1.3, 1.1 * float(np.max(np.abs(mus)))) if len(mus) else 1.3
    ax1.set_xlim(-lim, lim)
    ax1.set_ylim(-lim, lim)
    ax1.set_xlabel("Re mu")
    ax1.set_ylabel("Im mu")
    legend_outside(ax1)
    ft, per = si_scales(result, units)
    if len(mus):
        period = f"{result.period * ft:.6g} s" if units == "si" else f"{result.period:.6g}"
        head = (f"{result.label}: T = {period}, {result.impacts_per_period} impact(s), "
                f"{'stable' if result.stable else 'unstable'}")
    else:
        head = f"{result.label}: no multipliers ({result.status})"
    ax1.set_title(head, fontsize=10)

    k = plot_index(result)
    j = k + 1 if k + 1 < len(result.state_names) else 0
    (fk, uk), (fj, uj) = per[k], per[j]
    orbit = np.asarray(result.orbit if result.orbit is not None else np.empty((0, 0)))
    if orbit.ndim == 2 and len(orbit):
        ax2.plot(orbit[:, k] * fk, orbit[:, j] * fj, lw=1.0, color="C0", label="periodic orbit")
        ax2.plot(orbit[:1, k] * fk, orbit[:1, j] * fj, "g^", ms=6, label="start on the section")
    pre = np.asarray(result.impact_pre if result.impact_pre is not None else np.empty((0, 0)))
    post = np.asarray(result.impact_post if result.impact_post is not None else np.empty((0, 0)))
    if pre.ndim == 2 and len(pre):
        ax2.plot(pre[:, k] * fk, pre[:, j] * fj, "rv", ms=5, label="impact (before)")
        ax2.plot(post[:, k] * fk, post[:, j] * fj, "r^", ms=5, label="impact (after)")
    for name, level in surface_levels(result, k).items():
        ax2.axvline(level * fk, color="k", ls="--", lw=1.0,
                    label=f"{name}: {state_name(result, k)} = {level * fk:g}{' ' + uk if uk else ''}")
    label_axis(ax2, "x", result, state_name(result, k), unit=uk)
    label_axis(ax2, "y", result, state_name(result, j), unit=uj)
    legend_outside(ax2)
    ax2.set_title("the orbit over one period" if len(orbit) else "impacts over one period (sample_dt = 0)",
                  fontsize=10)
    suptitle(fig, title(result))
    return finish_figure(fig, path, dpi=120)


def lyapunov(result, path=None, units="model"):
    """Running estimates of the exponents (cumulative QR growth / elapsed time).

    Parameters
    ----------
    result : Lyapunov
        Uses ``history_t``, ``running_exponents``, ``t_start``, ``lle``,
        ``lle_standard_error``, ``tdm``, ``impacts``, ``time``, ``status``.
    path : str, optional
    units : "model" (default) or "si"
        With "si" (loaded from ``vimpact lyapunov --si ... --out DIR``): time in s and the
        exponents per second, by the time scale of ``result.si``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (ax1, ax2) = new_figure(path, None, figsize=(9, 7), nrows=2, ncols=1, sharex=True,
                                 gridspec_kw={"height_ratios": [1, 1.4]})
    ft = si_scales(result, units)[0]
    ht = np.asarray(result.history_t if result.history_t is not None else [])
    if len(ht):
        t = (ht - result.t_start) * ft
        run = result.running_exponents / ft
        for i in range(run.shape[1]):
            ax2.plot(t, run[:, i], lw=1.0, color=f"C{i}", label=f"lambda{i + 1}")
        # The largest on its own scale: whether it settles at 0 or above is the question.
        lead = int(np.argmax(run[-1]))
        ax1.plot(t, run[:, lead], color=f"C{lead}", lw=1.0)
        ax1.axhline(0.0, color="k", lw=0.6)
        exps = np.asarray(result.exponents, dtype=float) / ft
        if len(exps) and np.isfinite(exps[0]):
            se = result.lle_standard_error / ft if np.isfinite(result.lle_standard_error) else 0.0
            ax1.axhspan(exps[0] - se, exps[0] + se, color=f"C{lead}", alpha=0.15,
                        label=f"LLE = {exps[0]:.4g} +- {se:.1g}")
            legend_outside(ax1)
        tail = run[len(run) // 10:, lead]
        span = float(np.abs(tail).max()) if len(run) > 10 and np.abs(tail).max() > 0 else 1.0
        ax1.set_ylim(-1.5 * span, 1.5 * span)
        legend_outside(ax2)
    # Exponents are rates: per unit of the model's time, or per second.
    rate = "1/s" if units == "si" else "per unit t"
    ax1.set_ylabel(f"largest exponent [{rate}]")
    elapsed = f"{result.time * ft:.6g} s" if units == "si" else f"{result.time:.6g}"
    ax1.set_title(f"mapping at impacts: {result.tdm}; {result.impacts} impacts, t = {elapsed} "
                  f"({result.status})", fontsize=10)
    ax2.axhline(0.0, color="k", lw=0.6)
    ax2.set_xlabel("t - t_start, since the start of the average" + (" [s]" if units == "si" else ""))
    ax2.set_ylabel(f"running estimate [{rate}]")
    suptitle(fig, title(result))
    return finish_figure(fig, path, dpi=120)


def _diagram(ax, result):
    """The bifurcation diagram underneath: the plot variable at the section of every value."""
    k = plot_index(result)
    pts = np.asarray(result.points if result.points is not None else np.empty((0, 0)))
    if pts.ndim == 2 and len(pts):
        ax.plot(result.point_value, pts[:, k], "k.", ms=1.2)
    label_axis(ax, "x", result, result.param)
    label_axis(ax, "y", result, state_name(result, k), after=f" at the section ({section_name(result)})")


def floquet_sweep(result, path=None):
    """Multipliers against the swept parameter (the paper's Figures 14, 15), the band
    -1 <= mu <= 1 shaded, over the bifurcation diagram.

    Parameters
    ----------
    result : FloquetSweep
    path : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (ax1, ax2) = new_figure(path, None, figsize=(9, 8), nrows=2, ncols=1, sharex=True,
                                 gridspec_kw={"height_ratios": [1.2, 1]})
    ax1.axhspan(-1.0, 1.0, color="C2", alpha=0.08, label="|mu| <= 1 (stable)")
    ax1.axhline(1.0, color="k", lw=0.6)
    ax1.axhline(-1.0, color="k", lw=0.6)
    mus = np.asarray(result.multipliers, dtype=complex)
    if mus.size:
        v = np.repeat(np.asarray(result.value, dtype=float)[:, None], mus.shape[1], axis=1)
        trivial = np.asarray(result.trivial, dtype=bool)
        have = np.isfinite(mus.real)
        real = np.abs(mus.imag) <= 1e-12
        # Only the kinds present, so that the legend names nothing absent from the picture.
        for sel, y, style, colour, name in ((have & ~trivial & real, mus.real, ".", "C0", "real multipliers"),
                                            (have & ~trivial & ~real, np.abs(mus), "^", "C1", "|mu| of complex pairs"),
                                            (have & trivial, mus.real, "x", "0.6", "trivial")):
            if sel.any():
                ax1.plot(v[sel], y[sel], style, color=colour, ms=3, label=name)
    ax1.set_ylim(-1.6, 1.6)
    ax1.set_ylabel("Floquet multipliers mu")
    counts = ", ".join(f"{k} {n}" for k, n in result.label_counts.items())
    ax1.set_title(f"multipliers over {result.param} ({counts}; aperiodic points have none)", fontsize=10)
    legend_outside(ax1, markerscale=2)
    _diagram(ax2, result)
    suptitle(fig, title(result, (result.param,)))
    return finish_figure(fig, path, dpi=120)


def lyapunov_sweep(result, path=None):
    """The largest Lyapunov exponent against the swept parameter (the paper's Figures 16, 17)
    with its standard error, over the bifurcation diagram.

    Parameters
    ----------
    result : LyapunovSweep
    path : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (ax1, ax2) = new_figure(path, None, figsize=(9, 8), nrows=2, ncols=1, sharex=True)
    ax1.axhline(0.0, color="k", lw=0.6)
    v = np.asarray(result.value, dtype=float)
    lle = np.asarray(result.lle, dtype=float)
    se = np.asarray(result.lle_standard_error, dtype=float)
    ok = np.isfinite(lle)
    ax1.errorbar(v[ok], lle[ok], yerr=np.where(np.isfinite(se[ok]), se[ok], 0.0), fmt=".-", color="C3", ms=4,
                 lw=0.8, elinewidth=0.8, capsize=1.5)
    ax1.set_ylabel("largest Lyapunov exponent [per unit t]")
    ax1.set_title(f"mapping at impacts: {result.tdm}; {result.positive} of {len(v)} values above 3 standard errors",
                  fontsize=10)
    _diagram(ax2, result)
    suptitle(fig, title(result, (result.param,)))
    return finish_figure(fig, path, dpi=120)
