"""The analyses, as Python functions over the compiled core (vimpact._vimpact).

Each function checks nothing itself: the library checks every input with the messages the
command line prints (a ValueError, vimpact.InputError), runs with the GIL released (other
Python threads keep running) and stops within about 0.1 s on Ctrl-C (KeyboardInterrupt).
"""
import math
import string
import time

import numpy as np

from . import _vimpact
from ._vimpact import ForcedImpactOscillator, WakeImpact
from .results import (Attractor, Basins, Dimension, Floquet, Grazing, Lyapunov, Map, Period, Response, RunStats,
                      Simulation, Sweep)

_D = _vimpact.defaults


def _with_defaults(f):
    """Fills ``$name`` in the docstring with the library's default, so the text cannot drift
    from the numbers."""
    f.__doc__ = string.Template(f.__doc__).substitute({k: repr(v) for k, v in _D.items()})
    return f


_MODELS = (WakeImpact, ForcedImpactOscillator)


def _model(model):
    if not isinstance(model, _MODELS):
        raise TypeError(f"model must be a vimpact.WakeImpact or vimpact.ForcedImpactOscillator "
                        f"(got {type(model).__name__})")
    return model


def _ic(model, ic):
    return model.default_ic if ic is None else np.asarray(ic, dtype=float)


def _options(model, ic, **kw):
    o = {"ic": [float(v) for v in np.ravel(_ic(model, ic))]}
    o.update(kw)
    return o


def _simulation(d, model, options):
    return Simulation(outcome=d["outcome"], impacting=d["impacting"], transient_impacts=d["transient_impacts"],
                      t_record_start=d["t_record_start"], final_state=d["final_state"], section_t=d["section_t"],
                      section=d["section"], impact_t=d["impact_t"], impact_pre=d["impact_pre"],
                      impact_post=d["impact_post"], series_t=d["series_t"], series=d["series"],
                      stats=RunStats.from_dict(d["stats"]), parameters=model.parameters,
                      state_names=model.state_names, model=model, options=options)


def _strings(items, shape=None):
    a = np.array(list(items), dtype=str) if len(items) else np.array([], dtype="<U1")
    return a.reshape(shape) if shape is not None else a


def _timed(call):
    start = time.perf_counter()
    d = call()
    d["stats"]["wall_time"] = time.perf_counter() - start
    return d


_PROTOCOL_DOC = """    transient : int, default $transient
        Impacts discarded before recording (the paper: 500).
    record : int, default $record
        Section points kept (the paper: 200).
    rtol, atol : float, default $rtol, $atol
        Relative and absolute tolerances of the adaptive integrator.
    method : {"dop853", "dopri5"}, default $method
        Runge-Kutta pair: DOP853 (8th order, 7th-order interpolant) or DOPRI5.
    section : {"maxima", "minima", "impacts"}, default $section
        The section: maxima of y (ydot = 0 with ydot decreasing, the paper's Sigma), minima,
        or the state just after each impact.
    quiet_time : float, default $quiet_time
        The P0 rule: no impact for this long means the orbit has left the barrier; the points
        recorded from then on describe the barrier-free steady state.
    t_max : float, default $t_max
        The run ends with outcome ``time_limit`` at this time."""


def _doc(f):
    f.__doc__ = f.__doc__.replace("    <protocol>", _PROTOCOL_DOC)
    return _with_defaults(f)


