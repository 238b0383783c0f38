"""The analyses, as Python functions over the compiled core (vimpact._vimpact).

Each function is one library analysis of (model, options[, job options]): it fills in the
defaults, names the model's parameters, state variables, surfaces and sections, and shapes
the library's numbers into a result object. The library checks every input (a ValueError,
vimpact.InputError, with its message), runs with the GIL released (other Python threads keep
running) and stops within about 0.1 s on Ctrl-C (KeyboardInterrupt).
"""
import collections.abc
import functools
import inspect
import json
import os
import string
import time

import numpy as np

from . import _vimpact
from ._model import Model
from ._vimpact import InputError
from ._units import PhysicalUnits
from .results_continuation import Continuation
from .results import (Attractor, Basins, Clearance, Dimension, Floquet, FloquetSweep, Grazing, JobReport, Lyapunov,
                      LyapunovSweep, Map, Period, Response, RunStats, Simulation, Sweep, _picked, model_quantities)

_D = _vimpact.defaults


def _with_defaults(f):
    """Fills ``$name`` in the docstring with the library's default, so the text cannot drift
    from the numbers; and the shared paragraphs ``<section>``, ``<jobs>`` and, for
    ``ANALYSIS_sweep``, ``<per_value>``."""
    doc = f.__doc__.replace("    <section>", _SECTION_DOC).replace("    <jobs>", _JOBS_DOC)
    doc = doc.replace("    <per_value>", _PER_VALUE_DOC.replace("ANALYSIS", f.__name__.removesuffix("_sweep")))
    f.__doc__ = string.Template(doc).substitute({k: repr(v) for k, v in _D.items()})
    return f


def _declares(*kinds, without=()):
    """The keyword arguments that the library declares for the options of each of ``kinds``
    (``_vimpact.declared``, core/option.hpp) but those named in ``without``, added to f's
    signature as keyword-only arguments with the library's defaults and documented by the
    declaration's help and range: the protocol's (``"protocol"``) in place of ``<protocol>``,
    an analysis' own in place of ``<declared>``. f receives them as one dict ``declared``, which
    the bindings read by key. A new option is one line in the library."""
    entries = {k: [e for e in _vimpact.declared[k] if e["key"] not in without] for k in kinds}

    def kind_of(e):
        d = e["default"]
        return "bool" if isinstance(d, bool) else "int" if isinstance(d, int) else "float" if isinstance(d, float) \
            else "float or None" if d is None else "{" + ", ".join(f'"{n}"' for n in e["range"].split(", ")) + "}"

    def where(e):
        return "" if not e["range"] or isinstance(e["default"], str) else f" In {e['range']}."

    def doc(kind):
        return "".join(f"    {e['key']} : {kind_of(e)}, default {e['default']!r}\n        "
                       f"{e['help'][0].upper()}{e['help'][1:]}.{where(e)}\n" for e in entries[kind])

    every = [e for k in kinds for e in entries[k]]

    def wrap(f):
        inner = inspect.signature(f)
        params = [p for p in inner.parameters.values() if p.name != "declared"]
        params += [inspect.Parameter(e["key"], inspect.Parameter.KEYWORD_ONLY, default=e["default"]) for e in every]
        outer = inner.replace(parameters=params)

        @functools.wraps(f)
        def call(*args, **kw):
            bound = outer.bind(*args, **kw)  # a TypeError names a keyword nobody declares
            bound.apply_defaults()
            a = dict(bound.arguments)
            declared = {e["key"]: a.pop(e["key"]) for e in every}
            return f(**a, declared=declared)

        call.__signature__ = outer
        text = f.__doc__
        for k in kinds:
            text = text.replace("    <protocol>\n" if k == "protocol" else "    <declared>\n", doc(k))
        call.__doc__ = text
        return call
    return wrap


_SECTION_DOC = """    section : str, optional
        Where points are recorded: a section of the model (``model.sections``, e.g.
        ``"maxima"``), ``"impacts"`` (the state just after every impact) or
        ``"impacts:SURFACE"`` (after impacts on one surface). Default: the model's first
        section, or the impacts if it declares none."""

_JOBS_DOC = """    threads : int, default $threads
        Worker threads, 0 = every core. Results never depend on it.
    journal : str or path, optional
        A directory where every finished job is recorded as it finishes: a run stopped by
        Ctrl-C, an exception from ``progress`` or a kill keeps its finished jobs, and the same
        call with ``resume=True`` computes only the others. Removed when the run completes
        (unless ``keep_journal``).
    resume : bool, default False
        Continue the run recorded in ``journal`` (which must be of the same analysis, model
        and options). Without it an existing journal of a whole run is refused.
    shard : (int, int), optional
        ``(i, n)``: compute only shard i of n (every n-th job), in n processes that share
        ``journal``; a shard returns a JobReport unless the others have finished.
    progress : callable, optional
        ``progress(done, total)``, called from the calling thread while the jobs run (at most
        every 50 ms). An exception raised in it stops the run and propagates.
    keep_journal : bool, default False
        Keep the journal after a complete run."""


_PER_VALUE_DOC = """    One ``ANALYSIS`` analysis per value, each from ``ic`` on ``model.with_(param=value)``, as
    jobs of the library's job loop (threaded, deterministic, resumable: see ``sweep``).

    Parameters
    ----------
    model : Model
    param : str
    values : array_like, shape (n,)
    ic : array_like, shape (dim,), optional"""


def _model(model):
    if not isinstance(model, Model):
        raise TypeError(f"model must be a vimpact.Model (got {type(model).__name__}); "
                        f"e.g. vimpact.Model('wake_impact') or vimpact.Model.from_file(PATH)")
    return model


def _ic(ic):
    return None if ic is None else np.asarray(ic, dtype=float)


def _section(model, section):
    return model._handle.default_section() if section is None else str(section)


