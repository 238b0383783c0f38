"""Result objects of vimpact's analyses, and readers that load the command line's output
directories (``vimpact COMMAND ... --out DIR``) into the same objects.

Pure Python and numpy: the plotting helpers (``vimpact.plot``), and through them the command
line's PNGs, use this module without the compiled extension.

Every result carries the model's ``parameters`` (a dict), the effective ``options`` of the run,
its ``stats`` and numpy arrays whose shapes and dtypes are listed in each class. Arrays of a
grid are indexed ``[iy, ix]`` (rows follow the y axis), as the command line's JSON. A field that
a directory does not record is ``None`` in a loaded result (said per class).
"""
import csv
import json
import os
import re
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

WAKE_STATE_NAMES = ("y", "ydot", "x", "xdot")


def read_csv(path):
    """A vimpact CSV of numbers (a header line, then rows) as a dict of float64 column arrays."""
    with open(path) as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if data.size == 0:
        data = np.empty((0, len(header)))
    return {name: data[:, i] for i, name in enumerate(header)}

def save_in(fig, directory, out_name):
    """Lays out `fig`, writes it to directory/out_name (120 dpi), closes it; returns the path."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    path = os.path.join(directory, out_name)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path



def read_table(path):
    """A vimpact CSV with text cells (labels) as a dict of column lists of strings."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    return {name: [r[i] for r in body] for i, name in enumerate(header)}


def read_record(directory):
    """``DIR/run.json``: the configuration, version, git hash and result summary of a run."""
    with open(os.path.join(directory, "run.json")) as f:
        return json.load(f)


def label_order(labels):
    """Distinct labels in reading order: P0, P1, P2, ... numerically, then ``aperiodic``, then
    failed runs' outcomes and others alphabetically."""
    def key(lab):
        m = re.fullmatch(r"P(\d+)", lab)
        if m:
            return (0, int(m.group(1)), lab)
        return (1 if lab == "aperiodic" else 2, 0, lab)
    return sorted(set(labels), key=key)


def label_counts(labels):
    """How many cells or runs carry each label, in ``label_order``."""
    flat = list(np.asarray(labels).ravel())
    return {lab: flat.count(lab) for lab in label_order(flat)}


def _num(v):
    return np.nan if v is None else float(v)


def _str_array(items, shape=None):
    a = np.array(list(items), dtype=str)
    if a.size == 0:
        a = np.array([], dtype="<U1")
    return a.reshape(shape) if shape is not None else a


def _config_fields(record):
    cfg = record.get("config", {})
    return cfg.get("parameters", {}), cfg.get("preset"), cfg


@dataclass(frozen=True)
class RunStats:
    """Counters of one run, whatever its outcome."""
    steps: int = 0              #: accepted steps
    rejected: int = 0           #: rejected trial steps
    rhs_calls: int = 0          #: vector-field evaluations
    impacts: int = 0            #: impacts, transient included
    sections: int = 0           #: section crossings located
    sticking_phases: int = 0    #: chatter sequences ended by sticking
    sticking_time: float = 0.0
    h_min: float = np.inf       #: smallest accepted step
    h_max: float = 0.0          #: largest accepted step
    t_final: float = 0.0        #: time at the end of the run

    @classmethod
    def from_dict(cls, d):
        return cls(**{k: (np.inf if k == "h_min" and v is None else v) for k, v in d.items()})

    def as_dict(self):
        return dict(self.__dict__)