@_doc
def simulate(model, ic=None, *, transient=_D["transient"], record=_D["record"], rtol=_D["rtol"], atol=_D["atol"],
             method=_D["method"], section=_D["section"], sample_dt=_D["sample_dt"], quiet_time=_D["quiet_time"],
             t_max=_D["t_max"]):
    """Run the paper's protocol: discard a transient of impacts, then record section points.

    From ``ic`` at t = 0 the hybrid flow runs: smooth flight integrated by an adaptive
    Runge-Kutta method, impacts located on its interpolant and mapped by the reset
    (y, v) -> (sigma, -r v), chattering resolved into sticking (docs/model.md). After
    ``transient`` impacts, the next ``record`` section points are kept, with the impacts in
    between and, when ``sample_dt > 0``, the time series of that window.

    Parameters
    ----------
    model : WakeImpact or ForcedImpactOscillator
    ic : array_like, shape (dim,), optional
        Initial state (y, ydot, x, xdot); default ``model.default_ic``, the paper's
        (0, 0, 0, 0.1). It must lie above the barrier (y >= sigma).
    <protocol>
    sample_dt : float, default $sample_dt
        > 0: also sample the recorded window every ``sample_dt`` (``series``).

    Returns
    -------
    Simulation
        ``section`` (n, dim) float64 and ``section_t`` (n,), ``impact_t`` (k,),
        ``impact_pre``/``impact_post`` (k, dim), ``series`` (m, dim) and ``series_t`` (m,),
        ``outcome``, ``stats``.

    Raises
    ------
    ValueError
        (vimpact.InputError) an input outside its valid range; the message names it.
    KeyboardInterrupt
        Ctrl-C: the run stops within about 0.1 s.

    Examples
    --------
    >>> s = vimpact.simulate(vimpact.WakeImpact(Ur=21.5), sample_dt=0.05)
    >>> s.section.shape
    (200, 4)
    """
    model = _model(model)
    d = _vimpact._simulate(model, _ic(model, ic), transient, record, rtol, atol, method, section, sample_dt,
                           quiet_time, t_max)
    opts = _options(model, ic, transient=transient, record=record, rtol=rtol, atol=atol, method=method,
                    section=section, sample_dt=sample_dt, quiet_time=quiet_time, t_max=t_max)
    return _simulation(d, model, opts)


@_doc
def period(model, ic=None, *, tol=_D["period_tol"], transient=_D["transient"], record=_D["record"],
           rtol=_D["rtol"], atol=_D["atol"], method=_D["method"], section=_D["section"],
           quiet_time=_D["quiet_time"], t_max=_D["t_max"]):
    """Classify the attractor reached from ``ic``: P0, P1, P2, ..., aperiodic.

    Runs the protocol (see ``simulate``) and labels its section points c_i (the model's
    section coordinates, (y, x, xdot) for WakeImpact: the full state, not y alone) with the
    smallest N <= record/2 such that max_i |c_{i+N} - c_i| <= tol: ``PN``. No such N:
    ``aperiodic``. No impact after the transient: ``P0``. A failed run is labelled by its
    outcome.

    Parameters
    ----------
    model : WakeImpact or ForcedImpactOscillator
    ic : array_like, shape (dim,), optional
        Initial state; default ``model.default_ic``.
    tol : float, default $period_tol
        Period tolerance (the paper: 1e-8 for Figures 2 and 5, 1e-5 for Figure 4).
    <protocol>

    Returns
    -------
    Period
        ``label``, ``period`` (int), ``impacts`` per period, ``closure``, ``section_y``
        (period,) float64, and the classified run as ``simulation``.

    Examples
    --------
    >>> vimpact.period(vimpact.WakeImpact(Ur=19)).label
    'P3'
    """
    model = _model(model)
    d = _vimpact._period(model, _ic(model, ic), tol, transient, record, rtol, atol, method, section, quiet_time,
                         t_max)
    opts = _options(model, ic, tol=tol, transient=transient, record=record, rtol=rtol, atol=atol, method=method,
                    section=section, quiet_time=quiet_time, t_max=t_max)
    return Period(label=d["label"], period=d["period"], impacts=d["impacts"], closure=d["closure"], tol=tol,
                  section_y=d["section_y"], simulation=_simulation(d["simulation"], model, opts))


