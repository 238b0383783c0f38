"""Steppable systems: a model's hybrid flow, section map and tangent as objects to step.

Each holds a state (numpy array) and a time, moves by ``step`` (and ``advance_to`` in
continuous time), starts again by ``reinit``, and takes a new parameter value by
``set_parameter``: a new analysis is a loop of a few lines. The library's own analyses drive
the same flow (include/vimpact/system/). Bad input raises ValueError (``vimpact.InputError``);
numerical trouble is the ``status``: ``"ok"`` while the system can go on, else why it stopped
(``"non_finite"``, ``"chattering"``, ``"step_limit"``, ``"interrupted"`` after Ctrl-C, ...),
after which it stays until ``reinit``.
"""
import numpy as np

from . import _vimpact
from ._model import Model
from .results import RunStats

_D = _vimpact.defaults


def _model(model):
    if not isinstance(model, Model):
        raise TypeError(f"model must be a vimpact.Model (got {type(model).__name__})")
    return model


def _ic(ic):
    return None if ic is None else np.asarray(ic, dtype=float)


class _System:
    """What the three systems share: state, time, status, stats, parameters."""

    def __init__(self, model, handle):
        self._model = model
        self._sys = handle

    @property
    def model(self):
        """The Model, with the parameter values set on the system."""
        return self._model

    @property
    def state(self):
        """The current state, float64 (dim,) (a copy)."""
        return self._sys.state

    @property
    def time(self):
        return self._sys.time

    @property
    def status(self):
        """``"ok"`` while the system can go on, else why it stopped."""
        return self._sys.status

    @property
    def stats(self):
        """The run's counters since the last (re)start (``vimpact.RunStats``)."""
        return RunStats.from_dict(self._sys.stats)

    @property
    def parameters(self):
        return dict(zip(self._model.parameter_names, self._sys.parameters))

    def set_parameter(self, name, value):
        """Parameter ``name`` to ``value`` (range-checked); the system goes on from its state."""
        names = self._model.parameter_names
        if name not in names:
            raise _vimpact.InputError(f"set_parameter: model {self._model.name} has no parameter '{name}' "
                                      f"(parameters: {', '.join(names)})")
        self._sys.set_parameter(names.index(name), float(value))
        self._model = self._model.with_(**{name: float(value)})


class HybridSystem(_System):
    """The hybrid flow of a model, in continuous time.

    Parameters
    ----------
    model : Model
    ic : array_like, shape (dim,), optional
        Initial state (default ``model.default_ic``); it must be admissible.
    t : float, default 0
        Initial time.
    rtol, atol, hold_band, method, t_max, max_steps
        The integration and its limits, as in ``vimpact.simulate``.

    ``step()`` takes one accepted integrator step (through any impact in it); ``step(dt)`` and
    ``advance_to(t)`` go to a time exactly. ``impacts`` holds the impacts of the last call:
    ``impact_t``, ``impact_surface``, ``impact_pre``, ``impact_post``; ``switchings`` its
    crossings of switches: ``switching_t``, ``switching_surface`` (an index into
    ``model.switches``), ``switching_pre``, ``switching_post``.

    Examples
    --------
    >>> s = vimpact.HybridSystem(vimpact.Model("wake_impact", Ur=19))
    >>> ys = [s.state[0] for _ in range(100) if s.step(0.1) == "ok"]
    """

    def __init__(self, model, ic=None, *, t=0.0, rtol=_D["rtol"], atol=_D["atol"], hold_band=_D["hold_band"],
                 method=_D["method"], t_max=np.inf, max_steps=None):
        model = _model(model)
        o = dict(rtol=rtol, atol=atol, hold_band=hold_band, method=method, t_max=t_max, max_steps=max_steps)
        super().__init__(model, _vimpact._HybridSystem(model._handle, _ic(ic), float(t), o))

    @property
    def impacts(self):
        return self._sys.impacts

    @property
    def switchings(self):
        return self._sys.switchings

    @property
    def in_contact(self):
        return self._sys.in_contact

    def step(self, dt=None):
        """One integrator step, or to ``time + dt`` exactly; returns the status."""
        if dt is None:
            return self._sys.step()
        dt = float(dt)
        if not dt >= 0:
            raise _vimpact.InputError(f"dt = {dt} is outside its valid range [0, inf)")
        return self._sys.advance_to(self.time + dt)

    def advance_to(self, t):
        """To time ``t`` (>= ``time``) exactly; returns the status."""
        return self._sys.advance_to(float(t))

    def reinit(self, ic, t=0.0):
        """Starts again at (t, ic), as a new system would (the same steps, to the bit)."""
        self._sys.reinit(_ic(ic), float(t))


