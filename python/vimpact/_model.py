"""vimpact.Model: one class for every impacting system the library runs.

A Model is an immutable value: the model's code (a built-in, a compiled model file, a plugin)
and one valid set of parameter values. The library checks every value against its range, so a
Model always holds a valid parameter set; ``with_`` and ``preset`` make changed copies.
"""
import json
import math
import numbers
import os

import numpy as np

from . import _vimpact
from ._vimpact import InputError

_MODEL_FILE_SUFFIXES = (".toml", ".json", ".so")


def _jsonable(value):
    # json.dumps calls this for what it cannot write itself: numpy numbers and arrays.
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise InputError(f"model description: a value of type {type(value).__name__} has no meaning in a model "
                     f"description (numbers, strings, lists and dicts only)")


def _load(origin):
    """The library's model for an origin (see Model.__reduce__)."""
    kind = origin[0]
    if kind == "builtin":
        return _vimpact._Model.builtin(origin[1])
    if kind == "file":
        return _vimpact._Model.from_file(origin[1])
    if kind == "toml":
        return _vimpact._Model.from_toml(origin[1], origin[2])
    return _vimpact._Model.from_json(origin[1], origin[2])


def _rebuild(origin, parameters):
    return Model._wrap(_load(origin), origin).with_parameters(parameters)