@_with_defaults
def grazing(model, ic=None, *, tol=_D["grazing_tol"], transient_time=_D["grazing_transient_time"],
            rtol=_D["grazing_rtol"], atol=_D["grazing_atol"], method=_D["method"], block=_D["grazing_block"],
            t_max=_D["grazing_t_max"]):
    """The grazing value: the minimum of y on the attracting barrier-free orbit.

    The barrier-free system (sigma plays no part) runs from ``ic``; after ``transient_time``
    the minima of y (ydot = 0, ydot increasing), located on the interpolant, are taken in
    blocks of ``block``; when the smallest minimum of two successive blocks agrees within
    ``tol`` it is sigma_graze. A barrier just above sigma_graze is hit, just below it is not.
    The same run gives the largest maximum and the frequency of y (see ``response``).

    Parameters
    ----------
    model : WakeImpact or ForcedImpactOscillator
    ic : array_like, shape (dim,), optional
        Initial state; default ``model.default_ic``.
    tol : float, default $grazing_tol
        Agreement of successive block minima.
    transient_time : float, default $grazing_transient_time
        Time discarded before minima count.
    rtol, atol : float, default $grazing_rtol, $grazing_atol
        Tolerances; looser ones are tightened to 1e-12 (the grazing value is wanted to about
        1e-9), as the command line does.
    method : {"dop853", "dopri5"}, default $method
    block : int, default $grazing_block
        Minima per block.
    t_max : float, default $grazing_t_max
        Give up (``converged`` False, outcome ``time_limit``) at this time.

    Returns
    -------
    Grazing
        ``sigma_graze``, ``converged``, ``change``, ``t_graze``, ``x_graze`` (dim,) float64,
        ``y_max``, ``omega``, ``minima``, ``outcome``, ``stats``.

    Examples
    --------
    >>> round(vimpact.grazing(vimpact.WakeImpact(Ur=25)).sigma_graze, 6)   # the paper's sigma
    -0.150298
    """
    model = _model(model)
    d = _vimpact._grazing(model, _ic(model, ic), tol, transient_time, rtol, atol, method, block, t_max)
    opts = _options(model, ic, tol=tol, transient_time=transient_time, rtol=d["rtol"], atol=d["atol"],
                    method=method, block=block, t_max=t_max)
    return Grazing(sigma_graze=d["sigma_graze"], converged=d["converged"], change=d["change"],
                   t_graze=d["t_graze"], x_graze=d["x_graze"], y_max=d["y_max"], omega=d["omega"],
                   minima=d["minima"], outcome=d["outcome"], stats=RunStats.from_dict(d["stats"]),
                   parameters=model.parameters, model=model, options=opts)


@_doc
def sweep(model, param, values, ic=None, *, ic_mode="fixed", direction="up", tol=_D["period_tol"], grazing=False,
          threads=_D["threads"], progress=None, transient=_D["transient"], record=_D["record"], rtol=_D["rtol"],
          atol=_D["atol"], method=_D["method"], section=_D["section"], quiet_time=_D["quiet_time"],
          t_max=_D["t_max"]):
    """Bifurcation diagram: the protocol and the period label at every value of one parameter.

    Each value is one job of the library's job loop: ``threads`` workers, results delivered
    in job order, so the result does not depend on the thread count. Every point runs the
    protocol (see ``simulate``) on ``model.with_(param=value)`` and keeps all its section
    points, labelled as by ``period``.

    Parameters
    ----------
    model : WakeImpact or ForcedImpactOscillator
        Every parameter but ``param`` is taken from it.
    param : str
        The parameter to vary (``"Ur"``, ``"sigma"``, ``"r"``, ...).
    values : array_like, shape (n,)
        Its values, finite. ``vimpact.grid(a, b, n)`` gives the command line's ``a:b:n``
        bit for bit.
    ic : array_like, shape (dim,), optional
        Initial state; default ``model.default_ic``.
    ic_mode : {"fixed", "follow"}, default "fixed"
        ``fixed``: every point starts from ``ic`` (the paper's way; ``ic`` must be above the
        barrier at every point). ``follow``: each point starts from the previous point's final
        state, so the sweep stays on its attractor while it exists (hysteresis, coexisting
        attractors); a state below the next barrier is put on it, moving away.
    direction : {"up", "down", "both"}, default "up"
        Order of the values; ``both`` (follow only) runs the upward and downward branches as
        two chains in parallel.
    tol : float, default $period_tol
        Period tolerance.
    grazing : bool, default False
        Also compute the grazing value at every point (barrier-free, from ``ic``).
    threads : int, default $threads
        Worker threads; 0 means one per core. The result does not depend on it.
    progress : callable, optional
        Called as ``progress(done, total)`` from the calling thread while jobs finish (at
        most every 50 ms, and once at the end), e.g. to drive a progress bar.
    <protocol>

    Returns
    -------
    Sweep
        Per run (job order; ``both`` interleaves up and down): ``branch``, ``value``,
        ``label``, ``period``, ``impacts``, ``closure``, ``outcome``, ``sigma_graze``,
        ``final_state`` (runs, dim), ``steps``; all section points ``points`` (P, dim) float64
        with ``point_run`` (P,) int64 (``point_value``, ``point_branch``); ``stats``.

    Raises
    ------
    ValueError
        (vimpact.InputError) the command line's messages, naming the argument as spelled
        here (``ic_mode`` for ``--ic-mode``).
    KeyboardInterrupt
        Ctrl-C: no new job starts, running ones stop at their next step.

    Examples
    --------
    >>> s = vimpact.sweep(vimpact.WakeImpact(), "Ur", vimpact.grid(16, 19, 2))
    >>> list(s.label)
    ['P2', 'P3']
    """
    model = _model(model)
    vals = np.asarray(values, dtype=float)
    d = _timed(lambda: _vimpact._sweep(model, param, vals, _ic(model, ic), ic_mode, direction, tol, grazing,
                                       threads, transient, record, rtol, atol, method, section, quiet_time, t_max,
                                       progress))
    opts = _options(model, ic, ic_mode=ic_mode, direction=direction, tol=tol, grazing=grazing,
                    transient=transient, record=record, rtol=rtol, atol=atol, method=method, section=section,
                    quiet_time=quiet_time, t_max=t_max)
    return Sweep(param=param, values=vals.copy(), ic_mode=ic_mode, direction=direction, tol=tol, branch=d["branch"],
                 value=d["value"], label=_strings(d["label"]), period=d["period"], impacts=d["impacts"],
                 closure=d["closure"], outcome=_strings(d["outcome"]), sigma_graze=d["sigma_graze"],
                 final_state=d["final_state"], steps=d["steps"], points=d["points"], point_run=d["point_run"],
                 stats=d["stats"], parameters=model.parameters, state_names=model.state_names, model=model,
                 options=opts)