class SectionSystem(_System):
    """The section map (Poincare map) or impact map of a model, in discrete time.

    Parameters
    ----------
    model : Model
    ic : array_like, shape (dim,), optional
    section : str, optional
        A section of the model (``model.sections``), ``"impacts"`` or ``"impacts:SURFACE"``
        (the state after each impact), as in ``vimpact.simulate``; default the model's first.
    t : float, default 0
    rtol, atol, hold_band, method, max_steps
        As in ``vimpact.simulate``.
    max_return_time : float, default 1e4
        A step that finds no crossing within this flight time ends with ``"time_limit"``.

    ``step(n)`` goes n crossings on; ``state`` and ``time`` are the last crossing's;
    ``impacts`` and ``switchings`` (crossings of switches) those since the previous one.
    """

    def __init__(self, model, ic=None, *, section=None, t=0.0, rtol=_D["rtol"], atol=_D["atol"],
                 hold_band=_D["hold_band"], method=_D["method"], max_return_time=1e4, max_steps=None):
        model = _model(model)
        o = dict(section=model._handle.default_section() if section is None else str(section), rtol=rtol, atol=atol,
                 hold_band=hold_band, method=method, max_return_time=max_return_time, max_steps=max_steps)
        super().__init__(model, _vimpact._SectionSystem(model._handle, _ic(ic), float(t), o))

    @property
    def impacts(self):
        return self._sys.impacts

    @property
    def switchings(self):
        return self._sys.switchings

    def step(self, n=1):
        """n crossings on (fewer if the system stops); returns the status."""
        return self._sys.step(int(n))

    def points(self, n):
        """The next n crossings: times (n,) and states (n, dim) (fewer if the system stops)."""
        ts, xs = [], []
        for _ in range(int(n)):
            if self._sys.step(1) != "ok":
                break
            ts.append(self.time)
            xs.append(self.state)
        return np.array(ts), np.array(xs).reshape(len(xs), self._model.dim)

    def reinit(self, ic, t=0.0):
        self._sys.reinit(_ic(ic), float(t))


class TangentSystem(_System):
    """A model's flow or section map with k deviation vectors carried by its tangent.

    Parameters
    ----------
    model : Model
    ic : array_like, shape (dim,), optional
    section : str, optional
        None: continuous time (``step()``, ``advance_to(t)``); a section of the model: discrete
        time, ``step(n)`` to the n-th next crossing, the deviations projected along the flow
        onto the section (from the identity, the Jacobian of the section map).
    deviations : int, optional
        k, 1..dim (default dim); they start as the identity's first k columns.
    t : float, default 0
    rtol, atol, hold_band, max_steps, max_return_time
        As in ``SectionSystem``; the tangent always integrates with DOP853, with error control
        over the deviations (keep them of order 1: re-orthonormalise).

    ``deviations`` is the (dim, k) matrix W: W = Phi W0, Phi the fundamental matrix since W0
    was set (``set_deviations`` or ``reinit``), the saltation matrix applied at each impact.
    A contact phase ends the system with status ``"sticking"`` (its tangent map is not
    implemented).
    """

    def __init__(self, model, ic=None, *, section=None, deviations=None, t=0.0, rtol=_D["rtol"], atol=_D["atol"],
                 hold_band=_D["hold_band"], max_return_time=1e4, max_steps=None):
        model = _model(model)
        o = dict(section=None if section is None else str(section), deviations=deviations, rtol=rtol, atol=atol,
                 hold_band=hold_band, max_return_time=max_return_time, max_steps=max_steps)
        super().__init__(model, _vimpact._TangentSystem(model._handle, _ic(ic), float(t), o))

    @property
    def deviations(self):
        """W, float64 (dim, k) (a copy)."""
        return self._sys.deviations

    @property
    def discrete(self):
        return self._sys.discrete

    def step(self, n=1):
        return self._sys.step(int(n))

    def advance_to(self, t):
        return self._sys.advance_to(float(t))

    def set_deviations(self, w):
        """New deviations (dim, k) at the current point."""
        self._sys.set_deviations(np.asarray(w, dtype=float))

    def reinit(self, ic, t=0.0, deviations=None):
        self._sys.reinit(_ic(ic), float(t), None if deviations is None else np.asarray(deviations, dtype=float))