@dataclass(repr=False)
class Simulation:
    """A run of the protocol (``vimpact.simulate``, the command ``simulate``).

    Attributes
    ----------
    outcome : str
        ``ok`` or how the run ended early (``time_limit``, ``step_limit``, ``non_finite``, ...).
    impacting : bool
        False when no impact happened for ``quiet_time`` (the P0 rule): the recorded points
        then describe the barrier-free steady state.
    transient_impacts : int
        Impacts discarded before recording (None when loaded).
    t_record_start : float
        Time at which recording began.
    final_state : ndarray, float64, shape (dim,)
    section_t : ndarray, float64, shape (n,)
        Times of the recorded section points.
    section : ndarray, float64, shape (n, dim)
        The recorded section points (states; for ``maxima``, ydot = 0 exactly).
    impact_t : ndarray, float64, shape (k,)
        Times of the impacts in the recorded window.
    impact_pre, impact_post : ndarray, float64, shape (k, dim)
        States just before and just after each of them. (Loaded: y of ``impact_post`` is the
        pre-impact y, since the CSV stores one y.)
    series_t : ndarray, float64, shape (m,)
    series : ndarray, float64, shape (m, dim)
        The recorded window sampled every ``sample_dt``, plus the states before and after each
        impact (empty when ``sample_dt = 0``).
    stats : RunStats
    parameters : dict
        The model's parameters.
    state_names : tuple of str
        Names of the state components, ``("y", "ydot", "x", "xdot")`` for WakeImpact.
    """
    outcome: str
    impacting: Optional[bool]
    transient_impacts: Optional[int]
    t_record_start: Optional[float]
    final_state: Optional[np.ndarray]
    section_t: np.ndarray
    section: np.ndarray
    impact_t: np.ndarray
    impact_pre: np.ndarray
    impact_post: np.ndarray
    series_t: np.ndarray
    series: np.ndarray
    stats: RunStats
    parameters: dict
    state_names: tuple = WAKE_STATE_NAMES
    model: object = None
    options: dict = field(default_factory=dict)
    preset: Optional[str] = None

    def __repr__(self):
        return (f"Simulation(outcome={self.outcome!r}, {len(self.section_t)} section points, "
                f"{len(self.impact_t)} impacts recorded, {len(self.series_t)} samples, "
                f"{self.stats.impacts} impacts in all, {self.stats.steps} steps)")

    @classmethod
    def load(cls, directory):
        """The run of ``vimpact simulate --out DIR`` (or the points of ``period --out DIR``)."""
        record = read_record(directory)
        parameters, preset, cfg = _config_fields(record)
        res = record.get("result", {})
        names = WAKE_STATE_NAMES

        def states(path):
            if not os.path.exists(path):
                return np.empty(0), np.empty((0, len(names)))
            c = read_csv(path)
            return c["t"], np.column_stack([c[n] for n in names]) if len(c["t"]) else np.empty((0, len(names)))

        sec_t, sec = states(os.path.join(directory, "sections.csv"))
        ser_t, ser = states(os.path.join(directory, "timeseries.csv"))
        imp = read_csv(os.path.join(directory, "impacts.csv"))
        k = len(imp["t"])
        pre = np.column_stack([imp["y"], imp["ydot_before"], imp["x"], imp["xdot"]]) if k else np.empty((0, 4))
        post = np.column_stack([imp["y"], imp["ydot_after"], imp["x"], imp["xdot"]]) if k else np.empty((0, 4))
        fs = res.get("final_state")
        return cls(outcome=res.get("outcome", "ok"), impacting=res.get("impacting"), transient_impacts=None,
                   t_record_start=res.get("t_record_start"),
                   final_state=None if fs is None else np.array(fs, dtype=float),
                   section_t=sec_t, section=sec, impact_t=imp["t"], impact_pre=pre, impact_post=post,
                   series_t=ser_t, series=ser, stats=RunStats.from_dict(res.get("stats", {})),
                   parameters=parameters, state_names=names, options=cfg, preset=preset)