def _context(model, options):
    state_info, parameter_info = model_quantities(model.info["state"], model.info["parameters"])
    return dict(parameters=model.parameters, state_names=model.state_names, surfaces=model.surfaces,
                switches=model.switches, plot_variable=model.state_names[0], model=model, options=options, model_name=model.name,
                state_info=state_info, parameter_info=parameter_info)


def _protocol(model, section, declared, **extra):
    """The keywords the library's protocol_of reads: the declared ones, the section by name."""
    return dict(declared, section=_section(model, section), **extra)


def _jobs(threads, journal, resume, shard, progress, keep_journal):
    return dict(threads=threads, journal=None if journal is None else os.fspath(journal), resume=resume,
                shard=None if shard is None else (int(shard[0]), int(shard[1])), progress=progress,
                keep_journal=keep_journal)


def _run_jobs(call, options):
    """Runs a job analysis; the JobReport alone when the run is not complete."""
    start = time.perf_counter()
    d = call()
    report = JobReport.from_dict(d["jobs"], journal=options.get("journal"))
    if not report.complete:
        return None, report
    d["wall_time"] = time.perf_counter() - start
    return d, report


def _job_stats(d, report, **more):
    """A job analysis' stats: what it adds, its threads, the jobs computed now, the wall time."""
    return dict(more, threads=report.threads, jobs=report.computed, wall_time=d["wall_time"])


def _result_options(ic, o, *arrays):
    """The options a job analysis' result records: the call's but its arrays (ic as a list)."""
    return _options(ic, **{k: v for k, v in o.items() if k != "ic" and k not in arrays})


def _simulation(d, model, options):
    return Simulation(**dict(d, stats=RunStats.from_dict(d["stats"])), **_context(model, options))


def _options(ic, **kw):
    o = {"ic": None if ic is None else [float(v) for v in np.ravel(ic)]}
    o.update({k: v for k, v in kw.items() if k not in ("progress",)})
    return o


# ---------------------------------------------------------------- single runs

@_with_defaults
@_declares("protocol")
def simulate(model, ic=None, *, section=None, sample_dt=_D["sample_dt"], declared):
    """Run the simulation protocol: discard a transient of impacts, then record section points.

    From ``ic`` at t = 0 the hybrid flow runs: smooth flight integrated by an adaptive
    Runge-Kutta method, impacts on every surface located on its interpolant and mapped by the
    surface's reset, chattering ended by a contact phase where the surface declares one. After
    ``transient`` impacts, the next ``record`` section points are kept, with the impacts in
    between and, when ``sample_dt > 0``, the time series of that window.

    Parameters
    ----------
    model : Model
    ic : array_like, shape (dim,), optional
        Initial state, in the order of ``model.state_names``; default ``model.default_ic``.
        It must be admissible (no surface's gap negative).
    <section>
    <protocol>
    sample_dt : float, default $sample_dt
        > 0: also sample the recorded window every ``sample_dt`` (``series``).

    Returns
    -------
    Simulation
        ``section`` (n, dim) float64 and ``section_t`` (n,), ``impact_t`` (k,),
        ``impact_surface`` (k,) int64, ``impact_pre``/``impact_post`` (k, dim), ``series``
        (m, dim) and ``series_t`` (m,), ``outcome``, ``stats``.

    Raises
    ------
    ValueError
        (vimpact.InputError) an input outside its valid range; the message names it.
    KeyboardInterrupt
        Ctrl-C: the run stops within about 0.1 s.

    Examples
    --------
    >>> s = vimpact.simulate(vimpact.Model("wake_impact", Ur=21.5), sample_dt=0.05)
    >>> s.section.shape
    (200, 4)
    """
    model = _model(model)
    o = _protocol(model, section, declared, sample_dt=sample_dt)
    d = _vimpact._simulate(model._handle, _ic(ic), o)
    return _simulation(d, model, _options(ic, **o))


@_with_defaults
@_declares("protocol")
def period(model, ic=None, *, tol=_D["period_tol"], section=None, declared):
    """Classify the attractor reached from ``ic``: P0, P1, P2, ..., aperiodic.

    Runs the protocol (see ``simulate``) and labels its section points with the smallest N <=
    record/2 such that points N apart agree within ``tol`` in the max norm over the full state
    (phases compared modulo their period): ``PN``. No such N: ``aperiodic``. No impact after
    the transient: ``P0``. A failed run is labelled by its outcome.

    Parameters
    ----------
    model : Model
    ic : array_like, shape (dim,), optional
        Initial state; default ``model.default_ic``.
    tol : float, default $period_tol
        Period tolerance (the paper: 1e-8 for Figures 2 and 5, 1e-5 for Figure 4).
    <section>
    <protocol>

    Returns
    -------
    Period
        ``label``, ``period`` (int), ``impacts`` per period, ``impacts_by_surface`` (dict
        surface -> impacts per period), ``closure``, ``cycle`` (period, dim), and the
        classified run as ``simulation``.

    Examples
    --------
    >>> vimpact.period(vimpact.Model("wake_impact", Ur=19)).label
    'P3'
    """
    model = _model(model)
    o = _protocol(model, section, declared, tol=tol)
    d = _vimpact._period(model._handle, _ic(ic), o)
    return Period(record=d["record"], tol=tol, simulation=_simulation(d["simulation"], model, _options(ic, **o)))


def _default_gap_parameter(model):
    """The first parameter that moves a surface, else a switch, without entering the vector
    field, or None (the library's rule for a sweep's grazing line and a response)."""
    p = model._handle.first_grazing_parameter()
    return model.parameter_names[p] if p >= 0 else None