class Model:
    """An impacting system with its parameter values, the model every analysis takes.

    Parameters
    ----------
    source : str, path or dict, default "wake_impact"
        A built-in model's name (``Model.builtin_names()``: ``wake_impact``, the paper's
        model; ``forced_impact_oscillator``; ``two_sided_impact_oscillator``), a model file
        (``.toml``, ``.json``) or a shared library exporting a model (``.so``), or a dict with
        the keys of a model file (docs/model-files.md): ``{"name": ..., "state": [...],
        "parameters": {...}, "derivatives": {...}, "surfaces": [...], ...}``, parameters in
        the dict's order.
    **parameters : float
        Parameter values replacing the defaults, by name.

    Attributes
    ----------
    name : str
    parameters : dict
        Every parameter's value, in the model's order. Each is also an attribute
        (``m.Ur``); use ``with_`` for a changed copy.
    parameter_names, state_names, surfaces, sections, switches, presets : tuple of str
    dim : int
        Number of state variables.
    default_ic : ndarray, float64, shape (dim,)
        The initial state the analyses use when none is given.
    info : dict
        What the model says about itself: meanings, units and ranges of the state variables
        and parameters, surfaces, sections, switches, presets, source and identity.

    Raises
    ------
    ValueError
        (vimpact.InputError) an unknown model, a model file with a mistake (the message names
        the file, the key and the problem), an unknown parameter or a value outside its range.

    Examples
    --------
    >>> m = vimpact.Model("wake_impact", Ur=16)
    >>> m.with_(r=0.7).r
    0.7
    >>> vimpact.Model("examples/models/two_sided_impact_oscillator.toml").surfaces
    ('right', 'left')
    """

    __slots__ = ("_handle", "_origin", "_info")

    def __init__(self, source="wake_impact", **parameters):
        if isinstance(source, Model):
            handle, origin = source._handle, source._origin
        elif isinstance(source, dict):
            try:
                text = json.dumps(source, default=_jsonable, allow_nan=False)
            except ValueError as e:
                if isinstance(e, InputError):
                    raise
                raise InputError(f"model description: {e}") from None
            origin = ("json", text, "<dict>")
            handle = _load(origin)
        elif isinstance(source, (str, os.PathLike)):
            s = os.fspath(source)
            if s in _vimpact._Model.builtin_names():
                origin = ("builtin", s)
            elif s.endswith(_MODEL_FILE_SUFFIXES) or os.path.sep in s or os.path.exists(s):
                origin = ("file", os.path.abspath(s), s)
            else:
                origin = ("builtin", s)  # the library names the built-ins in its message
            handle = _load(origin)
        else:
            raise TypeError(f"a model is made from a name, a file or a dict (got {type(source).__name__})")
        object.__setattr__(self, "_handle", handle)
        object.__setattr__(self, "_origin", origin)
        object.__setattr__(self, "_info", None)
        if parameters:
            object.__setattr__(self, "_handle", self._changed(parameters))

    # ---------------------------------------------------------------- making models

    @classmethod
    def _wrap(cls, handle, origin, info=None):
        m = cls.__new__(cls)
        object.__setattr__(m, "_handle", handle)
        object.__setattr__(m, "_origin", origin)
        object.__setattr__(m, "_info", info)
        return m

    @classmethod
    def builtin(cls, name, **parameters):
        """A built-in model by name (``Model.builtin_names()``), with parameter overrides."""
        return cls._wrap(_load(("builtin", name)), ("builtin", name)).with_(**parameters)

    @classmethod
    def from_file(cls, path, **parameters):
        """A model file (``.toml``, ``.json``) or a shared library exporting a model (``.so``).

        A model file is compiled to native code the first time (a fraction of a second with
        the machine's C++ compiler, ``$CXX`` or ``c++``) and cached in ``$VIMPACT_CACHE_DIR``
        (else ``~/.cache/vimpact``); docs/model-files.md describes the format.
        """
        # Absolute, so that a pickled model loads in a worker started elsewhere; the path as
        # given is what the model shows.
        origin = ("file", os.path.abspath(os.fspath(path)), os.fspath(path))
        return cls._wrap(_load(origin), origin).with_(**parameters)

    @classmethod
    def from_toml(cls, text, source="<string>", **parameters):
        """A model file's text; ``source`` names it in messages."""
        origin = ("toml", str(text), str(source))
        return cls._wrap(_load(origin), origin).with_(**parameters)

    @staticmethod
    def builtin_names():
        """The names of the built-in models."""
        return tuple(_vimpact._Model.builtin_names())

    def _changed(self, values):
        current = list(self._handle.parameters)
        names = self.parameter_names
        for name, value in values.items():
            if name not in names:
                raise InputError(f"unknown parameter '{name}' of model {self.name} (parameters: {', '.join(names)})")
            if isinstance(value, bool) or not isinstance(value, numbers.Real):
                raise TypeError(f"parameter {name} must be a number (got {type(value).__name__})")
            current[names.index(name)] = float(value)
        return self._handle.with_parameters(current)

    def with_(self, **parameters):
        """A copy with the given parameters changed, e.g. ``m.with_(r=0.7, sigma=-0.1)``.

        Raises ValueError (vimpact.InputError) for an unknown name or a value outside its range.
        """
        if not parameters:
            return self
        return Model._wrap(self._changed(parameters), self._origin, self._info)

    def with_parameters(self, values):
        """A copy with every parameter given, in the model's order (a sequence of numbers)."""
        return Model._wrap(self._handle.with_parameters([float(v) for v in values]), self._origin, self._info)

    def preset(self, name, **parameters):
        """The model at a named preset (the defaults, then the preset's values), with overrides.

        ``vimpact.Model("wake_impact").preset("facchinetti", Ur=25)``; ``presets`` lists the
        names.
        """
        names = self.presets
        if name not in names:
            raise InputError(f"unknown preset '{name}' of model {self.name} (presets: {', '.join(names) or 'none'})")
        return Model._wrap(self._handle.with_preset(names.index(name)), self._origin, self._info).with_(**parameters)

    # ---------------------------------------------------------------- what it says about itself

    @property
    def info(self):
        """dict: name, description, source, identity, state, parameters, surfaces, sections,
        presets (each a list of dicts with name, meaning and what else applies: unit, default,
        range, period (None unless a phase), sticks, direction, values) and initial_state, as
        `vimpact models --json` gives them."""
        if self._info is None:
            object.__setattr__(self, "_info", json.loads(self._handle.info))
        return self._info

    @property
    def name(self):
        return self.info["name"]

    @property
    def description(self):
        return self.info["description"]

    @property
    def identity(self):
        """Equal identities, same model code: a built-in's name, else a hash of its description."""
        return self._handle.identity

    @property
    def source(self):
        """``built-in``, or the file (or ``<dict>``, ``<string>``) the model came from."""
        return self.info["source"]

    @property
    def parameters(self):
        return dict(zip(self.parameter_names, self._handle.parameters))

    def _names(self, kind):
        return tuple(x["name"] for x in self.info[kind])

    @property
    def parameter_names(self):
        return self._names("parameters")

    @property
    def state_names(self):
        return self._names("state")

    @property
    def surfaces(self):
        return self._names("surfaces")

    @property
    def sections(self):
        return self._names("sections")

    @property
    def switches(self):
        return self._names("switches")

    @property
    def presets(self):
        return self._names("presets")

    @property
    def dim(self):
        return len(self.info["state"])

    @property
    def default_ic(self):
        return np.array(self.info["initial_state"], dtype=float)

    def __getattr__(self, name):
        # Parameters as attributes: called only when no attribute of the class has the name.
        if not name.startswith("_"):
            try:
                i = self.parameter_names.index(name)
            except ValueError:
                pass
            else:
                return self._handle.parameters[i]
        raise AttributeError(f"'Model' object has no attribute {name!r}")

    def __setattr__(self, name, value):
        raise AttributeError(f"a Model is immutable: use m.with_({name}=...) for a changed copy")

    def __dir__(self):
        return sorted(set(object.__dir__(self)) | set(self.parameter_names))

    # ---------------------------------------------------------------- the vector field

    def rhs(self, x):
        """The vector field F(x) between impacts (ndarray, float64, shape (dim,))."""
        return self._handle.rhs(np.asarray(x, dtype=float))

    def jacobian(self, x):
        """The Jacobian DF(x) (ndarray, float64, shape (dim, dim)), exact (analytic,
        symbolic or automatic differentiation, never finite differences)."""
        return self._handle.jacobian(np.asarray(x, dtype=float))

    def gaps(self, x):
        """The gap of every surface at x (ndarray, float64, shape (surfaces,)): the motion keeps
        each >= 0."""
        return self._handle.gaps(np.asarray(x, dtype=float))

    def gap_parameters(self, surface):
        """The parameters that move a surface (by name or index) without entering the vector
        field: the candidates for its grazing value (``sigma`` of the paper's barrier)."""
        i = self._surface_index(surface)
        return tuple(self.parameter_names[p] for p in self._handle.gap_parameters(i))

    def _surface_index(self, surface):
        if isinstance(surface, str):
            if surface not in self.surfaces:
                raise InputError(f"model {self.name} has no surface '{surface}' "
                                 f"(surfaces: {', '.join(self.surfaces) or 'none'})")
            return self.surfaces.index(surface)
        return int(surface)

    # ---------------------------------------------------------------- value semantics

    def __eq__(self, other):
        if not isinstance(other, Model):
            return NotImplemented
        return self._handle == other._handle

    def __hash__(self):
        return hash((self.identity, tuple(self._handle.parameters)))

    def __reduce__(self):
        # Built-ins and files are loaded again from their source (a file must still be there);
        # TOML text and dicts travel with the pickle.
        return (_rebuild, (self._origin, list(self._handle.parameters)))

    def __repr__(self):
        values = ", ".join(f"{k}={_number(v)}" for k, v in self.parameters.items())
        kind = self._origin[0]
        if kind == "builtin":
            head = repr(self._origin[1])
        elif kind == "file":
            head = repr(self._origin[2])
        else:
            head = f"<{self.name} from {self._origin[2]}>"
        return f"Model({head}{', ' if values else ''}{values})"