def _axis(axis, what):
    try:
        name, vals = axis
    except (TypeError, ValueError):
        raise TypeError(f"{what} must be a pair (name, values), e.g. (\"Ur\", vimpact.grid(16, 25, 10))") from None
    return str(name), np.asarray(vals, dtype=float)


@_doc
def map(model, x, y, ic=None, *, tol=_D["period_tol"], grazing=False, threads=_D["threads"], progress=None,
        transient=_D["transient"], record=_D["record"], rtol=_D["rtol"], atol=_D["atol"], method=_D["method"],
        section=_D["section"], quiet_time=_D["quiet_time"], t_max=_D["t_max"]):
    """Periodicity map: the period label over a grid of two parameters.

    One job per grid point (threaded, deterministic, see ``sweep``); each runs the protocol
    from ``ic`` on the model with both parameters set and labels it as ``period`` does.

    Parameters
    ----------
    model : WakeImpact or ForcedImpactOscillator
    x, y : (str, array_like)
        The axes: a parameter name and its values, e.g. ``x=("Ur", vimpact.grid(16, 25, 10))``,
        ``y=("sigma", vimpact.grid(-0.16, -0.02, 8))``.
    ic : array_like, shape (dim,), optional
        Initial state of every run; default ``model.default_ic``.
    tol : float, default $period_tol
        Period tolerance (the paper's Figure 4: 1e-5).
    grazing : bool, default False
        With sigma on one axis: also compute sigma_graze of the other parameter, the boundary
        between P0 (barrier out of reach) and impacting motion.
    threads : int, default $threads
    progress : callable, optional
        ``progress(done, total)``, see ``sweep``.
    <protocol>

    Returns
    -------
    Map
        ``label`` (ny, nx) str, ``period``/``impacts``/``steps`` (ny, nx) int64,
        ``closure`` (ny, nx) float64, ``outcome`` (ny, nx) str, ``x_values`` (nx,),
        ``y_values`` (ny,), ``grazing`` (k, 2) float64 or None, ``stats``. Index ``[iy, ix]``.
    """
    model = _model(model)
    xn, xs = _axis(x, "x")
    yn, ys = _axis(y, "y")
    d = _timed(lambda: _vimpact._map(model, xn, xs, yn, ys, _ic(model, ic), tol, grazing, threads, transient, record,
                                     rtol, atol, method, section, quiet_time, t_max, progress))
    shape = (len(ys), len(xs))
    opts = _options(model, ic, tol=tol, grazing=grazing, transient=transient, record=record, rtol=rtol, atol=atol,
                    method=method, section=section, quiet_time=quiet_time, t_max=t_max)
    return Map(x=xn, y=yn, x_values=xs.copy(), y_values=ys.copy(), tol=tol, label=_strings(d["label"], shape),
               period=d["period"].reshape(shape), impacts=d["impacts"].reshape(shape),
               closure=d["closure"].reshape(shape), outcome=_strings(d["outcome"], shape),
               steps=d["steps"].reshape(shape), grazing=d["grazing"], stats=d["stats"],
               parameters=model.parameters, model=model, options=opts)