@dataclass(repr=False)
class Period:
    """The period label of the attractor (``vimpact.period``, the command ``period``).

    Attributes
    ----------
    label : str
        ``P0`` (no impact after the transient), ``P1``, ``P2``, ..., ``aperiodic``, or the
        outcome of a failed run.
    period : int
        N for PN, 0 for P0, -1 for aperiodic or failed runs.
    impacts : int
        Impacts per period.
    closure : float
        Largest max-norm distance between section points one period apart.
    tol : float
        The period tolerance used.
    section_y : ndarray, float64, shape (period,)
        y at the section points of one period (empty unless periodic).
    simulation : Simulation
        The run that was classified (its section points, impacts and statistics).
    """
    label: str
    period: int
    impacts: int
    closure: float
    tol: float
    section_y: np.ndarray
    simulation: Simulation

    @property
    def outcome(self):
        return self.simulation.outcome

    @property
    def stats(self):
        return self.simulation.stats

    @property
    def parameters(self):
        return self.simulation.parameters

    @property
    def preset(self):
        return self.simulation.preset

    @property
    def model(self):
        return self.simulation.model

    def __repr__(self):
        extra = f", {self.impacts} impact(s) per period, closure {self.closure:.3g}" if self.period > 0 else ""
        return f"Period(label={self.label!r}{extra}, outcome={self.outcome!r})"

    @classmethod
    def load(cls, directory):
        """The result of ``vimpact period --out DIR``."""
        res = read_record(directory)["result"]
        sim = Simulation.load(directory)
        sim.outcome = res.get("outcome", sim.outcome)
        period = res["period"] if res.get("period") is not None else -1
        return cls(label=res["label"], period=period, impacts=res.get("impacts", 0), closure=res.get("closure", 0.0),
                   tol=res.get("tolerance"), section_y=np.array(res.get("section_y", []), dtype=float),
                   simulation=sim)


@dataclass(repr=False)
class Grazing:
    """The grazing value (``vimpact.grazing``, the command ``grazing``).

    Attributes
    ----------
    sigma_graze : float
        The smallest minimum of y on the attracting barrier-free orbit: a barrier just above it
        is hit, just below it is not. NaN if no block of minima completed.
    converged : bool
        Two successive blocks of minima agreed within ``tol``.
    change : float
        The last block-to-block change of the minimum.
    t_graze : float
        Time of the smallest minimum.
    x_graze : ndarray, float64, shape (dim,)
        State there (NaN before the first block completes).
    y_max : float
        Largest maximum of y in the last block.
    omega : float
        Angular frequency of y over the last block, 2 pi (block - 1) / (t_last - t_first).
    minima : int
        Minima counted after the transient.
    outcome : str
    stats : RunStats
    """
    sigma_graze: float
    converged: bool
    change: float
    t_graze: float
    x_graze: Optional[np.ndarray]
    y_max: Optional[float]
    omega: Optional[float]
    minima: int
    outcome: str
    stats: RunStats
    parameters: dict
    model: object = None
    options: dict = field(default_factory=dict)
    preset: Optional[str] = None

    def __repr__(self):
        conv = "" if self.converged else f", NOT converged (last change {self.change:.3g})"
        return f"Grazing(sigma_graze={self.sigma_graze!r}{conv}, outcome={self.outcome!r})"