@_with_defaults
@_declares("grazing")
def grazing(model, ic=None, *, param=None, variable=None, rtol=_D["grazing_rtol"], atol=_D["grazing_atol"],
            method=_D["method"], declared):
    """Where the attracting surface-free orbit just touches each surface.

    The system runs with every surface switched off from ``ic``; after ``transient_time`` the
    minima of each surface's gap along the orbit, located on the interpolant, are taken in
    blocks of ``block``, until the smallest of two successive blocks agree within ``tol``. That
    smallest gap is the surface's margin; the state where it occurs gives the grazing value of
    a parameter P that moves the surface (g(x*, P) = 0): a surface just on the admissible
    side of it is never hit, one just beyond it is (for the paper's barrier, sigma_graze is
    the minimum of y). Switches the same way (``by_switch``): the switch-free system holds the
    sides of ``ic``, and each switch's margin is the smallest side * h on its orbit.

    Parameters
    ----------
    model : Model
    ic : array_like, shape (dim,), optional
        Initial state; default ``model.default_ic``.
    param : str, optional
        The parameter whose grazing value to give for every surface; it must move a surface
        and not enter the vector field. Default: for each surface, the first parameter that
        does (``model.gap_parameters(surface)``), none where none does.
    variable : str, optional
        Also measure the response of this state variable: its largest and smallest extremum
        over the last block and its angular frequency (see ``response``).
    <declared>
    rtol, atol : float, default $grazing_rtol, $grazing_atol
        Tolerances (the grazing value is wanted to about 1e-9).
    method : {"dop853", "dopri5"}, default $method

    Returns
    -------
    Grazing
        Per surface (arrays in the order of ``surfaces``): ``param``, ``value``, ``margin``,
        ``surface_converged``, ``change``, ``t``, ``x`` (surfaces, dim), ``minima``; and
        ``converged``, ``response_max``, ``response_min``, ``response_omega``, ``outcome``,
        ``stats``; ``by_surface`` as a dict.

    Examples
    --------
    >>> g = vimpact.grazing(vimpact.Model("wake_impact", Ur=25))
    >>> round(g.by_surface["barrier"]["value"], 6)   # the paper's sigma
    -0.150298
    """
    model = _model(model)
    o = dict(declared, param=param, variable=variable, rtol=rtol, atol=atol, method=method)
    d = _vimpact._grazing(model._handle, _ic(ic), o)
    by_switch = dict(zip(model.switches, d.pop("switch_grazing")))
    return Grazing(**dict(d, param=tuple(d["param"]), stats=RunStats.from_dict(d["stats"])), variable=variable,
                   by_switch=by_switch, **_context(model, _options(ic, **o)))


# ---------------------------------------------------------------- many-job analyses

@_with_defaults
@_declares("sweep", "protocol")
def sweep(model, param, values, ic=None, *, grazing=False, section=None, threads=_D["threads"], batch=0, journal=None,
          resume=False, shard=None, progress=None, keep_journal=False, declared):
    """Bifurcation diagram: the protocol and the period label at every value of one parameter.

    Each value is one job of the library's job loop: ``threads`` workers, results delivered
    in job order, so the result does not depend on the thread count. Every point runs the
    protocol (see ``simulate``) on ``model.with_(param=value)`` and keeps all its section
    points, labelled as by ``period``.

    Parameters
    ----------
    model : Model
        Every parameter but ``param`` is taken from it.
    param : str
        The parameter to vary (one of ``model.parameter_names``).
    values : array_like, shape (n,)
        Its values. ``vimpact.grid(a, b, n)`` gives the command line's ``a:b:n`` bit for bit.
    ic : array_like, shape (dim,), optional
        Initial state; default ``model.default_ic``.
    <declared>
    grazing : bool or str, default False
        Also compute, at every point, the grazing value per surface of a parameter that moves
        the surfaces (from ``ic``, surface-free): of this parameter, or with True of the first
        one found (``sigma`` for the paper's model, ``d`` for the two stops).
    <section>
    <protocol>
    batch : int, default 0
        Jobs integrated together in SIMD lanes: 0 the SIMD width of the build, 1 one at a time
        (a plugin, or a model file of a dimension without fixed-size states in this build, runs
        one at a time). Results never depend on it.
    <jobs>

    Returns
    -------
    Sweep
        Per run (job order): ``branch``, ``value``, ``label``, ``period``, ``impacts``,
        ``impacts_by_surface`` (runs, surfaces), ``closure``, ``outcome``, ``grazing`` (runs,
        surfaces), ``final_state`` (runs, dim), ``steps``; all section points ``points``
        (P, dim) with ``point_run``; ``stats``; ``jobs`` (JobReport). A shard whose partners
        have not finished returns only the JobReport.

    Examples
    --------
    >>> s = vimpact.sweep(vimpact.Model("wake_impact"), "Ur", vimpact.grid(15, 20, 6))
    >>> s.label.tolist()
    ['P2', 'P2', 'P2', 'P3', 'P3', 'P3']
    """
    model = _model(model)
    gparam = (_default_gap_parameter(model) if grazing is True else (grazing or None))
    if grazing is True and gparam is None:
        raise InputError(f"grazing: no parameter of model {model.name} moves a surface without entering the "
                         f"vector field")
    o = _protocol(model, section, declared, param=param, values=np.asarray(values, dtype=float), ic=_ic(ic),
                  grazing=gparam)
    o.update(_jobs(threads, journal, resume, shard, progress, keep_journal))
    o["batch"] = int(batch)
    d, report = _run_jobs(lambda: _vimpact._sweep(model._handle, o), o)
    if d is None:
        return report
    r = d["records"]
    return Sweep.of(r, _context(model, _result_options(ic, o, "values")), param=param, values=np.array(o["values"]),
                    ic_mode=declared["ic_mode"], direction=declared["direction"], tol=declared["tol"],
                    grazing_param=gparam,
                    stats=_job_stats(d, report, steps=int(r["stats"]["steps"].sum()),
                                     rhs_calls=int(r["stats"]["rhs_calls"].sum())),
                    jobs=report)


