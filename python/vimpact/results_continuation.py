"""The result of a continuation (``vimpact.continuation``, the command ``vimpact continue``):
branches of periodic orbits, stable and unstable, their bifurcations, and curves of
bifurcation points in a second parameter.

Both front ends give the library's one JSON form of the result (the command line in run.json,
the module from the compiled core); ``Continuation.from_json`` shapes it into numpy arrays.
Pure Python and numpy, like ``vimpact.results``.
"""
import csv
import os
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .frames import BranchFrames
from .results import _Context, _loaded


def _floats(values):
    return np.array([np.nan if v is None else v for v in values], dtype=float)


def _states(rows, dim):
    a = np.array([[np.nan if v is None else v for v in r] for r in rows], dtype=float)
    return a.reshape(len(rows), dim)


def _complex(rows, dim):
    """Rows of [[re, im], ...] as a complex array (n, dim), NaN where missing."""
    out = np.full((len(rows), dim), np.nan + 0j)
    for i, row in enumerate(rows):
        for k, (re_, im) in enumerate(row[:dim]):
            out[i, k] = (np.nan if re_ is None else re_) + 1j * (np.nan if im is None else im)
    return out


@dataclass(repr=False)
class Branch:
    """One branch: periodic orbits with ``returns`` section points per period, in order along
    the branch (arclength).

    Attributes
    ----------
    index, returns : int
    parent, origin : int or None
        The branch it was switched from, and the bifurcation (index in
        ``Continuation.bifurcations``) where.
    end : str
        Why it ended: range, point_limit, step_too_small, section_impact (its section point
        meets an impact it cannot be taken past), closed, grazing, failed, interrupted.
    end_reason : str
        The same in words with the parameter value where it happened ("step too small at
        w = 0.78", "grazing at w = 0.53", "range").
    failure : str
        With end == "failed": the outcome of the map.
    param, period, closure, arclength : ndarray, float64, shape (n,)
    stable : ndarray, bool, shape (n,)
    impacts : ndarray, int, shape (n,)
        Impacts per period, and per surface in ``impacts_by_surface`` (name -> (n,)).
    state : ndarray, float64, shape (n, dim)
        The orbit's point on the section.
    sections : ndarray, float64, shape (n, returns, dim)
        All its section points, in the orbit's order (``state`` first).
    multipliers : ndarray, complex128, shape (n, dim)
        Floquet multipliers with saltation at the impacts, trivial (1) first.
    """
    index: int = 0
    returns: int = 1
    parent: Optional[int] = None
    origin: Optional[int] = None
    end: str = ""
    end_reason: str = ""
    failure: str = "ok"
    param: np.ndarray = None
    stable: np.ndarray = None
    period: np.ndarray = None
    impacts: np.ndarray = None
    impacts_by_surface: dict = field(default_factory=dict)
    closure: np.ndarray = None
    arclength: np.ndarray = None
    state: np.ndarray = None
    sections: np.ndarray = None
    multipliers: np.ndarray = None

    def __repr__(self):
        n = len(self.param)
        lo, hi = (float(np.min(self.param)), float(np.max(self.param))) if n else (np.nan, np.nan)
        return (f"Branch({self.index}: P{self.returns}, {n} points over {lo:g}..{hi:g}, "
                f"{int(np.sum(self.stable))} stable, ends {self.end_reason or self.end})")