@dataclass(repr=False)
class Sweep:
    """A bifurcation diagram (``vimpact.sweep``, the command ``sweep``).

    Runs are in job order: the values in the sweep's direction; with ``direction="both"``
    the upward and downward branches interleave (run 2k is the k-th point up, 2k + 1 the k-th
    point down), as in the command line's ``labels.csv``.

    Attributes
    ----------
    param : str
        The swept parameter.
    values : ndarray, float64, shape (n,)
        The values asked for.
    ic_mode, direction : str
    tol : float
        Period tolerance.
    branch : ndarray, int64, shape (runs,)
        0 up, 1 down.
    value : ndarray, float64, shape (runs,)
        The parameter value of each run.
    label : ndarray, str, shape (runs,)
    period, impacts : ndarray, int64, shape (runs,)
        Period N (0 for P0, -1 aperiodic or failed) and impacts per period.
    closure : ndarray, float64, shape (runs,)
    outcome : ndarray, str, shape (runs,)
    sigma_graze : ndarray, float64, shape (runs,)
        Grazing value at each point with ``grazing=True``, else NaN.
    final_state : ndarray, float64, shape (runs, dim)
        Where each run ended (the start of the next one in follow mode). None when loaded.
    steps : ndarray, int64, shape (runs,)
        Accepted steps of each run. None when loaded.
    points : ndarray, float64, shape (points, dim)
        All recorded section points, run after run.
    point_run : ndarray, int64, shape (points,)
        The run of each point; ``point_value`` and ``point_branch`` follow from it.
    stats : dict
        ``jobs``, ``threads``, ``steps`` and ``rhs_calls`` in all, ``wall_time`` in seconds.
    """
    param: str
    values: np.ndarray
    ic_mode: str
    direction: str
    tol: Optional[float]
    branch: np.ndarray
    value: np.ndarray
    label: np.ndarray
    period: np.ndarray
    impacts: np.ndarray
    closure: np.ndarray
    outcome: np.ndarray
    sigma_graze: np.ndarray
    final_state: Optional[np.ndarray]
    steps: Optional[np.ndarray]
    points: np.ndarray
    point_run: np.ndarray
    stats: dict
    parameters: dict
    state_names: tuple = WAKE_STATE_NAMES
    model: object = None
    options: dict = field(default_factory=dict)
    preset: Optional[str] = None

    @property
    def point_value(self):
        """ndarray, float64, shape (points,): the parameter value of each section point."""
        return self.value[self.point_run]

    @property
    def point_branch(self):
        """ndarray, int64, shape (points,): the branch of each section point."""
        return self.branch[self.point_run]

    @property
    def label_counts(self):
        return label_counts(self.label)

    def __repr__(self):
        counts = ", ".join(f"{k} {v}" for k, v in self.label_counts.items())
        return (f"Sweep(param={self.param!r}, {len(self.values)} values, {self.ic_mode} starts, "
                f"direction {self.direction}: {counts}; {len(self.points)} section points)")

    @classmethod
    def load(cls, directory):
        """The result of ``vimpact sweep --out DIR``."""
        record = read_record(directory)
        parameters, preset, cfg = _config_fields(record)
        res = record["result"]
        param = res["param"]
        lab = read_table(os.path.join(directory, "labels.csv"))
        pts = read_csv(os.path.join(directory, "points.csv"))
        branch = np.array(lab["branch"], dtype=float).astype(np.int64)
        value = np.array(lab[param], dtype=float)
        # The points are written run after run; runs without points (failed) are skipped.
        pb, pv = pts["branch"].astype(np.int64), pts[param]
        point_run = np.empty(len(pv), dtype=np.int64)
        run = 0
        for k in range(len(pv)):
            while run < len(value) and (branch[run] != pb[k] or value[run] != pv[k]):
                run += 1
            point_run[k] = run
        order = np.unique(value)
        return cls(param=param, values=order, ic_mode=res.get("ic_mode", "fixed"),
                   direction=res.get("direction", "up"), tol=None, branch=branch, value=value,
                   label=_str_array(lab["label"]), period=np.array(lab["period"], dtype=np.int64),
                   impacts=np.array(lab["impacts"], dtype=np.int64),
                   closure=np.array(lab["closure"], dtype=float), outcome=_str_array(lab["outcome"]),
                   sigma_graze=np.array(lab["sigma_graze"], dtype=float), final_state=None, steps=None,
                   points=np.column_stack([pts[n] for n in WAKE_STATE_NAMES]) if len(pv) else np.empty((0, 4)),
                   point_run=point_run, stats={}, parameters=parameters, options=cfg, preset=preset)