def _axis(axis, what):
    try:
        if isinstance(axis, str):
            raise TypeError
        name, values = axis
    except (TypeError, ValueError):
        raise TypeError(f"{what} must be a pair (name, values), e.g. ('Ur', vimpact.grid(16, 25, 10))") from None
    return str(name), np.asarray(values, dtype=float)


@_with_defaults
@_declares("map", "protocol")
def map(model, x, y, ic=None, *, section=None, threads=_D["threads"], batch=0, journal=None, resume=False, shard=None,
        progress=None, keep_journal=False, declared):
    """Periodicity map: the period label over a grid of two parameters.

    Every cell runs the protocol from the same ``ic`` on the model with both parameters set
    (one job each, threaded and deterministic, see ``sweep``).

    Parameters
    ----------
    model : Model
    x, y : (str, array_like)
        The parameters on the axes and their values, e.g. ``("Ur", vimpact.grid(16, 25, 10))``.
    ic : array_like, shape (dim,), optional
        Initial state; default ``model.default_ic``. It must be admissible at every cell.
    <declared>
    <section>
    <protocol>
    batch : int, default 0
        Jobs integrated together in SIMD lanes: 0 the SIMD width of the build, 1 one at a time
        (a plugin, or a model file of a dimension without fixed-size states in this build, runs
        one at a time). Results never depend on it.
    <jobs>

    Returns
    -------
    Map
        ``label``, ``period``, ``impacts``, ``closure``, ``outcome``, ``steps`` of shape
        (ny, nx) (``[iy, ix]``), ``impacts_by_surface`` (ny, nx, surfaces); with grazing
        ``grazing_param``, ``grazing_other`` (k,), ``grazing`` (k, surfaces) and
        ``switch_grazing`` (k, switches); ``jobs``.
    """
    model = _model(model)
    xname, xs = _axis(x, "x")
    yname, ys = _axis(y, "y")
    o = _protocol(model, section, declared, x=xname, x_values=xs, y=yname, y_values=ys, ic=_ic(ic))
    o.update(_jobs(threads, journal, resume, shard, progress, keep_journal))
    o["batch"] = int(batch)
    d, report = _run_jobs(lambda: _vimpact._map(model._handle, o), o)
    if d is None:
        return report
    axis = d["grazing_axis"]
    return Map.of(d["records"], _context(model, _result_options(ic, o, "x_values", "y_values")), x=xname, y=yname,
                  x_values=xs.copy(), y_values=ys.copy(), tol=declared["tol"],
                  grazing_param=None if axis < 0 else (yname if axis == 1 else xname),
                  grazing_other=None if axis < 0 else d["grazing_other"], grazing=None if axis < 0 else d["grazing"],
                  switch_grazing=None if axis < 0 else d["switch_grazing"], stats=_job_stats(d, report), jobs=report)


@_with_defaults
@_declares("basins", "protocol")
def basins(model, x, y, ic=None, *, section=None, threads=_D["threads"], batch=0, journal=None, resume=False,
           shard=None, progress=None, keep_journal=False, declared):
    """Basins of attraction: the attractor reached from every initial state of a grid.

    The grid spans two state variables; the others are taken from ``ic``. Every admissible
    start runs the protocol (one job each, threaded and deterministic); two runs reached the
    same attractor when they carry the same label and, if periodic, the same cycle of section
    points within ``match_tol`` (in any cyclic order), or, if aperiodic, bounding boxes of
    their section points that agree within ``box_fraction`` of their extent. Attractors are
    numbered in order of first appearance (job order). Starts beyond a surface are
    ``inadmissible`` (attractor -1).

    Parameters
    ----------
    model : Model
    x, y : (str, array_like)
        The state variables on the axes and their values, e.g. ``("y", vimpact.grid(-0.2,
        0.2, 41))``.
    ic : array_like, shape (dim,), optional
        The other components of the starts; default ``model.default_ic``.
    <declared>
    <section>
    <protocol>
    batch : int, default 0
        Jobs integrated together in SIMD lanes: 0 the SIMD width of the build, 1 one at a time
        (a plugin, or a model file of a dimension without fixed-size states in this build, runs
        one at a time). Results never depend on it.
    <jobs>

    Returns
    -------
    Basins
        ``attractor`` (ny, nx) int64, ``label``, ``period``, ``settled``, ``outcome``, ``steps`` (ny, nx),
        ``attractors`` (list of Attractor: id, label, cells, cycle, box), ``jobs``.
    """
    model = _model(model)
    xname, xs = _axis(x, "x")
    yname, ys = _axis(y, "y")
    o = _protocol(model, section, declared, x=xname, x_values=xs, y=yname, y_values=ys, ic=_ic(ic))
    o.update(_jobs(threads, journal, resume, shard, progress, keep_journal))
    o["batch"] = int(batch)
    d, report = _run_jobs(lambda: _vimpact._basins(model._handle, o), o)
    if d is None:
        return report
    attractors = [Attractor(id=a["id"], label=a["label"], cells=a["cells"], cycle=a["cycle"], box=a["box"])
                  for a in d["attractors"]]
    return Basins.of(d["records"], _context(model, _result_options(ic, o, "x_values", "y_values")), x=xname,
                     y=yname, x_values=xs.copy(), y_values=ys.copy(), tol=declared["tol"],
                     match_tol=declared["match_tol"], attractors=attractors, stats=_job_stats(d, report), jobs=report)