@_doc
def basins(model, x, y, ic=None, *, tol=_D["period_tol"], match_tol=_D["match_tol"], threads=_D["threads"],
           progress=None, transient=_D["transient"], record=_D["record"], rtol=_D["rtol"], atol=_D["atol"],
           method=_D["method"], section=_D["section"], quiet_time=_D["quiet_time"], t_max=_D["t_max"]):
    """Basins of attraction over a grid of initial states.

    One job per initial state (threaded, deterministic, see ``sweep``): two state components
    vary over the grid, the others come from ``ic``. Each run is reduced to a signature and
    the attractors are numbered in job order: periodic runs with the same label whose cycle
    points match within ``match_tol`` (max norm, any cyclic order) reached the same attractor;
    aperiodic runs when their section points' bounding boxes agree within 5 % of their
    extent; failed runs form one class per outcome. Starts below the barrier get id -1.

    Parameters
    ----------
    model : WakeImpact or ForcedImpactOscillator
    x, y : (str, array_like)
        State components and values, e.g. ``x=("y", vimpact.grid(-0.2, 0.25, 46))``,
        ``y=("ydot", ...)``; names from ``model.state_names`` (``y``, ``ydot``, ``x``,
        ``xdot``).
    ic : array_like, shape (dim,), optional
        The other state components; default ``model.default_ic``.
    tol : float, default $period_tol
        Period tolerance.
    match_tol : float, default $match_tol
        Cycle points closer than this are the same attractor.
    threads : int, default $threads
    progress : callable, optional
        ``progress(done, total)``, see ``sweep``.
    <protocol>

    Returns
    -------
    Basins
        ``attractor`` (ny, nx) int64 (-1: start below the barrier), ``label`` (ny, nx) str,
        ``period``/``steps`` (ny, nx) int64, ``outcome`` (ny, nx) str, ``attractors`` (a
        list of Attractor: id, label, cells, cycle (N, k) float64, box (2, k)), ``stats``.
    """
    model = _model(model)
    xn, xs = _axis(x, "x")
    yn, ys = _axis(y, "y")
    d = _timed(lambda: _vimpact._basins(model, xn, xs, yn, ys, _ic(model, ic), tol, match_tol, threads, transient,
                                        record, rtol, atol, method, section, quiet_time, t_max, progress))
    shape = (len(ys), len(xs))
    opts = _options(model, ic, tol=tol, match_tol=match_tol, transient=transient, record=record, rtol=rtol,
                    atol=atol, method=method, section=section, quiet_time=quiet_time, t_max=t_max)
    attractors = [Attractor(id=a["id"], label=a["label"], cells=a["cells"], cycle=a["cycle"], box=a["box"])
                  for a in d["attractors"]]
    return Basins(x=xn, y=yn, x_values=xs.copy(), y_values=ys.copy(), tol=tol, match_tol=match_tol,
                  attractor=d["attractor"].reshape(shape), label=_strings(d["label"], shape),
                  period=d["period"].reshape(shape), outcome=_strings(d["outcome"], shape),
                  steps=d["steps"].reshape(shape), attractors=attractors, stats=d["stats"],
                  parameters=model.parameters, model=model, options=opts)


@_with_defaults
def response(model, param, values, ic=None, *, curves=None, transient_time=_D["grazing_transient_time"],
             rtol=_D["grazing_rtol"], atol=_D["grazing_atol"], method=_D["method"], threads=_D["threads"],
             progress=None):
    """Lock-in curves of the barrier-free system: amplitude and frequency over a parameter.

    One job per (curve, value) (threaded, deterministic, see ``sweep``). Each runs the
    barrier-free system of ``model.with_(A=A, eps=eps, param=value)`` as ``grazing`` does
    and measures, over the last block of 16 minima: sigma_graze (the smallest minimum of y),
    y_max (the largest maximum), the amplitude max|y| = max(|y_max|, |sigma_graze|) and the
    angular frequency of y, 2 pi 15 / (t_16 - t_1), relative to the wake's (which is 1 in the
    model's time unit). The paper's Figure 10a, b.

    Parameters
    ----------
    model : WakeImpact
    param : str
        The parameter to vary (usually ``"Ur"``; not ``"sigma"``, which has no effect here).
    values : array_like, shape (n,)
    ic : array_like, shape (4,), optional
        Initial state; default ``model.default_ic``.
    curves : sequence of (A, eps), optional
        One curve per pair; default ``[(model.A, model.eps)]``.
    transient_time : float, default $grazing_transient_time
        Time discarded before measuring.
    rtol, atol : float, default $grazing_rtol, $grazing_atol
        Looser values are tightened to 1e-12, as for ``grazing``.
    method : {"dop853", "dopri5"}, default $method
    threads : int, default $threads
    progress : callable, optional
        ``progress(done, total)``, see ``sweep``.

    Returns
    -------
    Response
        ``values`` (n,), ``curves`` (c, 2); per curve and value, shape (c, n):
        ``amplitude``, ``y_max``, ``sigma_graze``, ``frequency_ratio``,
        ``structure_frequency`` (float64), ``converged`` (bool), ``outcome`` (str),
        ``steps`` (int64); ``stats``.
    """
    if not isinstance(model, WakeImpact):
        raise TypeError(f"response needs a vimpact.WakeImpact model (got {type(model).__name__})")
    vals = np.asarray(values, dtype=float)
    pairs = [(model.A, model.eps)] if curves is None else [(float(a), float(e)) for a, e in curves]
    d = _timed(lambda: _vimpact._response(model, param, vals, pairs, _ic(model, ic), transient_time, rtol, atol,
                                          method, threads, progress))
    shape = (len(pairs), len(vals))
    opts = _options(model, ic, curves=pairs, transient_time=transient_time, rtol=rtol, atol=atol, method=method)
    return Response(param=param, values=vals.copy(), curves=np.array(pairs, dtype=float).reshape(-1, 2),
                    amplitude=d["amplitude"].reshape(shape), y_max=d["y_max"].reshape(shape),
                    sigma_graze=d["sigma_graze"].reshape(shape), frequency_ratio=d["frequency_ratio"].reshape(shape),
                    structure_frequency=d["structure_frequency"].reshape(shape),
                    converged=d["converged"].reshape(shape), outcome=_strings(d["outcome"], shape),
                    steps=d["steps"].reshape(shape), stats=d["stats"], parameters=model.parameters, model=model,
                    options=opts)