@dataclass(repr=False)
class Map:
    """A periodicity map over two parameters (``vimpact.map``, the command ``map``).

    Attributes
    ----------
    x, y : str
        The parameters on the axes.
    x_values : ndarray, float64, shape (nx,)
    y_values : ndarray, float64, shape (ny,)
    tol : float
    label : ndarray, str, shape (ny, nx)
        ``P0``, ``P1``, ..., ``aperiodic`` or a failed run's outcome; ``label[iy, ix]``.
    period, impacts : ndarray, int64, shape (ny, nx)
    closure : ndarray, float64, shape (ny, nx)
        None when loaded.
    outcome : ndarray, str, shape (ny, nx)
    steps : ndarray, int64, shape (ny, nx)
        None when loaded.
    grazing : ndarray, float64, shape (k, 2), or None
        With ``grazing=True``: rows (value of the other parameter, sigma_graze), the P0 /
        impacting boundary.
    stats : dict
    """
    x: str
    y: str
    x_values: np.ndarray
    y_values: np.ndarray
    tol: Optional[float]
    label: np.ndarray
    period: np.ndarray
    impacts: np.ndarray
    closure: Optional[np.ndarray]
    outcome: np.ndarray
    steps: Optional[np.ndarray]
    grazing: Optional[np.ndarray]
    stats: dict
    parameters: dict
    model: object = None
    options: dict = field(default_factory=dict)
    preset: Optional[str] = None

    @property
    def label_counts(self):
        return label_counts(self.label)

    def __repr__(self):
        counts = ", ".join(f"{k} {v}" for k, v in self.label_counts.items())
        return f"Map({self.x} x {self.y}, {len(self.x_values)} x {len(self.y_values)}: {counts})"

    @classmethod
    def load(cls, directory):
        """The result of ``vimpact map --out DIR``."""
        record = read_record(directory)
        parameters, preset, cfg = _config_fields(record)
        res = record["result"]
        xs, ys = np.array(res["x_values"], dtype=float), np.array(res["y_values"], dtype=float)
        shape = (len(ys), len(xs))
        lab = read_table(os.path.join(directory, "labels.csv"))
        g = res.get("grazing")
        return cls(x=res["x"], y=res["y"], x_values=xs, y_values=ys, tol=None,
                   label=_str_array(lab["label"], shape),
                   period=np.array(lab["period"], dtype=np.int64).reshape(shape),
                   impacts=np.array(lab["impacts"], dtype=np.int64).reshape(shape), closure=None,
                   outcome=_str_array(lab["outcome"], shape), steps=None,
                   grazing=None if g is None else np.array([[_num(a), _num(b)] for a, b in g], dtype=float).reshape(-1, 2),
                   stats={}, parameters=parameters, options=cfg, preset=preset)


@dataclass(repr=False)
class Attractor:
    """One attractor of a basins computation.

    Attributes
    ----------
    id : int
        Numbered in order of first appearance (job order).
    label : str
    cells : int
        Grid cells whose runs reached it.
    cycle : ndarray, float64, shape (N, k)
        For a periodic attractor, its N section points in the model's section coordinates
        ((y, x, xdot) for WakeImpact); empty otherwise.
    box : ndarray, float64, shape (2, k), or None
        Bounding box (lower, upper row) of the first run's section points; None when loaded.
    """
    id: int
    label: str
    cells: int
    cycle: np.ndarray
    box: Optional[np.ndarray] = None

    def __repr__(self):
        return f"Attractor(id={self.id}, label={self.label!r}, cells={self.cells})"