@_with_defaults
@_declares("response")
def response(model, param, values, ic=None, *, curves=None, variable=None, grazing=True, rtol=_D["grazing_rtol"],
             atol=_D["grazing_atol"], method=_D["method"], threads=_D["threads"], journal=None, resume=False,
             shard=None, progress=None, keep_journal=False, declared):
    """The surface-free response over a parameter (lock-in curves, the paper's Figure 10a, b).

    One job per (curve, value) (threaded, deterministic, see ``sweep``). Each runs the
    surface-free system as ``grazing`` does and measures, over the last block of minima, the
    largest and smallest extremum of ``variable``, its amplitude max(|max|, |min|) and its
    angular frequency, and for each surface its grazing value (or margin).

    Parameters
    ----------
    model : Model
    param : str
        The parameter to vary; it must enter the vector field (a parameter that only moves a
        surface does not change the surface-free response).
    values : array_like, shape (n,)
    ic : array_like, shape (dim,), optional
        Initial state; default ``model.default_ic``.
    curves : list of dict, optional
        One curve per dict of parameter values, e.g. ``[{"A": 12, "eps": 0.3}, {"A": 14,
        "eps": 0.35}]``; default one curve at the model's values.
    variable : str, optional
        The state variable measured; default the model's first (``model.state_names[0]``).
    grazing : bool or str, default True
        Per surface, the grazing value of this parameter, or with True of the first
        parameter that moves a surface (none: the margin); with False the margin, the smallest
        gap.
    <declared>
    rtol, atol, method
        As for ``grazing`` (defaults $grazing_rtol, $grazing_atol, $method).
    <jobs>

    Returns
    -------
    Response
        ``values`` (n,), ``curves``; per curve and value, shape (c, n): ``amplitude``,
        ``maximum``, ``minimum``, ``frequency`` (float64), ``converged`` (bool), ``outcome``
        (str), ``steps`` (int64); ``grazing`` and ``margin`` (c, n, surfaces); ``jobs``.
    """
    model = _model(model)
    var = model.state_names[0] if variable is None else variable
    gparam = _default_gap_parameter(model) if grazing is True else (grazing or None)
    if gparam == param:
        gparam = None
    if curves is not None and (isinstance(curves, (str, dict)) or
                               not all(isinstance(c, collections.abc.Mapping) for c in curves)):
        raise TypeError("curves must be a list of dicts of parameter values, e.g. [{'A': 12, 'eps': 0.3}]")
    cs = [{}] if curves is None else [dict(c) for c in curves]
    for c in cs:
        for k, v in c.items():
            if isinstance(v, bool) or not isinstance(v, (int, float, np.number)):
                raise TypeError(f"curves: the value of {k} must be a number (got {type(v).__name__})")
    vals = np.asarray(values, dtype=float)
    o = dict(declared, param=param, values=vals, curves=[{k: float(v) for k, v in c.items()} for c in cs],
             variable=var, ic=_ic(ic), grazing=gparam, rtol=rtol, atol=atol, method=method)
    o.update(_jobs(threads, journal, resume, shard, progress, keep_journal))
    d, report = _run_jobs(lambda: _vimpact._response(model._handle, o), o)
    if d is None:
        return report
    ctx = _context(model, _result_options(ic, o, "values"))
    ctx["plot_variable"] = var
    return Response.of(d["records"], ctx, param=param, values=vals.copy(), curves=o["curves"], variable=var,
                       grazing_param=gparam, stats=_job_stats(d, report), jobs=report)


@_with_defaults
@_declares("clearance", "protocol")
def clearance(model=None, param=None, values=None, ic=None, *, units=None, speeds=None, gaps=None, fractions=None,
              gap_param=None, section=None, threads=_D["threads"], journal=None, resume=False, shard=None, progress=None, keep_journal=False,
              declared):
    """Clearance design: the smallest gap to a surface without impact over a range of flow
    speeds (or of any parameter), the gaps where the response is aperiodic, and a design chart.

    At each value one job of the library's job loop runs the grazing analysis (surface-free,
    ``grazing``) for the gap parameter's surface: the clearance is the gap from the rest state
    to the surface at grazing (``-sigma_graze`` for the wake model; a surface farther away is
    never hit by the surface-free orbit). Then the protocol runs at each gap of the chart and
    labels the regime (P0 no impact, PN, aperiodic) with the impact statistics.

    Parameters
    ----------
    model : Model, optional
        Default the wake model; ``units`` with a cylinder sets its mu, xi, St.
    param : str, optional
        The flow parameter (any model), with ``values`` (model units); or give ``speeds``.
    values : array_like, shape (n,), optional
    ic : array_like, shape (dim,), optional
        The runs' initial state; default ``model.default_ic``.
    units : PhysicalUnits, optional
        SI inputs (a cylinder, or the model's units): gaps and results in SI.
    speeds : array_like, optional
        Flow speeds [m/s] (needs a cylinder in ``units``): the values of ``Ur``.
    gaps : array_like, optional
        The chart's gaps [m with ``units``, else model units]; default: ``fractions`` of each
        value's clearance.
    fractions : array_like, optional
        Default 0.1, 0.2, ..., 1.3.
    gap_param : str, optional
        The parameter that moves the surface (default the model's first: ``sigma``).
    <declared>
    <section>
    <protocol>
    <jobs>

    Returns
    -------
    Clearance
        ``clearance`` (n,) and ``clearance_si`` [m], ``aperiodic`` (n, 2), the chart ``gap``,
        ``label``, ``statistics`` (n, k) and their SI forms; a JobReport for an incomplete shard.

    Examples
    --------
    >>> u = vimpact.PhysicalUnits(D=0.02, m=0.6, fn=12, zeta=0.002, rho=1000)
    >>> c = vimpact.clearance(units=u, speeds=vimpact.grid(3, 6, 7))
    >>> c.clearance_si          # metres, one per speed
    """
    model = _model(model) if model is not None else Model("wake_impact")
    if units is not None and not isinstance(units, PhysicalUnits):
        raise TypeError(f"units must be a vimpact.PhysicalUnits (got {type(units).__name__})")
    if units is not None:
        if "U" in units.inputs or "gap" in units.inputs:
            raise InputError("clearance takes the speeds from speeds= and scans the gaps: leave U and gap out of units")
        model = units.model(model)
    if (speeds is None) == (param is None or values is None):
        raise InputError("clearance needs either speeds= (m/s, with a cylinder in units=) or param= with values=")
    speed = None
    if speeds is not None:
        if units is None or not units.cylinder:
            raise InputError("speeds= needs a cylinder in units= (D, m, fn, zeta, rho)")
        speed = np.asarray(speeds, dtype=float)
        pairs = [units.parameter("U", u, model) for u in speed]
        param, values = (pairs[0][0] if pairs else "Ur"), np.array([v for _, v in pairs], dtype=float)
    values = np.asarray(values, dtype=float)
    o = _protocol(model, section, declared, param=param, values=values, ic=_ic(ic), gap_param=gap_param,
                  gaps=None if gaps is None else np.asarray(gaps, dtype=float),
                  units=None if units is None else units._handle,
                  fractions=None if fractions is None else np.asarray(fractions, dtype=float))
    o.update(_jobs(threads, journal, resume, shard, progress, keep_journal))
    d, report = _run_jobs(lambda: _vimpact._clearance(model._handle, o), o)
    if d is None:
        return report
    warnings = []
    if units is not None:
        for v in d["records"]["value"]:
            warnings += [w for w in units.warnings(model.with_(**{param: v})) if w not in warnings]
    opts = _result_options(ic, o, "values", "gaps", "fractions", "units")
    if units is not None:
        opts["units"] = units.inputs
    return Clearance.of(d, d.get("si"), param=param, x="U" if speed is not None else param, gap_param=d["gap_param"],
                        surface=d.get("surface"), switch=d.get("switch"), speed=speed, warnings=tuple(warnings), stats=_job_stats(d, report),
                        jobs=report, **_context(model, opts))