@dataclass(repr=False)
class Bifurcation:
    """A located bifurcation: ``type`` fold, period_doubling, neimark_sacker or grazing; its
    ``param``, the ``branch`` and the point it follows there (``after_point``), whether it was
    ``located`` to the tolerance (``bracket``: the last parameter bracket), the orbit there
    (``state``, all its section points ``sections`` (returns, dim), ``period``, ``multipliers`` trivial first, ``section_multipliers`` the others)
    and, for a grazing, the ``surface`` (or the ``switch``, with its ``crossings_before`` and
    ``crossings_after`` per period), the ``time`` along the orbit and the impact sequences
    before and after it along the branch."""
    type: str = ""
    param: float = np.nan
    branch: int = 0
    after_point: int = 0
    located: bool = True
    bracket: float = 0.0
    state: np.ndarray = None
    sections: np.ndarray = None
    period: float = np.nan
    multipliers: np.ndarray = None
    section_multipliers: np.ndarray = None
    surface: Optional[str] = None
    switch: Optional[str] = None
    crossings_before: Optional[int] = None
    crossings_after: Optional[int] = None
    time: Optional[float] = None
    sequence_before: tuple = ()
    sequence_after: tuple = ()

    def __repr__(self):
        where = f" ({self.surface})" if self.surface else f" (switch {self.switch})" if self.switch else ""
        return f"Bifurcation({self.type}{where} at {self.param:.12g} on branch {self.branch})"


@dataclass(repr=False)
class Curve:
    """The curve of one bifurcation (``origin``, an index in ``Continuation.bifurcations``) in
    the plane of the two parameters: arrays ``param``, ``param2``, ``period``, ``closure``,
    ``condition`` (n,), ``state`` (n, dim), ``multipliers`` (n, dim); ``start`` the index of
    the point it was started from; ``end_backward``, ``end_forward`` why each end stopped."""
    type: str = ""
    origin: int = 0
    surface: Optional[str] = None
    switch: Optional[str] = None  #: a switch's grazing: the switch
    start: int = 0
    end_backward: str = ""
    end_forward: str = ""
    failure: str = "ok"
    param: np.ndarray = None
    param2: np.ndarray = None
    period: np.ndarray = None
    closure: np.ndarray = None
    condition: np.ndarray = None
    state: np.ndarray = None
    multipliers: np.ndarray = None

    def __repr__(self):
        return f"Curve({self.type} from bifurcation {self.origin}, {len(self.param)} points)"


