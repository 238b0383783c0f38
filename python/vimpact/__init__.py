"""vimpact: nonlinear dynamics of a wake-induced vibro-impacting oscillator.

The C++ library's analyses at C++ speed, with numpy arrays in and out::

    import vimpact
    m = vimpact.WakeImpact(Ur=16, sigma=-0.150298)       # the paper's model, paper preset
    p = vimpact.period(m)                                 # p.label == 'P2'
    s = vimpact.sweep(m, "Ur", vimpact.grid(12, 25, 131))
    vimpact.plot.bifurcation(s, "sweep.png")

Models: ``WakeImpact`` (parameters as attributes, ``with_``, ``preset``) and
``ForcedImpactOscillator``. Analyses: ``simulate``, ``period``, ``grazing`` (single runs) and
``sweep``, ``map``, ``basins``, ``response`` (the library's threaded, deterministic job loop);
stability: ``floquet``, ``lyapunov``; ``dimension`` of a point set.
Each returns a result object (``vimpact.results``) with numpy arrays and run statistics; the
same objects load the command line's output directories (``vimpact.Sweep.load(DIR)``).
Plots: ``vimpact.plot``. Bad input raises ValueError (``vimpact.InputError``) with the
library's message; long calls release the GIL and stop on Ctrl-C.

The compiled part lives in the build tree (``PYTHONPATH=build/python``). Without it,
``vimpact.plot`` and ``vimpact.results`` still work (the command line draws its PNGs with them).
"""
import importlib

from .results import (Attractor, Basins, Dimension, Floquet, Grazing, Lyapunov, Map, Period, Response,  # noqa: F401
                      RunStats, Simulation, Sweep)

try:
    from ._vimpact import ForcedImpactOscillator, InputError, WakeImpact, __version__, git_hash  # noqa: F401
    from ._api import (basins, dimension, floquet, grazing, grid, lyapunov, map, period, response,  # noqa: F401
                       simulate, sweep)
except ImportError as _error:  # the compiled module is not built or not on the path
    _import_error = _error
else:
    _import_error = None
    for _f in (basins, dimension, floquet, grazing, grid, lyapunov, map, period, response, simulate, sweep):
        _f.__module__ = __name__  # help() and tracebacks name them vimpact.sweep, not vimpact._api.sweep

_COMPILED = {"ForcedImpactOscillator", "InputError", "WakeImpact", "__version__", "git_hash", "basins", "dimension",
             "floquet", "grazing", "grid", "lyapunov", "map", "period", "response", "simulate", "sweep"}


def __getattr__(name):
    # vimpact.plot is imported on first use: matplotlib is slow to import and not needed
    # for computing.
    if name == "plot":
        return importlib.import_module(".plot", __name__)
    if name in _COMPILED and _import_error is not None:
        raise ImportError(f"vimpact.{name} needs the compiled module vimpact._vimpact, which could not be "
                          f"imported ({_import_error}). Build it (cmake --build build) and put build/python "
                          f"on PYTHONPATH.")
    raise AttributeError(f"module 'vimpact' has no attribute {name!r}")