def cylinder_units(D, m=None, fn=None, zeta=None, rho=None, U=None, CM=1.0, St=0.2, *, mstar=None, k=None,
                   nu=None):
    """A cylinder in a flow, in SI units, as the wake model's dimensionless parameters.

    The conversion of Facchinetti, de Langre & Biolley (2004), the model ``wake_impact`` builds
    on (``vimpact units`` on the command line; docs/engineering.md)::

        Ur = U / (fn D)
        mu = (m + m_f) / (rho D^2),  m_f = CM rho pi D^2 / 4   (added mass)
        xi = zeta                     (damping ratio from a free decay in still fluid)

    and the model's units: length D, time 1 / Omega_f with Omega_f = 2 pi St U / D.

    Parameters
    ----------
    D : float       diameter [m]
    m : float       structural mass per unit length [kg/m]; or ``mstar``
    fn : float      natural frequency in still fluid [Hz]; or ``k``
    zeta : float    structural damping ratio
    rho : float     fluid density [kg/m^3]
    U : float       flow speed [m/s]
    CM : float      added-mass coefficient (1)
    St : float      Strouhal number (0.2)
    mstar : float   instead of ``m``: the mass ratio m / (rho pi D^2 / 4)
    k : float       instead of ``fn``: stiffness per unit length [N/m^2],
                    fn = sqrt(k / (m + m_f)) / (2 pi)
    nu : float      kinematic viscosity for ``Re`` [m^2/s] (1e-6, water)

    Returns
    -------
    dict
        ``U``, ``Ur``, ``mu``, ``xi``, ``St`` (pass ``mu``, ``xi``, ``St`` and ``Ur`` to
        ``Model("wake_impact", ...)``), the SI value of one model unit: ``time_scale`` [s],
        ``length_scale`` [m], ``velocity_scale`` [m/s], ``frequency_scale`` [Hz] (of a
        dimensionless angular frequency), ``Re`` and ``mass_ratio``.
    """
    if U is None:
        raise InputError("U (flow speed, m/s) is required")
    try:
        U = float(U)
    except (TypeError, ValueError):
        raise InputError(f"U must be a number (got {U!r})") from None
    keys = dict(D=D, m=m, mstar=mstar, fn=fn, k=k, zeta=zeta, rho=rho, CM=CM, St=St, nu=nu)
    return PhysicalUnits(**keys)._handle.at(U)


def grid(a, b, n):
    """n values from a to b inclusive, evenly spaced, as the command line's range ``a:b:n``.

    Value i is a + i (b - a)/(n - 1), the last is b exactly: the values of
    ``vimpact sweep --range a:b:n`` bit for bit (``numpy.linspace`` rounds differently).

    Returns
    -------
    ndarray, float64, shape (n,)
    """
    return _vimpact.grid(float(a), float(b), int(n))


# ---------------------------------------------------------------- stability

def _floquet_options(model, declared, sample_dt, tangent_rtol, tangent_atol, section):
    return _protocol(model, section, declared, sample_dt=sample_dt, tangent_rtol=tangent_rtol,
                     tangent_atol=tangent_atol)


@_with_defaults
@_declares("floquet", "protocol")
def floquet(model, ic=None, *, sample_dt=0.0, tangent_rtol=_D["tangent_rtol"], tangent_atol=_D["tangent_atol"],
            section=None, declared):
    """Floquet multipliers of the periodic orbit reached from ``ic`` (the paper's Algorithm 1).

    1. The protocol (see ``simulate``; on a section crossing) and its period label, as
       ``period``. An aperiodic or failed run stops here: no multipliers.
    2. Newton shooting on P^k(z) = z, k the section returns per period, from the first
       recorded point, until the closure |P^k(z) - z|_inf <= ``newton_tol``.
    3. The monodromy Phi(T) = Phi_n S_n ... S_1 Phi_1 over one period from the refined point:
       the variational flow between impacts, the saltation matrix
       S = R' + (F+ - R' F) grad(g)^T / (grad(g) . F) at each impact (Eq. 8).
    4. The multipliers are its eigenvalues; the trivial one (for the flow direction) is 1 up
       to the accuracy of the monodromy and comes first.

    Parameters
    ----------
    model : Model
    ic : array_like, shape (dim,), optional
        Initial state; default ``model.default_ic``.
    <declared>
    sample_dt : float, default 0
        > 0: also sample the refined orbit over one period (``orbit``).
    tangent_rtol, tangent_atol : float, default $tangent_rtol, $tangent_atol
        Tolerances of the tangent runs (Newton closes the orbit only as far as they allow).
    <section>
    <protocol>

    Returns
    -------
    Floquet
        ``status``, ``label``, ``period``, ``multipliers`` (dim,) complex128 (trivial first),
        ``monodromy`` (dim, dim), ``orbit_point`` (dim,), ``stable``, ``closure``, ...

    Examples
    --------
    >>> f = vimpact.floquet(vimpact.Model("wake_impact", Ur=16))
    >>> f.label, f.stable
    ('P2', True)
    """
    model = _model(model)
    o = _floquet_options(model, declared, sample_dt, tangent_rtol, tangent_atol, section)
    d = _vimpact._floquet(model._handle, _ic(ic), o)
    record = d.pop("record")
    stats = dict(protocol=RunStats.from_dict(record.pop("protocol_stats")),
                 tangent=RunStats.from_dict(record.pop("tangent_stats")), map_evaluations=record.pop("map_evaluations"))
    return Floquet(**d, record=record, stats=stats, **_context(model, _options(ic, **o)))