@dataclass(repr=False)
class Continuation(_Context, BranchFrames):
    """Branches of periodic orbits in ``param`` (stable and unstable), their ``bifurcations``
    and, with a second parameter ``param2``, the ``curves`` of the bifurcation points.

    Attributes
    ----------
    param : str
    range : (float, float)
        From where the first branch starts towards where it runs.
    status : str
        ok, or why no branch could be started (aperiodic: no periodic attractor).
    start_label : str
        The protocol's label at the start (``"P1"``, ...), empty when started from a point.
    branches : list of Branch
    bifurcations : list of Bifurcation
    param2 : str or None
    range2 : (float, float) or None
    curves : list of Curve
    diagram : dict or None
        The brute-force bifurcation diagram drawn under the branches (``continue --diagram``):
        ``value`` (points,), ``label`` (points,), ``points`` (points, dim).
    map : dict or None
        The brute-force periodicity map under the curves (``continue --map``): ``x``
        (param values), ``y`` (param2 values), ``label`` (ny, nx).
    tangent_maps, plain_maps : int
        Section-map evaluations with and without the tangent flow.
    """
    param: str = ""
    range: tuple = ()
    status: str = "ok"
    start_label: str = ""
    branches: list = field(default_factory=list)
    bifurcations: list = field(default_factory=list)
    param2: Optional[str] = None
    range2: Optional[tuple] = None
    curves: list = field(default_factory=list)
    diagram: Optional[dict] = None
    map: Optional[dict] = None
    tangent_maps: int = 0
    plain_maps: int = 0

    def __repr__(self):
        kinds = ", ".join(f"{b.type} at {b.param:.10g}" for b in self.bifurcations) or "none"
        return (f"Continuation({self.param}: {len(self.branches)} branch(es); bifurcations: {kinds}"
                f"{'; ' + str(len(self.curves)) + ' curve(s) in ' + self.param2 if self.param2 else ''})")

    @classmethod
    def from_json(cls, result, **context):
        """From the library's JSON form (``result`` a dict) and a result's context."""
        dim = len(context.get("state_names") or ())
        surfaces = tuple(context.get("surfaces") or ())
        branches = []
        for i, (pts, info) in enumerate(zip(result["branches"], result["branch_info"])):
            k = info["returns"]
            branches.append(Branch(
                index=i, returns=k, parent=info["parent"], origin=info["origin"], end=info["end"],
                end_reason=info.get("end_reason", info["end"]), failure=info["failure"],
                param=_floats(p["param"] for p in pts),
                stable=np.array([bool(p["stable"]) for p in pts], dtype=bool),
                period=_floats(p["period"] for p in pts), impacts=np.array([p["impacts"] for p in pts], dtype=int),
                impacts_by_surface={s: np.array([p["impacts_by_surface"].get(s, 0) for p in pts], dtype=int)
                                    for s in surfaces},
                closure=_floats(p["closure"] for p in pts), arclength=_floats(p["arclength"] for p in pts),
                state=_states([p["state"] for p in pts], dim),
                sections=np.array([_states(p["section_points"], dim) for p in pts]).reshape(len(pts), k, dim),
                multipliers=_complex([p["multipliers"] for p in pts], dim)))
        bifurcations = [Bifurcation(
            type=b["type"], param=b["param"], branch=b["branch"], after_point=b["after_point"], located=b["located"],
            bracket=np.nan if b["bracket"] is None else b["bracket"], state=_floats(b["state"]),
            sections=_states(b["section_points"], dim),
            period=np.nan if b["period"] is None else b["period"],
            multipliers=_complex([b["multipliers"]], dim)[0],
            section_multipliers=_complex([b["section_multipliers"]], max(dim - 1, 0))[0], surface=b["surface"],
            switch=b.get("switch"), crossings_before=b.get("crossings_before"),
            crossings_after=b.get("crossings_after"), time=b["time"], sequence_before=tuple(b["sequence_before"]), sequence_after=tuple(b["sequence_after"]))
            for b in result["bifurcations"]]
        curves = [Curve(
            type=c["type"], origin=c["origin"], surface=c["surface"], switch=c.get("switch"), start=c["start"],
            end_backward=c["end_backward"],
            end_forward=c["end_forward"], failure=c["failure"], param=_floats(p["param"] for p in c["points"]),
            param2=_floats(p["param2"] for p in c["points"]), period=_floats(p["period"] for p in c["points"]),
            closure=_floats(p["closure"] for p in c["points"]), condition=_floats(p["condition"] for p in c["points"]),
            state=_states([p["state"] for p in c["points"]], dim),
            multipliers=_complex([p["multipliers"] for p in c["points"]], dim)) for c in result.get("curves", [])]
        return cls(param=result["param"], range=tuple(result["range"]), status=result["status"],
                   start_label=result["start_label"], branches=branches, bifurcations=bifurcations,
                   param2=result.get("param2"), range2=tuple(result["range2"]) if "range2" in result else None,
                   curves=curves, tangent_maps=result["tangent_maps"], plain_maps=result["plain_maps"], **context)

    @classmethod
    def load(cls, directory):
        """The result of ``vimpact continue ... --out DIR`` (with its brute-force diagram or
        map when it was asked for)."""
        ctx, res = _loaded(directory)
        out = cls.from_json(res, **ctx)
        out.diagram = _diagram(os.path.join(directory, "diagram.csv"), res["param"], ctx["state_names"])
        out.map = _map(os.path.join(directory, "map.csv"), res["param"], res.get("param2"))
        return out


def _rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def _diagram(path, param, names):
    if not os.path.exists(path):
        return None
    rows = _rows(path)
    return dict(value=np.array([float(r[param]) for r in rows]), label=np.array([r["label"] for r in rows]),
                points=np.array([[float(r[n]) for n in names] for r in rows]).reshape(len(rows), len(names)))


def _map(path, param, param2):
    if not param2 or not os.path.exists(path):
        return None
    rows = _rows(path)
    x = np.unique([float(r[param]) for r in rows])
    y = np.unique([float(r[param2]) for r in rows])
    label = np.empty((len(y), len(x)), dtype=object)
    for r in rows:
        label[np.searchsorted(y, float(r[param2])), np.searchsorted(x, float(r[param]))] = r["label"]
    return dict(x=x, y=y, label=label.astype(str))