@dataclass(repr=False)
class Basins:
    """Basins of attraction over a grid of initial states (``vimpact.basins``, the command
    ``basins``).

    Attributes
    ----------
    x, y : str
        The state components on the axes (``y``, ``ydot``, ``x``, ``xdot``); the others are
        taken from ``ic``.
    x_values : ndarray, float64, shape (nx,)
    y_values : ndarray, float64, shape (ny,)
    attractor : ndarray, int64, shape (ny, nx)
        The attractor id reached from each initial state; -1 for a start below the barrier.
    label : ndarray, str, shape (ny, nx)
        Its label (``inadmissible`` for a start below the barrier).
    period : ndarray, int64, shape (ny, nx)
        None when loaded.
    outcome : ndarray, str, shape (ny, nx)
        ``none`` for inadmissible starts. None when loaded.
    steps : ndarray, int64, shape (ny, nx)
        None when loaded.
    attractors : list of Attractor
    stats : dict
    """
    x: str
    y: str
    x_values: np.ndarray
    y_values: np.ndarray
    tol: Optional[float]
    match_tol: Optional[float]
    attractor: np.ndarray
    label: np.ndarray
    period: Optional[np.ndarray]
    outcome: Optional[np.ndarray]
    steps: Optional[np.ndarray]
    attractors: list
    stats: dict
    parameters: dict
    model: object = None
    options: dict = field(default_factory=dict)
    preset: Optional[str] = None

    @property
    def inadmissible_cells(self):
        return int((self.attractor < 0).sum())

    def __repr__(self):
        found = ", ".join(f"{a.id}: {a.label} ({a.cells} cells)" for a in self.attractors)
        return (f"Basins({self.x} x {self.y}, {len(self.x_values)} x {len(self.y_values)}: "
                f"{len(self.attractors)} attractor(s) {found}; {self.inadmissible_cells} inadmissible)")

    @classmethod
    def load(cls, directory):
        """The result of ``vimpact basins --out DIR``."""
        record = read_record(directory)
        parameters, preset, cfg = _config_fields(record)
        res = record["result"]
        sx, sy = res["x"], res["y"]
        ny, nx = res["shape"]
        tab = read_table(os.path.join(directory, "cells.csv"))
        xs = np.array(tab[sx], dtype=float)[:nx]
        ys = np.array(tab[sy], dtype=float)[::nx]
        attractors = [Attractor(id=t["id"], label=t["label"], cells=t["cells"],
                                cycle=np.array(t["section_points"], dtype=float).reshape(len(t["section_points"]), -1)
                                if t["section_points"] else np.empty((0, 3)))
                      for t in res["attractors"]["table"]]
        return cls(x=sx, y=sy, x_values=xs, y_values=ys, tol=None, match_tol=None,
                   attractor=np.array(tab["attractor"], dtype=np.int64).reshape(ny, nx),
                   label=_str_array(tab["label"], (ny, nx)), period=None, outcome=None, steps=None,
                   attractors=attractors, stats={}, parameters=parameters, options=cfg, preset=preset)


@dataclass(repr=False)
class Response:
    """Barrier-free lock-in curves (``vimpact.response``, the command ``response``).

    Attributes
    ----------
    param : str
    values : ndarray, float64, shape (n,)
    curves : ndarray, float64, shape (c, 2)
        The (A, eps) pair of each curve.
    amplitude : ndarray, float64, shape (c, n)
        max |y| on the barrier-free attractor, max(|y_max|, |sigma_graze|).
    y_max : ndarray, float64, shape (c, n)
        Largest maximum of y.
    sigma_graze : ndarray, float64, shape (c, n)
        Smallest minimum of y (the grazing value).
    frequency_ratio : ndarray, float64, shape (c, n)
        Angular frequency of y over the wake's (the wake oscillator's own frequency is 1).
    structure_frequency : ndarray, float64, shape (c, n)
        The structure's natural frequency delta = 1/(St Ur) in the same unit.
    converged : ndarray, bool, shape (c, n)
        The minima settled (False: a quasi-periodic response, say).
    outcome : ndarray, str, shape (c, n)
        None when loaded.
    steps : ndarray, int64, shape (c, n)
        None when loaded.
    stats : dict
    """
    param: str
    values: np.ndarray
    curves: np.ndarray
    amplitude: np.ndarray
    y_max: np.ndarray
    sigma_graze: np.ndarray
    frequency_ratio: np.ndarray
    structure_frequency: np.ndarray
    converged: np.ndarray
    outcome: Optional[np.ndarray]
    steps: Optional[np.ndarray]
    stats: dict
    parameters: dict
    model: object = None
    options: dict = field(default_factory=dict)
    preset: Optional[str] = None

    @property
    def not_converged(self):
        """ndarray, int64, shape (c,): points of each curve whose minima did not settle."""
        return (~self.converged).sum(axis=1)

    def __repr__(self):
        peaks = ", ".join(f"A={a:g}, eps={e:g}: peak {np.nanmax(amp):.6g}"
                          for (a, e), amp in zip(self.curves, self.amplitude))
        return f"Response(param={self.param!r}, {len(self.values)} values; {peaks})"

    @classmethod
    def load(cls, directory):
        """The result of ``vimpact response --out DIR``."""
        record = read_record(directory)
        parameters, preset, cfg = _config_fields(record)
        res = record["result"]
        param = res["param"]
        data = read_csv(os.path.join(directory, "response.csv"))
        curves = np.array([[c["A"], c["eps"]] for c in res["curves"]], dtype=float)
        c = len(curves)
        n = len(data[param]) // c if c else 0

        def grid(name):
            return data[name].reshape(c, n)
        return cls(param=param, values=data[param][:n].copy(), curves=curves, amplitude=grid("amplitude"),
                   y_max=grid("y_max"), sigma_graze=grid("sigma_graze"), frequency_ratio=grid("frequency_ratio"),
                   structure_frequency=grid("structure_frequency"), converged=grid("converged") != 0,
                   outcome=None, steps=None, stats={}, parameters=parameters, options=cfg, preset=preset)