def _lyapunov_options(declared, record, section):
    return dict(declared, record=record, section=section)


@_with_defaults
@_declares("lyapunov", "protocol", without=("record",))
def lyapunov(model, ic=None, *, record=0, section=None, declared):
    """The Lyapunov spectrum of the attractor reached from ``ic`` (the paper's Algorithm 2).

    After ``transient`` impacts, dim deviation vectors of size ``r0`` follow the orbit; every
    ``t0`` they are re-orthonormalised by a QR decomposition and ln(R_ii / r0) is accumulated.
    After ``warmup`` intervals (not counted) the averages over the next ``impacts`` impacts
    (the paper: 800), or over ``time``, are the exponents, in descending order (Eq. 13). Their
    sum must equal <div F> + (1/T) sum ln|det S| (``sum_rule``).

    Parameters
    ----------
    model : Model
    ic : array_like, shape (dim,), optional
        Initial state; default ``model.default_ic``.
    <declared>
    record : int, default 0
        > 0: also record this many section points in the averaging window (``section``).
    section : str, optional
        The section crossing those points lie on (default the model's first).
    <protocol>

    Returns
    -------
    Lyapunov
        ``exponents`` (dim,) float64, ``lle``, ``lle_standard_error``, ``sum_rule``,
        ``history_t`` (h,) and ``history_growth`` (h, dim), ``running_exponents``, ``status``.
    """
    model = _model(model)
    o = _lyapunov_options(declared, record, section)
    d = _vimpact._lyapunov(model._handle, _ic(ic), o)
    record = d.pop("record")
    stats = dict(transient=RunStats.from_dict(record.pop("transient_stats")),
                 tangent=RunStats.from_dict(record.pop("stats")))
    return Lyapunov(**d, record=record, stats=stats, **_context(model, _options(ic, **o)))


def _per_value(call, cls, model, param, values, ic, o, jobs, **run):
    """Runs ``call`` (a compiled stability sweep) over the values as jobs: a result of ``cls``
    made of its records, or the JobReport alone when the run is not complete."""
    o.update(param=param, values=np.asarray(values, dtype=float), ic=_ic(ic), **jobs)
    d, report = _run_jobs(lambda: call(model._handle, o), o)
    if d is None:
        return report
    return cls.of(d["records"], _context(model, _result_options(ic, o, "values")), param=param,
                  stats=_job_stats(d, report), jobs=report, **run)


@_with_defaults
@_declares("floquet", "protocol")
def floquet_sweep(model, param, values, ic=None, *, tangent_rtol=_D["tangent_rtol"], tangent_atol=_D["tangent_atol"],
                  section=None, threads=_D["threads"], journal=None, resume=False, shard=None, progress=None,
                  keep_journal=False, declared):
    """Floquet multipliers at every value of one parameter (the paper's Figures 14, 15).

    <per_value>
    <declared>
    tangent_rtol, tangent_atol
        As for ``floquet`` (defaults $tangent_rtol, $tangent_atol).
    <section>
    <protocol>
    <jobs>

    Returns
    -------
    FloquetSweep
        ``value`` (n,), ``results`` (a Floquet per value), ``label`` (n,), ``multipliers``
        (n, dim) complex128 (NaN rows without), ``stable``, ``points``/``point_run`` (the
        section points underneath), ``jobs``.
    """
    model = _model(model)
    o = _floquet_options(model, declared, 0.0, tangent_rtol, tangent_atol, section)
    return _per_value(_vimpact._floquet_sweep, FloquetSweep, model, param, values, ic, o,
                      _jobs(threads, journal, resume, shard, progress, keep_journal))


@_with_defaults
@_declares("lyapunov", "protocol", without=("record",))
def lyapunov_sweep(model, param, values, ic=None, *, record=0, section=None, threads=_D["threads"], journal=None,
                   resume=False, shard=None, progress=None, keep_journal=False, declared):
    """Lyapunov exponents at every value of one parameter (the paper's Figures 16, 17).

    <per_value>
    <declared>
    section : str, optional
        As for ``lyapunov`` (the model's first section).
    record : int, default 0
        > 0: section points per value in the averaging window (the diagram underneath).
    <protocol>
    <jobs>

    Returns
    -------
    LyapunovSweep
        ``value`` (n,), ``results`` (a Lyapunov per value), ``exponents`` (n, dim), ``lle``,
        ``lle_standard_error``, ``status``, ``points``/``point_run``, ``jobs``.
    """
    model = _model(model)
    o = _lyapunov_options(declared, record, section)
    return _per_value(_vimpact._lyapunov_sweep, LyapunovSweep, model, param, values, ic, o,
                      _jobs(threads, journal, resume, shard, progress, keep_journal), tdm=declared["tdm"])


