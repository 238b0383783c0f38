"""vimpact: nonlinear dynamics of impacting systems, at C++ speed, with numpy arrays in and out.

::

    import vimpact
    m = vimpact.Model("wake_impact", Ur=16)            # the paper's model
    p = vimpact.period(m)                               # p.label == 'P2'
    s = vimpact.sweep(m, "Ur", vimpact.grid(12, 25, 131))
    vimpact.plot.bifurcation(s, "sweep.png")

Models: ``Model`` (a built-in by name, a model file ``.toml``/``.json``, a plugin ``.so``, or
a dict with a model file's keys), with ``WakeImpact``, ``ForcedImpactOscillator`` and
``TwoSidedImpactOscillator`` as shortcuts for the built-ins. Analyses: ``simulate``,
``period``, ``grazing`` (single runs); ``sweep``, ``map``, ``basins``, ``response`` (the
library's threaded, deterministic, resumable job loop); stability: ``floquet``, ``lyapunov``,
``floquet_sweep``, ``lyapunov_sweep``; ``continuation`` of periodic orbits (stable and unstable,
with their bifurcations and two-parameter curves); ``dimension`` of a point set; engineering:
``clearance`` and ``PhysicalUnits`` (SI inputs to a model's parameters and its results back to
SI). Each returns a result
object (``vimpact.results``) with numpy arrays and run statistics; the same objects load the
command line's output directories (``vimpact.Sweep.load(DIR)``). Plots: ``vimpact.plot``.
Bad input raises ValueError (``vimpact.InputError``) with the library's message; long calls
release the GIL and stop on Ctrl-C.

The compiled part is built by CMake (``PYTHONPATH=build/python``) or installed with the package
(``pip install --no-build-isolation .``). Without it, ``vimpact.plot`` and ``vimpact.results``
still work (the command line of a CMake build draws its pictures with them from the source
tree), and everything else raises an ImportError saying why.
"""
import importlib

from .results import (Attractor, Basins, Clearance, Dimension, Floquet, FloquetSweep, Grazing,  # noqa: F401
                      JobReport, Lyapunov, LyapunovSweep, Map, Period, Response, RunStats, Simulation, Sweep,
                      read_tables)
from .results_continuation import Bifurcation, Branch, Continuation, Curve  # noqa: F401

_COMPILED = ("Model", "WakeImpact", "ForcedImpactOscillator", "TwoSidedImpactOscillator", "InputError", "git_hash",
             "PhysicalUnits", "basins", "clearance", "continuation", "cylinder_units", "dimension", "floquet",
             "floquet_sweep", "grazing", "grid", "lyapunov",
             "lyapunov_sweep", "map", "period", "response", "simulate", "sweep", "HybridSystem", "SectionSystem",
             "TangentSystem")

try:
    from ._vimpact import InputError, __version__, git_hash  # noqa: F401
    from ._model import ForcedImpactOscillator, Model, TwoSidedImpactOscillator, WakeImpact  # noqa: F401
    from ._api import (basins, clearance, continuation, cylinder_units, dimension, floquet, floquet_sweep,  # noqa: F401
                       grazing, grid, lyapunov, lyapunov_sweep, map, period, response, simulate, sweep)
    from ._units import PhysicalUnits  # noqa: F401
    from ._systems import HybridSystem, SectionSystem, TangentSystem  # noqa: F401
except ImportError as _error:  # the compiled module is not built or not on the path
    _import_error = _error
    __version__ = "unknown (the compiled module vimpact._vimpact is not built)"
else:
    _import_error = None
    Model.__module__ = __name__
    PhysicalUnits.__module__ = __name__
    for _c in (HybridSystem, SectionSystem, TangentSystem):
        _c.__module__ = __name__
    for _f in (basins, clearance, continuation, cylinder_units, dimension, floquet, floquet_sweep, grazing, grid,
               lyapunov, lyapunov_sweep,
               map, period, response, simulate, sweep):
        _f.__module__ = __name__  # help() and tracebacks name them vimpact.sweep, not vimpact._api.sweep


def __getattr__(name):
    # vimpact.plot is imported on first use: matplotlib is slow to import and not needed
    # for computing.
    if name == "plot":
        return importlib.import_module(".plot", __name__)
    if name in _COMPILED and _import_error is not None:
        raise ImportError(f"vimpact.{name} needs the compiled module vimpact._vimpact, which could not be "
                          f"imported ({_import_error}). Build it (cmake --build build --target _vimpact) and put "
                          f"build/python on PYTHONPATH, or install the package with it (pip install "
                          f"--no-build-isolation . in the source tree).")
    raise AttributeError(f"module 'vimpact' has no attribute {name!r}")