def grid(a, b, n):
    """n values from a to b inclusive, evenly spaced, as the command line's range ``a:b:n``.

    Value i is a + i (b - a)/(n - 1), the last is b exactly: the values of
    ``vimpact sweep --range a:b:n`` bit for bit (``numpy.linspace`` rounds differently).

    Returns
    -------
    ndarray, float64, shape (n,)
    """
    return _vimpact.grid(a, b, n)


@_with_defaults
def floquet(model, ic=None, *, tol=_D["period_tol"], newton_tol=_D["newton_tol"],
            newton_iterations=_D["newton_iterations"], impact_map="saltation", sample_dt=0.0,
            transient=_D["transient"], record=_D["record"], rtol=_D["rtol"], atol=_D["atol"], method=_D["method"],
            quiet_time=_D["quiet_time"], t_max=_D["t_max"]):
    """Floquet multipliers of the periodic orbit reached from ``ic`` (the paper's Algorithm 1).

    1. The protocol (see ``simulate``; section: maxima) and its period label, as ``period``.
       An aperiodic or failed run stops here: no multipliers.
    2. Newton shooting on P^k(z) = z, k the maxima per period, from the first recorded point,
       until the closure |P^k(z) - z|_inf <= ``newton_tol``.
    3. The monodromy Phi(T) = Phi_n S_n ... S_1 Phi_1 over one period from the refined point:
       the variational flow between impacts, the saltation matrix
       S = R' + (F+ - R' F) grad(h)^T / (grad(h) . F) at each impact (Eq. 8).
    4. The multipliers are its eigenvalues; the trivial one (for the flow direction) is 1 up
       to the accuracy of the monodromy and comes first.

    Parameters
    ----------
    model : WakeImpact or ForcedImpactOscillator
    ic : array_like, shape (dim,), optional
        Initial state; default ``model.default_ic``.
    tol : float, default $period_tol
        Period tolerance for the label.
    newton_tol : float, default $newton_tol
        Closure to reach by Newton shooting.
    newton_iterations : int, default $newton_iterations
    impact_map : {"saltation", "reset-jacobian", "identity"}, default "saltation"
        The tangent jump at impacts: saltation is correct; the other two are wrong and there
        to show it (the trivial multiplier moves off 1).
    sample_dt : float, default 0
        > 0: also sample the refined orbit over one period (``orbit``).
    transient, record, rtol, atol, method, quiet_time, t_max
        The protocol's, as for ``simulate`` (defaults $transient, $record, $rtol, $atol,
        $method, $quiet_time, $t_max). The tangent runs integrate at min(rtol, 1e-12), as the
        command line does.

    Returns
    -------
    Floquet
        ``status``, ``label``, ``period``, ``multipliers`` (dim,) complex128 (trivial first),
        ``monodromy`` (dim, dim), ``orbit_point`` (dim,), ``stable``, ``closure``, ...

    Examples
    --------
    >>> f = vimpact.floquet(vimpact.WakeImpact(Ur=16))
    >>> f.label, f.stable
    ('P2', True)
    """
    model = _model(model)
    d = _vimpact._floquet(model, _ic(model, ic), tol, newton_tol, newton_iterations, impact_map, sample_dt,
                          transient, record, rtol, atol, method, quiet_time, t_max)
    opts = _options(model, ic, tol=tol, newton_tol=newton_tol, newton_iterations=newton_iterations,
                    impact_map=impact_map, sample_dt=sample_dt, transient=transient, record=record, rtol=rtol,
                    atol=atol, tangent_rtol=d["tangent_rtol"], method=method, quiet_time=quiet_time, t_max=t_max)
    stats = {"protocol": RunStats.from_dict(d["protocol_stats"]), "tangent": RunStats.from_dict(d["tangent_stats"]),
             "map_evaluations": d["map_evaluations"]}
    keys = ("status", "flow_outcome", "label", "section_returns", "period", "impacts_per_period", "initial_closure",
            "closure", "newton_iterations", "orbit_point", "monodromy", "multipliers", "trivial_error",
            "trivial_residual", "max_nontrivial_modulus", "stable", "det_monodromy", "liouville_det", "impact_map",
            "orbit_t", "orbit", "impact_t", "impact_pre", "impact_post")
    return Floquet(**{k: d[k] for k in keys}, stats=stats, parameters=model.parameters, model=model, options=opts)