# ---------------------------------------------------------------- correlation dimension

def _points_of(points, columns):
    """An array of points, or a result's section points in the library's coordinates of a
    state (every state variable; a phase as its NAME_cos, NAME_sin pair), the columns the
    command line's ``dimension`` takes: all of them, or those named."""
    if hasattr(points, "section") and isinstance(getattr(points, "model", None), Model):
        names, coords = _vimpact._state_points(points.model._handle, np.asarray(points.section, dtype=float))
        if columns is None:
            columns = tuple(names)
        missing = [c for c in columns if c not in names]
        if missing:
            raise InputError(f"columns: no coordinate {missing[0]!r} (coordinates: {', '.join(names)})")
        return coords[:, [names.index(c) for c in columns]], tuple(columns)
    if columns is not None:
        raise TypeError("columns names state variables of a result (a Simulation, say), not of an array")
    return np.asarray(points, dtype=float), None


@_with_defaults
@_declares("dimension")
def dimension(points, *, columns=None, radii=_D["radii"], fit_range=None, threads=1, declared):
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
    points : array_like, shape (n, d), or a result with section points
        One point per row; or a Simulation (Period, ...) whose ``section`` points are used.
    columns : sequence of str, optional
        With a result: the coordinates to use, among the model's state variables (a phase as
        its NAME_cos, NAME_sin pair); default all of them, as the command line does (a
        coordinate constant on the section, ydot on the maxima, adds nothing to a distance).
    radii : (float, float, float), default $radii
        Centres estimator: r_min, r_max, step (the paper's).
    fit_range : (float, float), optional
        Fit over [r_min, r_max] instead of the automatic scaling region.
    <declared>
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
    pts, cols = _points_of(points, columns)
    fr = None if fit_range is None else (float(fit_range[0]), float(fit_range[1]))
    d = _vimpact._dimension(pts, declared, tuple(float(v) for v in radii), fr, threads)
    opts = dict(declared, radii=tuple(radii), fit_range=fr)
    return Dimension(**_picked(Dimension, d), columns=cols, options=opts)


@_with_defaults
@_declares("continuation", "protocol")
def continuation(model, param, range, ic=None, *, starts=None, param2=None, range2=None,
                 curves=("fold", "period_doubling", "grazing"), threads=_D["threads"], section=None, declared):
    """Continuation of periodic orbits in one parameter, stable and unstable, with their
    bifurcations; optionally the curves of the bifurcation points in a second parameter.

    A periodic orbit that crosses the section k times per period is a zero of
    G(z, p) = P^k(z; p) - z in the section's chart coordinates z. From the start, the branch of
    zeros is followed by pseudo-arclength continuation (a predictor along the tangent, Newton's
    method on (z, p) in the plane normal to it, an adaptive step), through folds and onto
    unstable parts, each point closed to ``closure_tol`` with all its Floquet multipliers
    (saltation matrices at the impacts). Folds (a multiplier through +1), period doublings
    (through -1) and Neimark-Sacker points (a complex pair through the unit circle) are located
    by test functions to ``locate_tol`` in the parameter; a grazing (an impact velocity or a gap
    minimum reaching 0), where the impact sequence changes, is located on the family without
    the grazing impact, and the branch turns there onto the other family (or ends). Where the
    section point meets an impact (a stroboscopic section at the phase of an impact) the branch
    goes on from the orbit's other state at the section. Each branch says why it ended
    (``Branch.end``, and in words with the parameter value ``Branch.end_reason``).

    Parameters
    ----------
    model : Model
    param : str
        The parameter continued.
    range : (float, float)
        ``(a, b)``: the branch starts at a and runs towards b; it ends where the parameter
        leaves [a, b].
    ic : array_like, shape (dim,), optional
        With ``period`` 0: the initial state of the protocol whose attractor at a starts the
        branch (default ``model.default_ic``). Else a point near the orbit on the section.
    starts : list of array_like, optional
        Further initial states, each giving a branch (the same orbit found twice is kept once).
    param2 : str, optional
        Two-parameter mode: every located bifurcation of the types in ``curves`` is followed in
        (param, param2).
    range2 : (float, float)
        The range of ``param2``; the model's value of it must lie inside.
    curves : sequence of str, default ("fold", "period_doubling", "grazing")
    <declared>
    threads : int, default $threads
        Worker threads for several starts, switched branches and curves; results never depend
        on it.
    <section>
    <protocol>

    Returns
    -------
    Continuation
        ``branches`` (Branch: ``param``, ``state``, ``sections``, ``stable``, ``multipliers``,
        ``period``, ``impacts``, ...), ``bifurcations`` (Bifurcation: ``type``, ``param``,
        ``branch``, ``state``, ``multipliers``, ...), ``curves`` (Curve: ``param``, ``param2``,
        ...). ``vimpact.plot.continuation(result)`` draws it.

    Examples
    --------
    >>> c = vimpact.continuation(vimpact.Model("wake_impact"), "Ur", (14, 16), switch=1)
    >>> [(b.type, round(b.param, 6)) for b in c.bifurcations][:2]
    [('period_doubling', 15.018158), ('grazing', 14.751445)]
    """
    model = _model(model)
    a, b = (float(v) for v in range)
    o = _protocol(model, section, declared, param=str(param), start=a, end=b, threads=int(threads))
    if param2 is not None or range2 is not None:
        if param2 is None or range2 is None:
            raise InputError("param2 and range2 go together")
        lo2, hi2 = sorted(float(v) for v in range2)
        o.update(param2=str(param2), lo2=lo2, hi2=hi2, curves=[str(c) for c in curves])
    xs = [_ic(ic)] + [_ic(x) for x in (starts or [])]
    d = json.loads(_vimpact._continuation(model._handle, xs, o))
    return Continuation.from_json(d, **_context(model, _options(ic, **o)))
