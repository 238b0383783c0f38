"""The stability results (``vimpact.floquet``, ``lyapunov``, ``floquet_sweep``,
``lyapunov_sweep``, the command line's ``floquet`` and ``lyapunov``): the library's records of
a run or of each value, their attributes by name as in ``vimpact.results``, which names them
too. Pure Python and numpy."""
import os
from dataclasses import dataclass, fields
from typing import Optional

import numpy as np

from .frames import ImpactFrames
from .results import (_a, _documented, _Impacts, _Labels, _loaded_record, _PointRuns, _Records, _Run, _states,
                      read_csv)


@_documented("floquet", section_points="section", protocol_stats=None, tangent_stats=None, map_evaluations=None)
@dataclass(repr=False)
class Floquet(_Run, _Impacts, ImpactFrames):
    """Floquet multipliers of the periodic orbit reached (``vimpact.floquet``, the command
    ``floquet``; the paper's Algorithm 1 with the orbit refined by Newton shooting). Without
    a period (``status`` aperiodic, or a failed run) there are no multipliers and the period
    is NaN. Its impacts are those of the refined orbit over one period."""
    _timed_files, _si_key = {"orbit": "orbit.csv"}, "period_si"
    _state_tables = {"orbit": ("orbit_t", "orbit")}
    monodromy: np.ndarray = _a("ndarray, float64, shape (dim, dim)")
    stable: Optional[bool] = _a("bool or None", "Every nontrivial |mu| < 1 (None without multipliers).")
    impact_map: str = _a("str", "The mapping of deviations at impacts.", "saltation")
    orbit_t: np.ndarray = _a("ndarray, float64, shape (m,)", "Times of the refined orbit over one period, sampled "
                             "every ``sample_dt`` (empty when 0).")
    orbit: np.ndarray = _a("ndarray, float64, shape (m, dim)", "Its states.")
    stats: dict = _a("dict", "``protocol`` and ``tangent`` RunStats, ``map_evaluations``.", dict)
    si: dict = _a("dict or None", "Loaded from a run with ``--si``: its run.json's ``si`` (the scales in "
                  "``values``, the SI columns of ``orbit.csv`` in ``columns``) and ``period_si`` [s].")

    def __repr__(self):
        if not len(self.multipliers):
            return f"Floquet(label={self.label!r}, status={self.status!r}: no multipliers)"
        mus = ", ".join(f"{m.real:.6g}{m.imag:+.3g}j" if m.imag else f"{m.real:.6g}" for m in self.multipliers)
        return (f"Floquet(label={self.label!r}, status={self.status!r}, T={self.period:.6g}, multipliers [{mus}], "
                f"{'stable' if self.stable else 'unstable'})")

    @classmethod
    def _read(cls, res, directory):
        mus = np.array(res["multipliers"], dtype=float).reshape(-1, 2) @ np.array([1, 1j])
        return dict(stats={}, record=_loaded_record(cls, res, status=res["outcome"], multipliers=mus,
                                                    impacts_by_surface=res["impacts_by_surface"] or {}))


@_documented("lyapunov", section_points="section", transient_stats=None, stats=None)
@dataclass(repr=False)
class Lyapunov(_Run):
    """The Lyapunov spectrum (``vimpact.lyapunov``, the command ``lyapunov``; the paper's
    Algorithm 2). Loaded from a directory, its interval history is the one its running estimates
    (convergence.csv) give."""
    _si_key = "exponents_si"
    tdm: str = _a("str", "The mapping of deviations at impacts.", "saltation")
    positive: bool = _a("bool", "The library's verdict: the largest exponent lies more than 3 standard errors "
                        "above 0.", False)
    history_t: np.ndarray = _a("ndarray, float64, shape (h,)", "The end of every counted interval.")
    history_growth: np.ndarray = _a("ndarray, float64, shape (h, dim)", "ln(R_ii / r0) of every counted interval "
                                    "(QR order).")
    running_exponents: np.ndarray = _a("ndarray, float64, shape (h, dim)", "The estimates after each counted "
                                       "interval (QR order): the growth so far over the time since ``t_start``.")
    stats: dict = _a("dict", "``transient`` and ``tangent`` RunStats.", dict)
    si: dict = None

    @property
    def lle(self):
        """The largest exponent."""
        return float(self.exponents[0])

    def __repr__(self):
        return (f"Lyapunov(status={self.status!r}, exponents {np.array2string(self.exponents, precision=6)}, "
                f"largest +- {self.lle_standard_error:.2g}, {self.impacts} impacts, tdm {self.tdm})")

    @classmethod
    def _read(cls, res, directory):
        conv = read_csv(os.path.join(directory, "convergence.csv"))
        running = _states(conv, [f"lambda{i + 1}" for i in range(len(res["exponents"]))], len(conv["t"]))
        # Back from the running estimates to each interval's growth.
        total = running * (conv["t"] - res["t_start"])[:, None]
        growth = np.diff(np.vstack([np.zeros((1, running.shape[1])), total]), axis=0) if len(total) else total
        return dict(positive=res["positive"], history_t=conv["t"], history_growth=growth, running_exponents=running,
                    stats={},
                    record=_loaded_record(cls, res, status=res["outcome"]))