@_with_defaults
def lyapunov(model, ic=None, *, tdm="saltation", r0=_D["r0"], t0=_D["t0"], impacts=_D["lyapunov_impacts"],
             time=0.0, warmup=_D["warmup"], transient=_D["transient"], rtol=_D["rtol"], atol=_D["atol"],
             method=_D["method"], quiet_time=_D["quiet_time"], t_max=_D["t_max"]):
    """The Lyapunov spectrum of the attractor reached from ``ic`` (the paper's Algorithm 2).

    After ``transient`` impacts, dim deviation vectors of size ``r0`` follow the orbit; every
    ``t0`` they are re-orthonormalised by a QR decomposition and ln(R_ii / r0) is accumulated.
    After ``warmup`` intervals (not counted) the averages over the next ``impacts`` impacts
    (or ``time``) are the exponents, lambda_i = (1/T) sum ln(R_ii / r0), in descending order
    (Eq. 13). Their sum must equal <div F> + (1/T) sum ln|det S| (``sum_rule``).

    Parameters
    ----------
    model : WakeImpact or ForcedImpactOscillator
    ic : array_like, shape (dim,), optional
        Initial state; default ``model.default_ic``.
    tdm : {"saltation", "second-order", "trajectory"}, default "saltation"
        How deviations cross an impact: the saltation matrix (first order, the textbook
        spectrum), the second-order discontinuity mapping (SPEC section 4) applied to the
        finite deviations, or two-trajectory integration (Benettin).
    r0 : float, default $r0
        Size of the deviation vectors.
    t0 : float, default $t0
        Re-orthonormalisation interval (pi, the paper's).
    impacts : int, default $lyapunov_impacts
        Average over this many impacts (the paper: 800) ...
    time : float, default 0
        ... or, if > 0, over this much time.
    warmup : int, default $warmup
        Intervals not counted while the vectors align.
    transient, rtol, atol, method, quiet_time, t_max
        As for ``simulate`` (defaults $transient, $rtol, $atol, $method, $quiet_time, $t_max).

    Returns
    -------
    Lyapunov
        ``exponents`` (dim,) float64, ``lle``, ``lle_standard_error``, ``sum_rule``,
        ``history_t`` (h,) and ``history_growth`` (h, dim), ``running_exponents``, ``status``.
    """
    model = _model(model)
    d = _vimpact._lyapunov(model, _ic(model, ic), tdm, r0, t0, impacts, time, warmup, transient, rtol, atol, method,
                           quiet_time, t_max)
    opts = _options(model, ic, tdm=tdm, r0=r0, t0=t0, impacts=impacts, time=time, warmup=warmup, transient=transient,
                    rtol=rtol, atol=atol, method=method, quiet_time=quiet_time, t_max=t_max)
    stats = {"transient": RunStats.from_dict(d["transient_stats"]), "tangent": RunStats.from_dict(d["tangent_stats"])}
    keys = ("status", "flow_outcome", "tdm", "impacting", "exponents", "lle_standard_error", "t_start", "time",
            "impacts", "intervals", "divergence_average", "jump_log_det_rate", "sum_rule", "misses", "history_t",
            "history_growth")
    return Lyapunov(**{k: d[k] for k in keys}, stats=stats, parameters=model.parameters, model=model, options=opts)