def _number(v):
    return repr(v) if math.isfinite(v) else f"float('{v}')"


class _BuiltinConstructor:
    """``vimpact.WakeImpact(**parameters)`` and the like: a built-in model as a Model."""

    def __init__(self, model_name, doc):
        self.model_name = model_name
        self.__name__ = "".join(w.capitalize() for w in model_name.split("_"))
        self.__qualname__ = self.__name__
        self.__doc__ = doc

    def __call__(self, **parameters):
        return Model.builtin(self.model_name, **parameters)

    def preset(self, name, **parameters):
        """The model at a named preset, with keyword overrides."""
        return Model.builtin(self.model_name).preset(name, **parameters)

    @property
    def parameter_names(self):
        return Model.builtin(self.model_name).parameter_names

    @property
    def state_names(self):
        return Model.builtin(self.model_name).state_names

    def __repr__(self):
        return f"<constructor of vimpact.Model('{self.model_name}')>"


def _constructor(model_name, summary):
    m = Model.builtin(model_name)
    lines = [summary, "", m.description + ".", "", "Parameters", "----------",
             "Keyword arguments; those not given take their defaults.", ""]
    for p in m.info["parameters"]:
        lines.append(f"{p['name']} : float, default {_number(p['default'])}")
        lines.append(f"    {p['meaning'] or p['name']}; valid range {p['range']['text']}.")
    lines += ["", "Returns", "-------", f"Model", f"    ``vimpact.Model('{model_name}', **parameters)``."]
    if m.presets:
        cls = "".join(w.capitalize() for w in model_name.split("_"))
        lines += ["", "Presets: " + ", ".join(m.presets) + f" (``{cls}.preset(name, **parameters)``)."]
    return _BuiltinConstructor(model_name, "\n".join(lines))


WakeImpact = _constructor("wake_impact", "WakeImpact(**parameters): the paper's wake-induced vibro-impacting "
                                         "oscillator as a vimpact.Model.")
ForcedImpactOscillator = _constructor("forced_impact_oscillator",
                                      "ForcedImpactOscillator(**parameters): the forced linear impact oscillator "
                                      "as a vimpact.Model.")
TwoSidedImpactOscillator = _constructor("two_sided_impact_oscillator",
                                        "TwoSidedImpactOscillator(**parameters): the forced oscillator between two "
                                        "stops as a vimpact.Model.")
