"""SI units both ways: an engineer's inputs to a model's dimensionless parameters, and the
model's results back to metres, seconds, hertz, joules and watts (the library's
physical/si_units.hpp; docs/engineering.md has every formula and its source)."""
import numpy as np

from . import _vimpact
from ._model import Model
from ._vimpact import InputError


class PhysicalUnits:
    """SI inputs for a model: a cylinder in a flow for the wake model, or the SI value of one
    model unit for any model; optionally a flow speed and a gap.

    Parameters (keyword only; the keys of the command line's ``--si``)
    ----------
    D, m, fn, zeta, rho : float
        A cylinder in a flow: diameter [m], structural mass per unit length [kg/m], natural
        frequency in still fluid [Hz], structural damping ratio (free decay in still fluid),
        fluid density [kg/m^3]. Optional ``CM`` (added-mass coefficient, 1), ``St`` (0.2),
        ``nu`` (kinematic viscosity for the Reynolds number, 1e-6 m^2/s: water), ``CL0`` (the
        wake model's lift coefficient; default the model's own, 0.31583 for the paper's
        preset, 0.3 for ``facchinetti``).
    mstar, k : float
        Instead of ``m``: the mass ratio ``m / (rho pi D^2 / 4)``; instead of ``fn``: the
        stiffness per unit length [N/m^2], ``fn = sqrt(k / (m + m_f)) / (2 pi)`` with the added
        mass ``m_f = CM rho pi D^2 / 4``. Exactly one of ``m``, ``mstar`` and one of ``fn``,
        ``k``.
    length, time, mass : float
        Instead of a cylinder, for any model: one model unit of length [m], time [s] and mass
        [kg] (mass 1 when left out: energies per kilogram).
    U : float, optional
        The flow speed [m/s] (with a cylinder): sets ``Ur``.
    gap : float, optional
        [m] The distance from the rest state (the model's initial state) to the surface moved
        by the model's first gap parameter: sets it (``sigma = -gap / D`` for the wake model).

    Examples
    --------
    >>> u = vimpact.PhysicalUnits(D=0.02, m=0.6, fn=12, zeta=0.002, rho=1000, U=4, gap=0.003)
    >>> model = u.model(vimpact.Model("wake_impact"))      # SI -> model
    >>> round(model.parameters["Ur"], 4), model.parameters["sigma"]
    (16.6667, -0.15)
    >>> u.flow_speed(model), u.gap(model)                  # model -> SI
    (4.0, 0.003)
    """

    def __init__(self, **values):
        pairs = []
        for k, v in values.items():
            if v is None:
                continue
            try:
                pairs.append((str(k), float(v)))
            except (TypeError, ValueError):
                raise InputError(f"{k} must be a number (got {v!r})") from None
        try:
            self._handle = _vimpact._SIUnits(pairs)
        except InputError as e:
            raise InputError(f"PhysicalUnits: {e}") from None

    def __repr__(self):
        return "PhysicalUnits(" + ", ".join(f"{k}={v:g}" for k, v in self.inputs.items()) + ")"

    @property
    def inputs(self):
        """dict: the inputs by key, defaults filled in (``m`` and ``fn`` computed when ``mstar``
        and ``k`` were given)."""
        return dict(self._handle.inputs)

    @property
    def cylinder(self):
        """bool: a cylinder in a flow (else the model's units were given)."""
        return self._handle.cylinder

    @staticmethod
    def _model(model):
        if model is None:
            return Model("wake_impact")
        if not isinstance(model, Model):
            raise TypeError(f"model must be a vimpact.Model (got {type(model).__name__})")
        return model

    def model(self, model=None):
        """SI -> model: ``model`` (default the wake model) with the parameters the inputs set."""
        m = self._model(model)
        return Model._wrap(self._handle.apply(m._handle), m._origin, m._info)

    def parameters(self, model=None):
        """dict: the model parameters the inputs set (name -> dimensionless value)."""
        return dict(self._handle.parameters(self._model(model)._handle))

    def parameter(self, quantity, value, model=None):
        """An SI quantity's model parameter: ``("Ur", 16.67)`` for ``("U", 4.0)``,
        ``("sigma", -0.15)`` for ``("gap", 0.003)``."""
        return tuple(self._handle.parameter(self._model(model)._handle, str(quantity), float(value)))

    def flow_speed(self, model):
        """Model -> SI: the flow speed [m/s] of the model's Ur (NaN without a cylinder)."""
        return self._handle.flow_speed(self._model(model)._handle)

    def gap(self, model):
        """Model -> SI: the gap [m] from the rest state to the surface of the model's gap parameter."""
        return self._handle.gap(self._model(model)._handle)

    def values(self, model):
        """dict: at the model's parameters, U, Re, mass_ratio and CL0 (a cylinder), gap, and one
        model unit in SI: length_scale [m], time_scale [s], mass_scale, velocity_scale [m/s],
        energy_scale, power_scale."""
        return dict(self._handle.values(self._model(model)._handle))

    @property
    def length_scale(self):
        """One model unit of length [m]."""
        return self._handle.length_scale()

    def warnings(self, model):
        """list of str: where a cylinder leaves the wake model's calibrated range (Reynolds
        number, mass ratio) at the model's flow speed."""
        return list(self._handle.warnings(self._model(model)._handle))

    def statistics(self, result, model=None):
        """A run's impact statistics in SI: rate [Hz], velocities [m/s], energy per impact [J; J/m
        for a cylinder], power [W; W/m], excursion [m], duration [s].

        ``result`` is a Simulation or Period (its ``statistics`` and model) or a statistics dict
        (then give ``model``)."""
        sim = getattr(result, "simulation", result)
        stats = getattr(sim, "statistics", result)
        m = model if model is not None else getattr(sim, "model", None)
        if not isinstance(stats, dict) or m is None:
            raise TypeError("statistics: a Simulation or Period, or a statistics dict with model=")
        clean = {k: (np.nan if v is None else v) for k, v in stats.items()}
        return dict(self._handle.statistics(self._model(m)._handle, clean))


def impact_statistics_names():
    """The names of the impact statistics, in the library's order (JSON keys, CSV columns)."""
    return tuple(_vimpact._impact_statistics_names())