@_with_defaults
def dimension(points, *, estimator="correlation_sum", theiler=0, centres=_D["centres"], radii=_D["radii"],
              fit_range=None, slope_tolerance=_D["slope_tolerance"], slope_window=_D["slope_window"],
              min_extent=_D["min_extent"], min_pairs=_D["min_pairs"], max_correlation=_D["max_correlation"],
              r_max=math.inf, max_pairs=_D["max_pairs"], bins_per_octave=_D["bins_per_octave"], search="grid",
              threads=1):
    """The correlation dimension of a point set (Grassberger & Procaccia; the paper's Eq. 5).

    The correlation curve C(r) is either the Grassberger-Procaccia sum over all pairs,
    C(r) = #{i < j, j - i > w : |x_i - x_j| < r} / #{i < j, j - i > w} (w the Theiler
    window), binned in one pass, or the paper's centre counts (N_k(r) averaged over
    ``centres`` points on a linear grid of radii). The dimension is the least-squares slope of
    log C against log r over the scaling region: the longest range of r whose local slopes
    agree within 2 ``slope_tolerance``, spanning at least ``min_extent``, between the
    counting-noise floor (``min_pairs``) and saturation (``max_correlation``); or over
    ``fit_range``. docs/dimension.md has the details.

    Parameters
    ----------
    points : array_like, shape (n, d)
        One point per row, e.g. ``vimpact.simulate(m, record=20000).section[:, [0, 2, 3]]``
        (the section coordinates y, x, xdot, as the command line uses).
    estimator : {"correlation_sum", "centres"}, default "correlation_sum"
    theiler : int, default 0
        Pairs at most this many rows apart are not counted.
    centres : int, default $centres
        Centres estimator: number of centres (the paper: 15).
    radii : (float, float, float), default $radii
        Centres estimator: r_min, r_max, step (the paper's).
    fit_range : (float, float), optional
        Fit over [r_min, r_max] instead of the automatic scaling region.
    slope_tolerance, slope_window, min_extent, min_pairs, max_correlation
        The scaling-region rule (defaults $slope_tolerance, $slope_window, $min_extent,
        $min_pairs, $max_correlation).
    r_max : float, default inf
        Correlation sum: count pairs closer than this only (inf: set from ``max_pairs``).
    max_pairs : int, default $max_pairs
        Correlation sum: cap r so that about this many pairs are counted.
    bins_per_octave : int, default $bins_per_octave
        Correlation sum: radii per factor 2 (a power of two).
    search : {"grid", "kd_tree", "brute_force"}, default "grid"
        How pairs are found (identical counts).
    threads : int, default 1
        Correlation sum threads, 0 = all cores (the counts do not depend on it).

    Returns
    -------
    Dimension
        ``dimension``, ``found``, ``fit_range``, ``r2``, ``slope_error``; the curve ``r`` (k,),
        ``pairs`` (k,) int64, ``c`` (k,), ``local_slope`` (k,).

    Notes
    -----
    This computation has no cancel flag in the library: Ctrl-C takes effect when it returns.
    """
    pts = np.asarray(points, dtype=float)
    fr = None if fit_range is None else (float(fit_range[0]), float(fit_range[1]))
    d = _vimpact._dimension(pts, estimator, theiler, centres, tuple(float(v) for v in radii), fr, slope_tolerance,
                            slope_window, min_extent, int(min_pairs), max_correlation, r_max, int(max_pairs),
                            bins_per_octave, search, threads)
    opts = dict(estimator=estimator, theiler=theiler, centres=centres, radii=tuple(radii), fit_range=fr,
                slope_tolerance=slope_tolerance, slope_window=slope_window, min_extent=min_extent,
                min_pairs=min_pairs, max_correlation=max_correlation, r_max=r_max, max_pairs=max_pairs,
                bins_per_octave=bins_per_octave, search=search)
    keys = ("dimension", "found", "automatic", "fit_range", "r2", "slope_error", "slope_spread", "intercept", "fitted",
            "fit_first", "fit_last", "r", "pairs", "total_pairs", "local_slope", "centres", "r_cap", "all_pairs",
            "estimator", "points", "embedding")
    return Dimension(**{k: d[k] for k in keys}, options=opts)