@dataclass(repr=False)
class Floquet:
    """Floquet multipliers of the periodic orbit reached (``vimpact.floquet``, the command
    ``floquet``; the paper's Algorithm 1 with the orbit refined by Newton shooting).

    Attributes
    ----------
    status : str
        ``ok``, ``aperiodic`` (no period within the tolerance: no multipliers),
        ``not_converged`` (Newton did not reach ``newton_tol``; multipliers of the last
        iterate), ``sticking`` or ``flow_failed`` (``flow_outcome`` says how).
    label : str
        The protocol's period label.
    section_returns : int
        Maxima per period.
    period : float
        The period T (NaN without multipliers).
    impacts_per_period : int
    initial_closure, closure : float
        |P^k(z) - z| before and after Newton shooting.
    newton_iterations : int
    orbit_point : ndarray, float64, shape (dim,)
        The refined point of the orbit on the section.
    monodromy : ndarray, float64, shape (dim, dim)
    multipliers : ndarray, complex128, shape (dim,)
        The trivial multiplier (the one for the flow direction, 1 up to the error) first, then
        by decreasing modulus; empty without multipliers.
    trivial_error : float
        |mu_trivial - 1|: the accuracy of the monodromy.
    max_nontrivial_modulus : float
    stable : bool or None
        Every nontrivial |mu| < 1 (None without multipliers).
    det_monodromy, liouville_det : float
        det Phi(T) and exp(integral of div F) * prod det S: equal for a correct monodromy.
    orbit_t, orbit : ndarray, float64, shapes (m,), (m, dim)
        The refined orbit over one period, sampled every ``sample_dt`` (empty when 0).
    impact_t, impact_pre, impact_post : ndarray
        Its impacts, shapes (k,), (k, dim), (k, dim).
    stats : dict
        ``protocol`` and ``tangent`` RunStats.
    """
    status: str
    flow_outcome: str
    label: str
    section_returns: int
    period: float
    impacts_per_period: int
    initial_closure: float
    closure: float
    newton_iterations: int
    orbit_point: np.ndarray
    monodromy: np.ndarray
    multipliers: np.ndarray
    trivial_error: float
    trivial_residual: float
    max_nontrivial_modulus: float
    stable: Optional[bool]
    det_monodromy: float
    liouville_det: float
    impact_map: str
    orbit_t: np.ndarray
    orbit: np.ndarray
    impact_t: np.ndarray
    impact_pre: np.ndarray
    impact_post: np.ndarray
    stats: dict
    parameters: dict
    model: object = None
    options: dict = field(default_factory=dict)
    preset: Optional[str] = None

    def __repr__(self):
        if not len(self.multipliers):
            return f"Floquet(label={self.label!r}, status={self.status!r}: no multipliers)"
        mus = ", ".join(f"{m.real:.6g}{m.imag:+.3g}j" if m.imag else f"{m.real:.6g}" for m in self.multipliers)
        return (f"Floquet(label={self.label!r}, status={self.status!r}, T={self.period:.6g}, multipliers [{mus}], "
                f"{'stable' if self.stable else 'unstable'})")