@dataclass(repr=False)
class _ValueSweep(_Records, _PointRuns):
    """A stability sweep: its record's fields, ``results`` (the result of each value with the
    fields of its record) and the section points of every value (the bifurcation diagram
    underneath)."""
    _series = "section_points"
    param: str = _a("str", "The swept parameter.", "")
    results: list = _a("list", "The result of each value, with the fields of its record.", list)

    @classmethod
    def of(cls, records, ctx, **run):
        sweep = super().of(records, ctx, **run)
        n, result = len(sweep.value), cls._result
        cols = {k: v for k, v in sweep.records.items()
                if isinstance(v, np.ndarray) and len(v) == n and not k.startswith(cls._series)}
        cols.update(sweep._per_value())
        own = {f.name for f in fields(result)}

        def cell(v):  # a spectrum without its NaN, a numpy scalar as Python's
            return v[~np.isnan(v)] if np.iscomplexobj(v) else v.item() if isinstance(v, np.generic) else v

        def record(i):
            by = dict(zip(ctx["surfaces"], sweep.impacts_by_surface[i].tolist()))
            return dict({k: cell(v[i]) for k, v in cols.items() if k not in own},
                        section_points=sweep.points[sweep.point_run == i], impacts_by_surface=by)
        sweep.results = [result(**{k: cell(v[i]) for k, v in cols.items() if k in own}, record=record(i), **ctx)
                         for i in range(n)]
        return sweep


@_documented("floquet_sweep", "n", section_points="points")
@dataclass(repr=False)
class FloquetSweep(_ValueSweep, _Labels):
    """Floquet multipliers over a range of one parameter (``vimpact.floquet_sweep``, the
    command ``floquet --param P --range a:b:n``; the paper's Figures 14 and 15). Each value's
    result is a Floquet without monodromy, impacts or orbit."""
    _result = Floquet

    @property
    def trivial(self):
        """ndarray, bool, shape (n, dim): the trivial multiplier (column 0 where there are multipliers)."""
        t = np.zeros(self.multipliers.shape, dtype=bool)
        t[:, :1] = ~np.isnan(self.multipliers[:, :1])
        return t

    @property
    def stable(self):
        """ndarray, object, shape (n,): the library's verdict (the record's ``stable``), None where
        there are no multipliers."""
        return np.array([bool(s) if h else None for s, h in zip(self.records["stable"], self.trivial.any(axis=1))],
                        dtype=object)

    def _per_value(self):
        return {"stable": self.stable}

    def __repr__(self):
        unstable = sum(1 for s in self.stable if s is False)
        return (f"FloquetSweep(param={self.param!r}, {len(self.value)} values: {self._counts_text()}; "
                f"{unstable} unstable)")


@_documented("lyapunov_sweep", "n", section_points="points", positive="positive_exponent", stats=None)
@dataclass(repr=False)
class LyapunovSweep(_ValueSweep):
    """Lyapunov exponents over a range of one parameter (``vimpact.lyapunov_sweep``, the
    command ``lyapunov --param P --range a:b:n``; the paper's Figures 16 and 17). Each value's
    result is a Lyapunov without interval history; the points are those of each averaging
    window (``record > 0``)."""
    _result = Lyapunov
    tdm: str = _a("str", "The mapping of deviations at impacts.", "saltation")

    @property
    def lle(self):
        """ndarray, float64, shape (n,): the largest exponent of each value."""
        return self.exponents[:, 0] if len(self.exponents) else np.empty(0)

    @property
    def positive(self):
        """How many values have a positive largest exponent (``positive_exponent``)."""
        return int(np.sum(self.positive_exponent))

    def _per_value(self):
        return {"tdm": np.full(len(self.value), self.tdm, dtype=object)}

    def __repr__(self):
        return (f"LyapunovSweep(param={self.param!r}, {len(self.value)} values, tdm {self.tdm}: {self.positive} "
                f"with a positive largest exponent)")