@dataclass(repr=False)
class Lyapunov:
    """The Lyapunov spectrum (``vimpact.lyapunov``, the command ``lyapunov``; the paper's
    Algorithm 2).

    Attributes
    ----------
    status : str
        ``ok``, ``time_limit`` (averaged over less than asked), ``sticking`` or
        ``flow_failed`` (``flow_outcome`` says how).
    tdm : str
        The mapping of deviations at impacts.
    exponents : ndarray, float64, shape (dim,)
        Descending (NaN when the run failed).
    lle_standard_error : float
        Of the largest exponent, from 8 block means.
    t_start, time : float
        Start and length of the averaging window.
    impacts, intervals, misses : int
    divergence_average, jump_log_det_rate, sum_rule : float
        <div F>, (1/T) sum ln|det S| and their sum, which the exponents must add up to
        (tangent mappings only).
    history_t : ndarray, float64, shape (h,)
    history_growth : ndarray, float64, shape (h, dim)
        ln(R_ii / r0) of every counted interval (QR order); ``running_exponents`` gives the
        running averages.
    stats : dict
        ``transient`` and ``tangent`` RunStats.
    """
    status: str
    flow_outcome: str
    tdm: str
    impacting: bool
    exponents: np.ndarray
    lle_standard_error: float
    t_start: float
    time: float
    impacts: int
    intervals: int
    divergence_average: float
    jump_log_det_rate: float
    sum_rule: float
    misses: int
    history_t: np.ndarray
    history_growth: np.ndarray
    stats: dict
    parameters: dict
    model: object = None
    options: dict = field(default_factory=dict)
    preset: Optional[str] = None

    @property
    def lle(self):
        """The largest exponent."""
        return float(self.exponents[0])

    @property
    def running_exponents(self):
        """ndarray, float64, shape (h, dim): the estimates after each counted interval."""
        elapsed = (self.history_t - self.t_start)[:, None]
        return np.cumsum(self.history_growth, axis=0) / elapsed

    def __repr__(self):
        return (f"Lyapunov(status={self.status!r}, exponents {np.array2string(self.exponents, precision=6)}, "
                f"largest +- {self.lle_standard_error:.2g}, {self.impacts} impacts, tdm {self.tdm})")


@dataclass(repr=False)
class Dimension:
    """The correlation dimension of a point set (``vimpact.dimension``, the command
    ``dimension``).

    Attributes
    ----------
    dimension : float
        The slope of log C against log r over the scaling region (NaN when undetermined).
    found : bool
        The automatic rule met its slope tolerance (or a ``fit_range`` was given).
    automatic : bool
    fit_range : (float, float)
        The radii fitted.
    r2, slope_error, slope_spread, intercept : float
    fitted : int
        Radii in the fit; indices ``fit_first`` .. ``fit_last`` of ``r``.
    r : ndarray, float64, shape (k,)
        Radii of the correlation curve.
    pairs : ndarray, int64, shape (k,)
        Pairs closer than each radius; ``c`` = pairs / total_pairs.
    local_slope : ndarray, float64, shape (k,)
        NaN where not evaluated.
    centres : ndarray, int64
        The centres estimator's centre indices (empty for the correlation sum).
    r_cap : float
        The correlation sum counted pairs closer than this.
    estimator : str
    points, embedding : int
        Number of points and coordinates per point.
    """
    dimension: float
    found: bool
    automatic: bool
    fit_range: tuple
    r2: float
    slope_error: float
    slope_spread: float
    intercept: float
    fitted: int
    fit_first: int
    fit_last: int
    r: np.ndarray
    pairs: np.ndarray
    total_pairs: int
    local_slope: np.ndarray
    centres: np.ndarray
    r_cap: float
    all_pairs: bool
    estimator: str
    points: int
    embedding: int
    options: dict = field(default_factory=dict)

    @property
    def c(self):
        """ndarray, float64, shape (k,): the correlation C(r)."""
        return self.pairs / self.total_pairs if self.total_pairs else np.zeros(len(self.pairs))

    def __repr__(self):
        return (f"Dimension({self.dimension:.4g} +- {self.slope_error:.2g}, {self.estimator} over {self.points} "
                f"points in {self.embedding} coordinates, fit r = {self.fit_range[0]:.3g} .. {self.fit_range[1]:.3g}"
                f"{'' if self.found else ', tolerance NOT met'})")
