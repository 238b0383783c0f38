"""Result objects of vimpact's analyses, and readers that load the command line's output
directories (``vimpact COMMAND ... --out DIR``) into the same objects.

Pure Python and numpy (no matplotlib, no compiled module): the plotting modules import this
one, never the reverse, and the command line's PNGs are drawn through it.

Every result carries the model's ``parameters`` (a dict), its ``state_names`` (state columns
of every array of states are in this order), its ``surfaces``, the meaning and unit of each
state variable (``state_info``) and parameter (``parameter_info``), the ``plot_variable`` its
pictures show, the effective ``options`` of the run, its ``stats`` and numpy arrays whose
shapes and dtypes are listed in each class. Arrays of a grid are indexed ``[iy, ix]`` (rows
follow the y axis). A field that a directory does not record is ``None`` in a loaded result.
"""
import csv
import json
import os
import re
from dataclasses import dataclass, field, fields
from typing import Optional

import numpy as np


# ---------------------------------------------------------------- reading the command line's files

def read_csv(path):
    """A vimpact CSV of numbers (a header line, then rows) as a dict of float64 column arrays."""
    with open(path) as f:
        header = [h.strip() for h in f.readline().strip().split(",")]
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if data.size == 0:
        data = np.empty((0, len(header)))
    return {name: data[:, i] for i, name in enumerate(header)}


def read_table(path):
    """A vimpact CSV with text cells (labels) as a dict of column lists of strings."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    return {name: [r[i] for r in body] for i, name in enumerate(header)}


def read_mixed(path):
    """A CSV with numeric and text columns (impacts.csv names the surface): numeric columns as
    float64 arrays, the others as lists of strings."""
    out = {}
    for name, cells in read_table(path).items():
        try:
            out[name] = np.array([float(c) for c in cells], dtype=float)
        except ValueError:
            out[name] = cells
    return out


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
    flat = [str(x) for x in np.asarray(labels).ravel()]
    return {lab: flat.count(lab) for lab in label_order(flat)}


def _num(v):
    return np.nan if v is None else float(v)


def _str_array(items, shape=None):
    a = np.array(list(items), dtype=str)
    if a.size == 0:
        a = np.array([], dtype="<U1")
    return a.reshape(shape) if shape is not None else a


# The paper's model, for directories written before run.json named the state variables.
_LEGACY_STATE_NAMES = ("y", "ydot", "x", "xdot")


def _described(entries):
    """name -> {meaning, unit} from the model's description of its state variables or
    parameters: a list of dicts with a name (``Model.info``, run.json's ``state_info``) or a
    dict by name (run.json's ``parameter_info``)."""
    if isinstance(entries, dict):
        entries = [dict(e, name=n) for n, e in entries.items()]
    return {e["name"]: {"meaning": e.get("meaning") or "", "unit": e.get("unit") or ""} for e in entries or ()}


def model_quantities(state, parameters):
    """(state_info, parameter_info) of a result from a model's description of its state
    variables and parameters (see ``_described``): ``state_info`` a tuple of dicts name,
    meaning, unit in the model's order, ``parameter_info`` a dict name -> {meaning, unit}."""
    return tuple(dict(name=n, **e) for n, e in _described(state).items()), _described(parameters)


def _context(record):
    """What every loaded result carries, from run.json: the model's parameters, state names,
    surfaces, plot variable, options and preset."""
    cfg = record.get("config", {}) or {}
    model = record.get("model", cfg.get("model", {}))
    model = model if isinstance(model, dict) else {"name": model}
    parameters = cfg.get("parameters", model.get("parameters", {})) or {}
    if isinstance(parameters, list):
        names = model.get("parameter_names") or [f"p{i}" for i in range(len(parameters))]
        parameters = dict(zip(names, parameters))
    state = record.get("state_names") or model.get("state_names") or cfg.get("state_names") or _LEGACY_STATE_NAMES
    surfaces = record.get("surfaces") or model.get("surfaces") or ()
    surfaces = tuple(s["name"] if isinstance(s, dict) else s for s in surfaces)
    # Directories written before run.json described the model have neither: labels without units.
    state_info, parameter_info = model_quantities(model.get("state_info"), model.get("parameter_info"))
    return dict(parameters=dict(parameters), state_names=tuple(state), surfaces=surfaces,
                state_info=state_info, parameter_info=parameter_info,
                plot_variable=record.get("plot_variable") or state[0], options=cfg, preset=cfg.get("preset"),
                model_name=model.get("name") or cfg.get("model_name"))


def _loaded(directory):
    """What a result loaded from DIR starts from: its context (``_context``) and the result
    summary of its run.json."""
    record = read_record(directory)
    return _context(record), record["result"]


def _written(table, key, where):
    """table[key], or a ValueError saying that `where` comes from a vimpact that did not write
    it yet (older output directories lack the newer columns and keys)."""
    if key not in table:
        raise ValueError(f"{where} has no '{key}': it was written by an older vimpact; run the command again")
    return table[key]


def _cells(cells, kind):
    """A column of a table as its schema types it: int64, float64, bool (1/0) or str."""
    if kind == "text":
        return list(cells)
    values = np.array([float(c) for c in cells], dtype=float)
    return values > 0.5 if kind == "bool" else values.astype(np.int64) if kind == "int" else values


def _tabled(schema, table, tables):
    """The columns of one table as the bindings return them (python/bindings/records.hpp):
    field -> array, a per-surface or per-state field an (n, width) array, a group a dict; a
    series table gives its field's points and, from its key columns, NAME_run: the row of
    each point's record in the records table (its rows come record after record); a spectrum
    table its field's values, (records, width) complex."""
    out, parts = {}, {}
    n = len(next(iter(table.values()), ()))
    for c in schema["columns"]:
        if "field" not in c or "part" in c:
            continue
        target = out.setdefault(c["group"], {}) if "group" in c else out
        values = _cells(table[c["name"]], c.get("type", "float"))
        if "surface" in c or "state" in c:
            parts.setdefault((c.get("group"), c["field"]), (target, []))[1].append(values)
        else:
            target[c["field"]] = values
    for (_, name), (target, cols) in parts.items():
        target[name] = np.column_stack(cols) if n else np.empty((0, len(cols)))
    if "records" in schema:
        keys = [(c["name"], c["key"]) for c in schema["columns"] if "key" in c]
        records = tables[schema["records"]]
        run, runs = 0, np.empty(n, dtype=np.int64)
        for k in range(n):
            while any(float(records[f][run]) != float(table[name][k]) for name, f in keys):
                run += 1
            runs[k] = run
        if "spectrum" in schema:  # (records, width) complex, NaN where a record has fewer values
            values = np.full((len(records[keys[0][1]]), schema["width"]), np.nan + 0j)
            part = {k: _cells(table[k], "float") for k in ("index", "re", "im")}
            values[runs, part["index"].astype(np.int64)] = part["re"] + 1j * part["im"]
            return {schema["spectrum"]: values}
        out[schema["series"] + "_run"] = runs
    return out


def _shaped(columns, shape):
    """Columns of the cells of a grid with their first axis made the grid's ``shape`` (rows
    follow y); text columns as str arrays."""
    out = {}
    for name, c in columns.items():
        if isinstance(c, dict):
            out[name] = _shaped(c, shape)
        elif isinstance(c, list):
            out[name] = _str_array(c, shape)
        else:
            out[name] = np.asarray(c).reshape(tuple(shape) + np.shape(c)[1:])
    return out


def read_tables(directory):
    """The tables of ``vimpact COMMAND --out DIR`` as run.json's ``tables`` describes them:
    file name -> the columns of its records, as the Python API's calls return them."""
    record = read_record(directory)
    if "tables" not in record:
        raise ValueError(f"{directory}/run.json does not describe its tables: it was written by an older "
                         f"vimpact; run the command again")
    out = {}
    for name, schema in sorted(record["tables"].items(), key=lambda kv: "records" in kv[1]):
        out[name] = _tabled(schema, read_table(os.path.join(directory, name)), out)
    return out


def _states(columns, names, n=None):
    """The state columns of a CSV as an (n, dim) array."""
    if n is None:
        n = len(next(iter(columns.values()))) if columns else 0
    if not n:
        return np.empty((0, len(names)))
    return np.column_stack([columns[k] for k in names])


def _impact_states(columns, names, when):
    """States before or after impacts: columns NAME_before / NAME_after where the CSV has
    them (the variables an impact changes), NAME otherwise."""
    n = len(columns.get("t", ()))
    if not n:
        return np.empty((0, len(names)))
    out = []
    for k in names:
        for key in (f"{k}_{when}", f"{k}_{'pre' if when == 'before' else 'post'}", k):
            if key in columns:
                out.append(columns[key])
                break
        else:
            out.append(np.full(n, np.nan))
    return np.column_stack(out)


def _surface_column(table, surfaces):
    """Surface indices of impacts from a column of names or numbers."""
    cells = table.get("surface")
    if cells is None:
        return np.zeros(len(table.get("t", ())), dtype=np.int64)
    out = []
    for c in cells:
        c = str(c).strip()
        if c.endswith(".0"):
            c = c[:-2]
        if c in surfaces:
            out.append(surfaces.index(c))
        else:
            try:
                out.append(int(float(c)))
            except ValueError:
                out.append(-1)
    return np.array(out, dtype=np.int64)


def _grazing_columns(table, surfaces, runs):
    """Per-surface grazing values of a CSV: columns grazing_SURFACE, else grazing, else the
    legacy sigma_graze; NaN where none."""
    keys = [f"grazing_{s}" for s in surfaces]
    if surfaces and all(k in table for k in keys):
        cols = [table[k] for k in keys]
    elif "grazing" in table:
        cols = [table["grazing"]]
    elif "sigma_graze" in table:
        cols = [table["sigma_graze"]]
    else:
        return np.full((runs, max(len(surfaces), 1)), np.nan)
    return np.column_stack([np.array([_num(None if v in ("", "nan", None) else v) for v in c], dtype=float)
                            for c in cols]) if runs else np.empty((0, len(cols)))


# ---------------------------------------------------------------- run statistics and job reports

def _statistics(d):
    """A run's impact statistics from run.json (null -> NaN; excursion_by_surface a list)."""
    out = {}
    for k, v in (d or {}).items():
        if k == "excursion_by_surface":
            out[k] = [_num(x) for x in (v.values() if isinstance(v, dict) else v)]
        elif k == "impacts_recorded":
            out[k] = int(v)
        else:
            out[k] = _num(v)
    return out


def _statistics_columns(table, names, shape=None):
    """The impact statistics columns of a labels table (those of ``names`` present), as float64
    arrays of ``shape``."""
    out = {}
    for k in names or ():
        if k in table:
            a = np.array([_num(None if v in ("", "nan") else v) for v in table[k]], dtype=float)
            out[k] = a.reshape(shape) if shape is not None else a
    return out


@dataclass(frozen=True)
class RunStats:
    """Counters of one run, whatever its outcome."""
    steps: int = 0              #: accepted steps
    rejected: int = 0           #: rejected trial steps
    rhs_calls: int = 0          #: vector-field evaluations
    impacts: int = 0            #: impacts on every surface, transient included
    impacts_by_surface: dict = field(default_factory=dict)  #: surface name -> impacts
    sections: int = 0           #: section crossings located
    sticking_phases: int = 0    #: chatter sequences ended by a contact phase
    sticking_time: float = 0.0
    h_min: float = np.inf       #: smallest accepted step
    h_max: float = 0.0          #: largest accepted step
    t_final: float = 0.0        #: time at the end of the run

    @classmethod
    def from_dict(cls, d, surfaces=()):
        d = dict(d or {})
        by = d.get("impacts_by_surface", {})
        if not isinstance(by, dict):
            names = list(surfaces) + [str(i) for i in range(len(surfaces), len(by))]
            by = dict(zip(names, (int(v) for v in by)))
        d["impacts_by_surface"] = by
        if d.get("h_min") is None:
            d["h_min"] = np.inf
        known = cls.__dataclass_fields__
        return cls(**{k: v for k, v in d.items() if k in known})

    def as_dict(self):
        return dict(self.__dict__)


def _by_surface(counts, surfaces):
    """A list of per-surface counts as a dict surface name -> count."""
    return {name: int(counts[i]) if i < len(counts) else 0 for i, name in enumerate(surfaces)}


@dataclass(repr=False)
class JobReport:
    """What a many-job run did, and all it returns when it is not complete: a shard whose
    partners have not finished (run again with ``resume=True`` and the same journal, without
    ``shard``, once they have: that call computes nothing and returns the whole result).

    Attributes
    ----------
    jobs : int
        Jobs of the whole run.
    owned : int
        Jobs of this shard.
    resumed : int
        Of them, found in the journal.
    computed : int
        Computed by this call.
    done : int
        Jobs of the whole run with a result.
    complete : bool
    threads : int
    stopped : bool
        Ctrl-C (or an exception from ``progress``) ended the call early.
    written_elsewhere : bool
        A shard that found the journal removed at its end: another shard completed the run
        (and its caller wrote the outputs and removed the journal).
    journal : str or None
    """
    jobs: int
    owned: int
    resumed: int
    computed: int
    done: int
    complete: bool
    threads: int
    stopped: bool = False
    written_elsewhere: bool = False
    journal: Optional[str] = None

    @classmethod
    def from_dict(cls, d, journal=None):
        return cls(**{k: d[k] for k in ("jobs", "owned", "resumed", "computed", "done", "complete", "threads",
                                         "stopped", "written_elsewhere")}, journal=journal)

    def __repr__(self):
        return (f"JobReport({self.done} of {self.jobs} jobs done: {self.computed} computed now, {self.resumed} "
                f"resumed; {'complete' if self.complete else 'incomplete'})")


# What every result carries: the model's description and the run's options. A base class, so
# the results' own fields (all with defaults) follow it.
@dataclass(repr=False)
class _Context:
    parameters: dict = field(default_factory=dict)
    state_names: tuple = ()
    surfaces: tuple = ()
    plot_variable: Optional[str] = None
    model: object = None
    options: dict = field(default_factory=dict)
    preset: Optional[str] = None
    model_name: Optional[str] = None
    state_info: tuple = ()  #: per state variable, {name, meaning, unit}, in the model's order
    parameter_info: dict = field(default_factory=dict)  #: parameter name -> {meaning, unit}

    def state_index(self, name):
        """The column of a state variable in this result's arrays of states."""
        return self.state_names.index(name)

    @property
    def plot_index(self):
        """The column of ``plot_variable``."""
        names = tuple(self.state_names)
        return names.index(self.plot_variable) if self.plot_variable in names else 0


# What results of many runs share: their labels counted, and the parameter value of each
# section point (``points`` and the run of each, ``point_run``). Plain classes, so that a
# result's fields stay in the order its dataclass declares them.
class _Labels:
    @property
    def label_counts(self):
        """How many runs or cells carry each label, in ``label_order``."""
        return label_counts(self.label)

    def _counts_text(self):
        return ", ".join(f"{k} {v}" for k, v in self.label_counts.items())


class _PointRuns:
    @property
    def point_value(self):
        """ndarray, float64, shape (points,): the parameter value of each section point."""
        return self.value[self.point_run]


# ---------------------------------------------------------------- single runs

@dataclass(repr=False)
class Simulation(_Context):
    """A run of the protocol (``vimpact.simulate``, the command ``simulate``).

    Attributes
    ----------
    outcome : str
        ``ok`` or how the run ended early (``time_limit``, ``step_limit``, ``non_finite``,
        ``chattering``, ...).
    impacting : bool
        False when no impact happened for ``quiet_time``: the recorded points then describe
        the surface-free steady state (label P0).
    transient_impacts : int
        Impacts discarded before recording (None when loaded).
    t_record_start : float
        Time at which recording began.
    final_state : ndarray, float64, shape (dim,)
    section_t : ndarray, float64, shape (n,)
    section : ndarray, float64, shape (n, dim)
        The recorded section points (states, columns as ``state_names``).
    impact_t : ndarray, float64, shape (k,)
        Times of the impacts in the recorded window.
    impact_surface : ndarray, int64, shape (k,)
        The surface hit (an index into ``surfaces``).
    impact_pre, impact_post : ndarray, float64, shape (k, dim)
        States just before and just after each impact.
    series_t : ndarray, float64, shape (m,)
    series : ndarray, float64, shape (m, dim)
        The recorded window sampled every ``sample_dt`` (empty when ``sample_dt = 0``).
    stats : RunStats
    t_record_end : float
        End of the recorded window (its last point), the end of the statistics' window.
    statistics : dict
        The impact statistics of the recorded window (docs/model.md, "Impact statistics"):
        ``impacts_recorded``, ``duration``, ``impact_rate``, ``impact_velocity_min``,
        ``impact_velocity_mean``, ``impact_velocity_rms``, ``impact_velocity_max``,
        ``energy_per_impact``, ``power``, ``contact_fraction``, ``excursion`` (NaN where
        undefined, e.g. velocities without impacts) and ``excursion_by_surface`` (a list).
    impact_velocity, impact_rebound, impact_energy : ndarray, float64, shape (k,)
        Per recorded impact: the normal velocity -dg/dt before the reset, the rebound
        velocity dg/dt after it, and the energy dissipated (v^2 - u^2)/2 per unit mass.
    si : dict or None
        A run in SI units (``--si``; None otherwise): run.json's ``si`` (``values``: the SI
        value of one model unit, ``length_scale``, ``time_scale``, ``velocity_scale``, ...;
        ``columns``: the SI columns of the CSV files and their units) and
        ``impact_statistics_si``. The arrays above stay in the model's units.
    """
    outcome: str = "ok"
    impacting: Optional[bool] = None
    transient_impacts: Optional[int] = None
    t_record_start: Optional[float] = None
    final_state: Optional[np.ndarray] = None
    section_t: np.ndarray = None
    section: np.ndarray = None
    impact_t: np.ndarray = None
    impact_surface: np.ndarray = None
    impact_pre: np.ndarray = None
    impact_post: np.ndarray = None
    series_t: np.ndarray = None
    series: np.ndarray = None
    stats: RunStats = field(default_factory=RunStats)
    t_record_end: Optional[float] = None
    statistics: dict = field(default_factory=dict)
    impact_velocity: np.ndarray = None
    impact_rebound: np.ndarray = None
    impact_energy: np.ndarray = None
    si: Optional[dict] = None

    def __repr__(self):
        return (f"Simulation(outcome={self.outcome!r}, {len(self.section_t)} section points, "
                f"{len(self.impact_t)} impacts recorded, {len(self.series_t)} samples, "
                f"{self.stats.impacts} impacts in all, {self.stats.steps} steps)")

    @classmethod
    def load(cls, directory):
        """The run of ``vimpact simulate --out DIR`` (or the points of ``period --out DIR``)."""
        record = read_record(directory)
        ctx = _context(record)
        names = ctx["state_names"]
        res = record.get("result", {})

        def states(path):
            if not os.path.exists(path):
                return np.empty(0), np.empty((0, len(names)))
            c = read_csv(path)
            return c["t"], _states(c, names, len(c["t"]))

        sec_t, sec = states(os.path.join(directory, "sections.csv"))
        ser_t, ser = states(os.path.join(directory, "timeseries.csv"))
        path = os.path.join(directory, "impacts.csv")
        imp = read_mixed(path) if os.path.exists(path) else {"t": np.empty(0)}
        surface = _surface_column(imp, list(ctx["surfaces"]))
        fs = res.get("final_state")
        n = len(imp["t"])

        def per_impact(name):
            return np.asarray(imp[name], dtype=float) if name in imp else np.full(n, np.nan)

        return cls(outcome=res.get("outcome", "ok"), impacting=res.get("impacting"), transient_impacts=None,
                   t_record_start=res.get("t_record_start"),
                   final_state=None if fs is None else np.array(fs, dtype=float),
                   section_t=sec_t, section=sec, impact_t=imp["t"], impact_surface=surface,
                   impact_pre=_impact_states(imp, names, "before"), impact_post=_impact_states(imp, names, "after"),
                   series_t=ser_t, series=ser, stats=RunStats.from_dict(res.get("stats", {}), ctx["surfaces"]),
                   t_record_end=res.get("t_record_end"), statistics=_statistics(res.get("impact_statistics")),
                   impact_velocity=per_impact("normal_velocity"), impact_rebound=per_impact("rebound_velocity"),
                   impact_energy=per_impact("energy"),
                   si=dict(res["si"], impact_statistics_si=res.get("impact_statistics_si")) if res.get("si") else None,
                   **ctx)


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
        Impacts per period, on every surface.
    impacts_by_surface : dict
        Surface name -> impacts per period.
    closure : float
        Largest max-norm distance between section points one period apart.
    tol : float
        The period tolerance used.
    simulation : Simulation
        The run that was classified (its section points, impacts and statistics).
    settled : bool
        False when the record has not settled: it still converges geometrically onto a
        periodic orbit (one whose period divides the label's, for a periodic label), or it is
        aperiodic as a whole but periodic in its last half. A longer transient gives that
        period.
    """
    label: str
    period: int
    impacts: int
    impacts_by_surface: dict
    closure: float
    tol: Optional[float]
    simulation: Simulation
    settled: bool = True

    def __getattr__(self, name):
        # The run's context (parameters, state_names, model, stats, outcome, ...).
        if name.startswith("__") or name == "simulation":
            raise AttributeError(name)
        return getattr(self.simulation, name)

    @property
    def cycle(self):
        """ndarray, float64, shape (period, dim): the section points of one period (empty
        unless periodic)."""
        return self.simulation.section[:max(self.period, 0)]

    def __repr__(self):
        extra = f", {self.impacts} impact(s) per period, closure {self.closure:.3g}" if self.period > 0 else ""
        if not self.settled:
            extra += ", not settled (still converging over the record: lengthen the transient)"
        return f"Period(label={self.label!r}{extra}, outcome={self.simulation.outcome!r})"

    @classmethod
    def load(cls, directory):
        """The result of ``vimpact period --out DIR``."""
        res = read_record(directory)["result"]
        sim = Simulation.load(directory)
        sim.outcome = res.get("outcome", sim.outcome)
        period = res["period"] if res.get("period") is not None else -1
        by = res.get("impacts_by_surface", {})
        if not isinstance(by, dict):
            by = _by_surface(by, sim.surfaces)
        return cls(label=res["label"], period=period, impacts=res.get("impacts", 0), impacts_by_surface=by,
                   closure=res.get("closure", 0.0), tol=res.get("tolerance"), simulation=sim,
                   settled=res.get("settled", True))


@dataclass(repr=False)
class Grazing(_Context):
    """Where the attracting surface-free orbit just touches each surface (``vimpact.grazing``,
    the command ``grazing``).

    Attributes
    ----------
    param : tuple of (str or None)
        Per surface, the parameter whose grazing value ``value`` gives (None: no parameter
        moves that surface).
    value : ndarray, float64, shape (surfaces,)
        The grazing value of ``param`` per surface: a surface just on the admissible side of
        it is never hit, one just beyond it is (NaN where none).
    margin : ndarray, float64, shape (surfaces,)
        The smallest gap on the surface-free orbit (negative: the free orbit crosses it).
    converged : bool
        Every surface's minimum settled within ``tol``.
    surface_converged : ndarray, bool, shape (surfaces,)
    change : ndarray, float64, shape (surfaces,)
        The last block-to-block change of the minimum gap.
    t : ndarray, float64, shape (surfaces,)
        Time of the minimum gap.
    x : ndarray, float64, shape (surfaces, dim)
        State there (NaN before a block completes).
    minima : ndarray, int64, shape (surfaces,)
    variable : str or None
        The state variable whose response was measured: ``response_max``,
        ``response_min`` (extrema over the last block) and ``response_omega`` (its angular
        frequency).
    outcome : str
    stats : RunStats
    """
    param: tuple = ()
    value: np.ndarray = None
    margin: np.ndarray = None
    converged: bool = False
    surface_converged: np.ndarray = None
    change: np.ndarray = None
    t: np.ndarray = None
    x: np.ndarray = None
    minima: np.ndarray = None
    variable: Optional[str] = None
    response_max: float = np.nan
    response_min: float = np.nan
    response_omega: float = np.nan
    outcome: str = "ok"
    stats: RunStats = field(default_factory=RunStats)

    @property
    def by_surface(self):
        """dict: surface name -> {param, value, margin, converged, change, t, x, minima}."""
        return {s: dict(param=self.param[i], value=float(self.value[i]), margin=float(self.margin[i]),
                        converged=bool(self.surface_converged[i]), change=float(self.change[i]), t=float(self.t[i]),
                        x=self.x[i], minima=int(self.minima[i])) for i, s in enumerate(self.surfaces)}

    def __repr__(self):
        parts = ", ".join(f"{s}: {p} = {v:.10g}" if p else f"{s}: margin {m:.10g}"
                          for s, p, v, m in zip(self.surfaces, self.param, self.value, self.margin))
        conv = "" if self.converged else ", NOT converged"
        return f"Grazing({parts}{conv}, outcome={self.outcome!r})"


# ---------------------------------------------------------------- many-job analyses

@dataclass(repr=False)
class Sweep(_Context, _Labels, _PointRuns):
    """A bifurcation diagram (``vimpact.sweep``, the command ``sweep``).

    Runs are in job order: the values in the sweep's direction; with ``direction="both"``
    the upward and downward branches interleave (run 2k is the k-th point up, 2k + 1 the k-th
    point down).

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
    impacts_by_surface : ndarray, int64, shape (runs, surfaces)
        Impacts per period on each surface.
    closure : ndarray, float64, shape (runs,)
    settled : ndarray, bool, shape (runs,)
        False where the record has not settled: still converging onto a periodic orbit, or
        periodic only in its last half (lengthen the transient).
    outcome : ndarray, str, shape (runs,)
    grazing_param : str or None
        The parameter whose grazing value ``grazing`` holds.
    grazing : ndarray, float64, shape (runs, surfaces)
        Its grazing value per surface at each point (NaN where none or not asked).
    final_state : ndarray, float64, shape (runs, dim)
        Where each run ended (the start of the next one in follow mode). None when loaded.
    steps : ndarray, int64, shape (runs,)
        Accepted steps of each run. None when loaded.
    statistics : dict
        The impact statistics of each run (see ``Simulation.statistics``): name -> ndarray,
        float64, shape (runs,).
    points : ndarray, float64, shape (points, dim)
        All recorded section points, run after run.
    point_run : ndarray, int64, shape (points,)
        The run of each point; ``point_value`` and ``point_branch`` follow from it.
    stats : dict
        ``steps`` and ``rhs_calls`` in all, ``wall_time`` in seconds.
    jobs : JobReport
    records : dict
        Every field of the library's record of each run by name (``read_tables``' form: the
        arrays above are taken from it), a field added to the record included.
    """
    param: str = ""
    values: np.ndarray = None
    ic_mode: str = "fixed"
    direction: str = "up"
    tol: Optional[float] = None
    branch: np.ndarray = None
    value: np.ndarray = None
    label: np.ndarray = None
    period: np.ndarray = None
    impacts: np.ndarray = None
    impacts_by_surface: Optional[np.ndarray] = None
    closure: Optional[np.ndarray] = None
    settled: Optional[np.ndarray] = None
    outcome: np.ndarray = None
    grazing_param: Optional[str] = None
    grazing: np.ndarray = None
    final_state: Optional[np.ndarray] = None
    steps: Optional[np.ndarray] = None
    statistics: dict = field(default_factory=dict)
    points: np.ndarray = None
    point_run: np.ndarray = None
    stats: dict = field(default_factory=dict)
    jobs: Optional[JobReport] = None
    records: dict = field(default_factory=dict)

    @property
    def point_branch(self):
        """ndarray, int64, shape (points,): the branch of each section point."""
        return self.branch[self.point_run]

    def __repr__(self):
        return (f"Sweep(param={self.param!r}, {len(self.values)} values, {self.ic_mode} starts, "
                f"direction {self.direction}: {self._counts_text()}; {len(self.points)} section points)")

    @classmethod
    def of(cls, records, ctx, **run):
        """A sweep from the columns of its points (``read_tables``, or the bindings'), the
        context of its model and what the run says of itself (param, values, ...)."""
        stats = records.get("stats", {})
        return cls(branch=records["branch"], value=records["value"], label=_str_array(records["label"]),
                   period=records["period"], impacts=records["impacts"],
                   impacts_by_surface=records["impacts_by_surface"], closure=records["closure"],
                   settled=records["settled"], outcome=_str_array(records["outcome"]), grazing=records["grazing"],
                   final_state=records.get("final_state"), steps=stats.get("steps"),
                   statistics=dict(records["statistics"]), points=records["points"],
                   point_run=records["points_run"], records=records, **run, **ctx)

    @classmethod
    def load(cls, directory):
        """The result of ``vimpact sweep --out DIR``."""
        ctx, res = _loaded(directory)
        t = read_tables(directory)
        records = dict(t["labels.csv"], **t["points.csv"])
        return cls.of(records, ctx, param=res["param"], values=np.unique(records["value"]),
                      ic_mode=res["ic_mode"], direction=res["direction"], grazing_param=res.get("grazing_param"))


@dataclass(repr=False)
class Map(_Context, _Labels):
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
    impacts_by_surface : ndarray, int64, shape (ny, nx, surfaces)
        None when loaded.
    closure : ndarray, float64, shape (ny, nx)
        None when loaded.
    settled : ndarray, bool, shape (ny, nx)
        False where the record has not settled (still converging, or periodic only in its
        last half).
    outcome : ndarray, str, shape (ny, nx)
    steps : ndarray, int64, shape (ny, nx)
        None when loaded.
    statistics : dict
        The impact statistics of each cell (see ``Simulation.statistics``): name -> ndarray,
        float64, shape (ny, nx).
    grazing_param : str or None
        With ``grazing=True``: the axis parameter that moves the surfaces.
    grazing_other : ndarray, float64, shape (k,)
        Values of the other axis along the grazing line.
    grazing : ndarray, float64, shape (k, surfaces), or None
        The grazing value of ``grazing_param`` per surface at each of them: the boundary
        between impacting and surface-free motion.
    stats : dict
    jobs : JobReport
    records : dict
        Every field of the library's record of each run by name (``read_tables``' form: the
        arrays above are taken from it), a field added to the record included.
    """
    x: str = ""
    y: str = ""
    x_values: np.ndarray = None
    y_values: np.ndarray = None
    tol: Optional[float] = None
    label: np.ndarray = None
    period: np.ndarray = None
    impacts: np.ndarray = None
    impacts_by_surface: Optional[np.ndarray] = None
    closure: Optional[np.ndarray] = None
    settled: Optional[np.ndarray] = None
    outcome: np.ndarray = None
    steps: Optional[np.ndarray] = None
    statistics: dict = field(default_factory=dict)
    grazing_param: Optional[str] = None
    grazing_other: Optional[np.ndarray] = None
    grazing: Optional[np.ndarray] = None
    stats: dict = field(default_factory=dict)
    jobs: Optional[JobReport] = None
    records: dict = field(default_factory=dict)

    def __repr__(self):
        return f"Map({self.x} x {self.y}, {len(self.x_values)} x {len(self.y_values)}: {self._counts_text()})"

    @classmethod
    def of(cls, records, ctx, **run):
        """A map from the columns of its cells (``read_tables``, or the bindings'), the context
        of its model and what the run says of itself (x, y, x_values, y_values, ...)."""
        r = _shaped(records, (len(run["y_values"]), len(run["x_values"])))
        return cls(label=r["label"], period=r["period"], impacts=r["impacts"], impacts_by_surface=r["impacts_by_surface"],
                   closure=r["closure"], settled=r["settled"], outcome=r["outcome"], steps=r.get("steps"),
                   statistics=r["statistics"], records=r, **run, **ctx)

    @classmethod
    def load(cls, directory):
        """The result of ``vimpact map --out DIR``."""
        ctx, res = _loaded(directory)
        gparam, gother, graze = res.get("grazing_param"), None, None
        path = os.path.join(directory, "grazing.csv")
        if os.path.exists(path):
            g = read_table(path)
            other = next(k for k in g if k != "surface" and "_graze" not in k and not k.startswith("grazing"))
            gother = np.array(g[other], dtype=float)
            graze = _grazing_columns(g, ctx["surfaces"], len(gother))
        return cls.of(read_tables(directory)["labels.csv"], ctx, x=res["x"], y=res["y"],
                      x_values=np.array(res["x_values"], dtype=float), y_values=np.array(res["y_values"], dtype=float),
                      grazing_param=gparam, grazing_other=gother, grazing=graze)


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
        For a periodic attractor, its N section points in the signature's coordinates (the
        state, with each phase as a (cos, sin) pair scaled by its period / 2 pi); empty
        otherwise.
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
class Basins(_Context):
    """Basins of attraction over a grid of initial states (``vimpact.basins``, the command
    ``basins``).

    Attributes
    ----------
    x, y : str
        The state variables on the axes; the others are taken from ``ic``.
    x_values : ndarray, float64, shape (nx,)
    y_values : ndarray, float64, shape (ny,)
    attractor : ndarray, int64, shape (ny, nx)
        The attractor id reached from each initial state; -1 for a start beyond a surface.
    label : ndarray, str, shape (ny, nx)
        Its label (``inadmissible`` for a start beyond a surface).
    period : ndarray, int64, shape (ny, nx)
    outcome : ndarray, str, shape (ny, nx)
    settled : ndarray, bool, shape (ny, nx)
        False where a start's record has not settled (still converging, or periodic only in
        its last half: such a start may show a spurious attractor; lengthen the transient).
    steps : ndarray, int64, shape (ny, nx)
        None when loaded.
    attractors : list of Attractor
    stats : dict
    jobs : JobReport
    records : dict
        Every field of the library's record of each cell by name, shape (ny, nx, ...)
        (``read_tables``' form: the arrays above are taken from it).
    """
    x: str = ""
    y: str = ""
    x_values: np.ndarray = None
    y_values: np.ndarray = None
    tol: Optional[float] = None
    match_tol: Optional[float] = None
    attractor: np.ndarray = None
    label: np.ndarray = None
    period: Optional[np.ndarray] = None
    outcome: Optional[np.ndarray] = None
    settled: Optional[np.ndarray] = None
    steps: Optional[np.ndarray] = None
    attractors: list = field(default_factory=list)
    stats: dict = field(default_factory=dict)
    jobs: Optional[JobReport] = None
    records: dict = field(default_factory=dict)

    @property
    def inadmissible_cells(self):
        return int((self.attractor < 0).sum())

    def __repr__(self):
        found = ", ".join(f"{a.id}: {a.label} ({a.cells} cells)" for a in self.attractors)
        return (f"Basins({self.x} x {self.y}, {len(self.x_values)} x {len(self.y_values)}: "
                f"{len(self.attractors)} attractor(s) {found}; {self.inadmissible_cells} inadmissible)")

    @classmethod
    def of(cls, records, ctx, **run):
        """Basins from the columns of their cells (``read_tables``, or the bindings'), the
        context of the model and what the run says of itself (x, y, x_values, y_values,
        attractors, ...)."""
        r = _shaped(records, (len(run["y_values"]), len(run["x_values"])))
        return cls(attractor=r["attractor"], label=r["label"], period=r["period"], outcome=r["outcome"],
                   settled=r["settled"], steps=r.get("steps"), records=r, **run, **ctx)

    @classmethod
    def load(cls, directory):
        """The result of ``vimpact basins --out DIR``."""
        ctx, res = _loaded(directory)
        attractors = [Attractor(id=t["id"], label=t["label"], cells=t["cells"],
                                cycle=np.array(t["section_points"], dtype=float).reshape(len(t["section_points"]), -1)
                                if t["section_points"] else np.empty((0, 0)))
                      for t in res["attractors"]["table"]]
        return cls.of(read_tables(directory)["cells.csv"], ctx, x=res["x"], y=res["y"],
                      x_values=np.array(res["x_values"], dtype=float), y_values=np.array(res["y_values"], dtype=float),
                      attractors=attractors)


@dataclass(repr=False)
class Response(_Context):
    """The surface-free response over a parameter (lock-in curves; ``vimpact.response``, the
    command ``response``).

    Attributes
    ----------
    param : str
    values : ndarray, float64, shape (n,)
    curves : list of dict
        The parameter values each curve sets (parameter name -> value).
    variable : str
        The state variable measured.
    amplitude : ndarray, float64, shape (c, n)
        max(|maximum|, |minimum|) of the variable on the surface-free attractor.
    maximum, minimum : ndarray, float64, shape (c, n)
        Its largest maximum and smallest minimum over the last block.
    frequency : ndarray, float64, shape (c, n)
        Its angular frequency in the model's time unit.
    grazing_param : str or None
        The parameter whose grazing value ``grazing`` holds (None: ``grazing`` holds each
        surface's margin, the smallest gap).
    grazing : ndarray, float64, shape (c, n, surfaces)
    margin : ndarray, float64, shape (c, n, surfaces)
        The smallest gap of each surface on the surface-free orbit (negative: it crosses it).
    converged : ndarray, bool, shape (c, n)
        The minima settled (False: a quasi-periodic response, say).
    outcome : ndarray, str, shape (c, n)
    steps : ndarray, int64, shape (c, n)
        None when loaded.
    stats : dict
    jobs : JobReport
    records : dict
        Every field of the library's record of each point by name, shape (c, n, ...)
        (``read_tables``' form: the arrays above are taken from it).
    """
    param: str = ""
    values: np.ndarray = None
    curves: list = field(default_factory=list)
    variable: str = ""
    amplitude: np.ndarray = None
    maximum: np.ndarray = None
    minimum: np.ndarray = None
    frequency: np.ndarray = None
    grazing_param: Optional[str] = None
    grazing: np.ndarray = None
    margin: np.ndarray = None
    converged: np.ndarray = None
    outcome: Optional[np.ndarray] = None
    steps: Optional[np.ndarray] = None
    stats: dict = field(default_factory=dict)
    jobs: Optional[JobReport] = None
    records: dict = field(default_factory=dict)

    @property
    def not_converged(self):
        """ndarray, int64, shape (c,): points of each curve whose minima did not settle."""
        return (~self.converged).sum(axis=1)

    def curve_label(self, k):
        """``A = 12, eps = 0.3``: what curve k sets."""
        return ", ".join(f"{n} = {v:g}" for n, v in self.curves[k].items()) or "model's values"

    def __repr__(self):
        peaks = "; ".join(f"{self.curve_label(k)}: peak {np.nanmax(a):.6g}" if np.isfinite(a).any()
                          else f"{self.curve_label(k)}: no amplitude" for k, a in enumerate(self.amplitude))
        return f"Response(param={self.param!r}, {len(self.values)} values, {self.variable}; {peaks})"

    @classmethod
    def of(cls, records, ctx, **run):
        """A response from the columns of its points (``read_tables``, or the bindings'), the
        context of its model and what the run says of itself (param, values, curves, ...)."""
        r = _shaped(records, (len(run["curves"]), len(run["values"])))
        return cls(amplitude=r["amplitude"], maximum=r["maximum"], minimum=r["minimum"], frequency=r["frequency"],
                   grazing=r["grazing"] if run.get("grazing_param") else r["margin"], margin=r["margin"],
                   converged=r["converged"], outcome=r["outcome"], steps=r.get("stats", {}).get("steps"), records=r,
                   **run, **ctx)

    @classmethod
    def load(cls, directory):
        """The result of ``vimpact response --out DIR``."""
        ctx, res = _loaded(directory)
        records = read_tables(directory)["response.csv"]
        curves = [{k: float(v) for k, v in c["parameters"].items()} for c in res["curves"]]
        return cls.of(records, ctx, param=res["param"], values=records["value"][:len(records["value"]) // len(curves)],
                      curves=curves, variable=res["variable"], grazing_param=res["grazing_param"])


# ---------------------------------------------------------------- stability

@dataclass(repr=False)
class Floquet(_Context):
    """Floquet multipliers of the periodic orbit reached (``vimpact.floquet``, the command
    ``floquet``; the paper's Algorithm 1 with the orbit refined by Newton shooting).

    Attributes
    ----------
    status : str
        ``ok``, ``aperiodic`` (no period within the tolerance: no multipliers),
        ``not_converged`` (Newton did not reach ``newton_tol``; multipliers of the last
        iterate), ``sticking``, or how the protocol's run failed.
    label : str
        The protocol's period label.
    section_returns : int
        Section points per period.
    period : float
        The period T (NaN without multipliers).
    impacts_per_period : int
    impacts_by_surface : dict
        Surface name -> impacts per period.
    initial_closure, closure : float
        |P^k(z) - z| before and after Newton shooting.
    newton_iterations : int
    orbit_point : ndarray, float64, shape (dim,)
        The refined point of the orbit on the section.
    monodromy : ndarray, float64, shape (dim, dim)
    multipliers : ndarray, complex128, shape (dim,)
        The trivial multiplier (the flow direction's, 1 up to the error) first, then by
        decreasing modulus; empty without multipliers.
    trivial_error : float
        |mu_trivial - 1|: the accuracy of the monodromy.
    max_nontrivial_modulus : float
    stable : bool or None
        Every nontrivial |mu| < 1 (None without multipliers).
    det_monodromy, liouville_det : float
        det Phi(T) and exp(integral of div F) * prod det S: equal for a correct monodromy.
    orbit_t, orbit : ndarray, float64, shapes (m,), (m, dim)
        The refined orbit over one period, sampled every ``sample_dt`` (empty when 0).
    impact_t, impact_surface, impact_pre, impact_post : ndarray
        Its impacts, shapes (k,), (k,), (k, dim), (k, dim).
    section_t, section : ndarray
        The protocol's recorded section points, shapes (n,), (n, dim).
    stats : dict
        ``protocol`` and ``tangent`` RunStats, ``map_evaluations``.
    si : dict or None
        Loaded from a run with ``--si``: its run.json's ``si`` (the scales in ``values``, the
        SI columns of ``orbit.csv`` in ``columns``) and ``period_si`` [s].
    """
    status: str = "ok"
    label: str = ""
    section_returns: int = 0
    period: float = np.nan
    impacts_per_period: int = 0
    impacts_by_surface: dict = field(default_factory=dict)
    initial_closure: float = np.nan
    closure: float = np.nan
    newton_iterations: int = 0
    orbit_point: np.ndarray = None
    monodromy: np.ndarray = None
    multipliers: np.ndarray = None
    trivial_error: float = np.nan
    trivial_residual: float = np.nan
    max_nontrivial_modulus: float = np.nan
    stable: Optional[bool] = None
    det_monodromy: float = np.nan
    liouville_det: float = np.nan
    divergence_integral: float = np.nan
    log_det_jumps: float = np.nan
    impact_map: str = "saltation"
    orbit_t: np.ndarray = None
    orbit: np.ndarray = None
    impact_t: np.ndarray = None
    impact_surface: np.ndarray = None
    impact_pre: np.ndarray = None
    impact_post: np.ndarray = None
    section_t: np.ndarray = None
    section: np.ndarray = None
    stats: dict = field(default_factory=dict)
    si: dict = None

    def __repr__(self):
        if self.multipliers is None or not len(self.multipliers):
            return f"Floquet(label={self.label!r}, status={self.status!r}: no multipliers)"
        mus = ", ".join(f"{m.real:.6g}{m.imag:+.3g}j" if m.imag else f"{m.real:.6g}" for m in self.multipliers)
        return (f"Floquet(label={self.label!r}, status={self.status!r}, T={self.period:.6g}, multipliers [{mus}], "
                f"{'stable' if self.stable else 'unstable'})")

    @classmethod
    def load(cls, directory):
        """The result of ``vimpact floquet --out DIR`` (multipliers, orbit and impacts)."""
        ctx, res = _loaded(directory)
        names = ctx["state_names"]
        mult = read_csv(os.path.join(directory, "multipliers.csv"))
        mus = mult["re"] + 1j * mult["im"] if len(mult.get("re", ())) else np.empty(0, dtype=complex)
        if "trivial" in mult and len(mus):
            order = np.argsort(-mult["trivial"], kind="stable")  # trivial first
            mus = mus[order]
        orbit_path, imp_path = os.path.join(directory, "orbit.csv"), os.path.join(directory, "impacts.csv")
        orbit = read_csv(orbit_path) if os.path.exists(orbit_path) else {"t": np.empty(0)}
        imp = read_mixed(imp_path) if os.path.exists(imp_path) else {"t": np.empty(0)}
        surface = _surface_column(imp, list(ctx["surfaces"]))
        return cls(status=res.get("outcome", res.get("status", "ok")), label=res.get("label", ""),
                   section_returns=res.get("section_returns", 0), period=_num(res.get("period")),
                   impacts_per_period=res.get("impacts_per_period") or 0,
                   closure=_num(res.get("closure")), multipliers=mus, trivial_error=_num(res.get("trivial_error")),
                   max_nontrivial_modulus=_num(res.get("max_nontrivial_modulus")), stable=res.get("stable"),
                   orbit_t=orbit["t"], orbit=_states(orbit, names, len(orbit["t"])), impact_t=imp["t"],
                   impact_surface=surface, impact_pre=_impact_states(imp, names, "before"),
                   impact_post=_impact_states(imp, names, "after"),
                   si=dict(res["si"], period_si=res.get("period_si")) if res.get("si") else None, **ctx)


@dataclass(repr=False)
class Lyapunov(_Context):
    """The Lyapunov spectrum (``vimpact.lyapunov``, the command ``lyapunov``; the paper's
    Algorithm 2).

    Attributes
    ----------
    status : str
        ``ok``, ``time_limit`` (averaged over less than asked), ``sticking``, or how the run
        failed.
    tdm : str
        The mapping of deviations at impacts.
    exponents : ndarray, float64, shape (dim,)
        Descending (NaN when the run failed).
    lle_standard_error : float
        Of the largest exponent, from 8 block means.
    positive : bool
        The library's verdict: the largest exponent lies more than 3 standard errors above 0.
    settled : bool
        False when the largest exponent drifts: its means over the two halves of the
        averaging differ by more than 4 standard errors (lengthen the transient or averaging).
    t_start, time : float
        Start and length of the averaging window.
    impacts, intervals, misses : int
    impacts_by_surface : dict
    divergence_average, jump_log_det_rate, sum_rule : float
        <div F>, (1/T) sum ln|det S| and their sum, which the exponents must add up to
        (tangent mappings only).
    history_t : ndarray, float64, shape (h,)
    history_growth : ndarray, float64, shape (h, dim)
        ln(R_ii / r0) of every counted interval (QR order); ``running_exponents`` gives the
        running averages.
    section_t, section : ndarray
        Section points of the averaging window (``record > 0``).
    stats : dict
        ``transient`` and ``tangent`` RunStats.
    """
    status: str = "ok"
    tdm: str = "saltation"
    impacting: Optional[bool] = None
    exponents: np.ndarray = None
    lle_standard_error: float = np.nan
    positive: bool = False
    settled: bool = True
    t_start: float = 0.0
    time: float = np.nan
    impacts: int = 0
    impacts_by_surface: dict = field(default_factory=dict)
    intervals: int = 0
    divergence_average: float = np.nan
    jump_log_det_rate: float = np.nan
    sum_rule: float = np.nan
    misses: int = 0
    history_t: np.ndarray = None
    history_growth: np.ndarray = None
    section_t: np.ndarray = None
    section: np.ndarray = None
    stats: dict = field(default_factory=dict)
    si: dict = None

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

    @classmethod
    def load(cls, directory):
        """The result of ``vimpact lyapunov --out DIR`` (its running estimates, not the
        per-interval growth)."""
        ctx, res = _loaded(directory)
        conv = read_csv(os.path.join(directory, "convergence.csv"))
        lam = sorted((k for k in conv if re.fullmatch(r"lambda\d+", k)), key=lambda k: int(k[6:]))
        t_start = float(res.get("t_start", 0.0))
        running = _states(conv, lam, len(conv["t"]))
        # Back from running averages to per-interval growth, so running_exponents round-trips.
        elapsed = (conv["t"] - t_start)[:, None]
        total = running * elapsed
        growth = np.diff(np.vstack([np.zeros((1, len(lam))), total]), axis=0) if len(total) else total
        return cls(status=res.get("outcome", "ok"), tdm=res.get("tdm", "saltation"),
                   exponents=np.array([_num(v) for v in res.get("exponents", [])], dtype=float),
                   lle_standard_error=_num(res.get("lle_standard_error")),
                   positive=_written(res, "positive", os.path.join(directory, "run.json")),
                   settled=res.get("settled", True),
                   t_start=t_start,
                   time=_num(res.get("time")), impacts=res.get("impacts", 0), sum_rule=_num(res.get("sum_rule")),
                   misses=res.get("misses", 0), history_t=conv["t"], history_growth=growth,
                   si=dict(res["si"], exponents_si=res.get("exponents_si")) if res.get("si") else None, **ctx)


@dataclass(repr=False)
class _ValueSweep(_Context, _PointRuns):
    """What a stability sweep holds besides its own arrays: ``param``; ``value`` (n,), the
    value of each run; ``results``, the result of each value with the fields of its record;
    ``points`` and ``point_run``, the section points of every value and the value index of
    each (the bifurcation diagram underneath); ``stats``; ``jobs``; and ``records``, every
    field of the library's record of each value by name (``read_tables``' form)."""
    param: str = ""
    value: np.ndarray = None
    results: list = field(default_factory=list)
    points: np.ndarray = None
    point_run: np.ndarray = None
    stats: dict = field(default_factory=dict)
    jobs: Optional[JobReport] = None
    records: dict = field(default_factory=dict)

    @classmethod
    def _of(cls, result, records, ctx, run, **own):
        """The sweep of the columns of its records (``read_tables``', or the bindings'), the
        context of its model, what the run says of itself (``run``) and its own arrays; each
        value's ``result`` (a spectrum without its NaN, impacts by surface name)."""
        cols, same = dict(records, **own), {"tdm": run["tdm"]} if "tdm" in run else {}
        names = [f.name for f in fields(result) if f.name in cols and f.name != "impacts_by_surface"
                 and not isinstance(cols[f.name], dict)]
        pts, at = records["section_points"], records["section_points_run"]
        cell = lambda v: v[~np.isnan(v)] if np.iscomplexobj(v) else v  # noqa: E731
        results = [result(**{k: cell(cols[k][i]) for k in names}, section=pts[at == i], **same,
                          impacts_by_surface=dict(zip(ctx["surfaces"], records["impacts_by_surface"][i].tolist())),
                          **ctx) for i in range(len(records["value"]))]
        return cls(value=records["value"], results=results, points=pts, point_run=at, records=records, **own,
                   **run, **ctx)

    @classmethod
    def load(cls, directory):
        """The result of ``vimpact floquet`` (``lyapunov``) ``--param P --range a:b:n --out DIR``."""
        ctx, res = _loaded(directory)
        records = {}
        for columns in read_tables(directory).values():
            records.update(columns)
        return cls.of(records, ctx, **{k: res[k] for k in ("param", "tdm") if k in res})


@dataclass(repr=False)
class FloquetSweep(_ValueSweep, _Labels):
    """Floquet multipliers over a range of one parameter (``vimpact.floquet_sweep``, the
    command ``floquet --param P --range a:b:n``; the paper's Figures 14 and 15).

    Attributes
    ----------
    param, value, results (of Floquet: no monodromy, impacts or orbit), points, point_run, stats, jobs, records
        As every stability sweep's (``_ValueSweep``).
    label : ndarray, str, shape (n,)
    multipliers : ndarray, complex128, shape (n, dim)
        NaN rows where there are none (aperiodic or failed points).
    trivial : ndarray, bool, shape (n, dim)
        Marks the trivial multiplier (column 0 where there are multipliers).
    stable : ndarray, object, shape (n,)
        True, False or None.
    """
    label: np.ndarray = None
    multipliers: np.ndarray = None
    trivial: np.ndarray = None
    stable: np.ndarray = None

    def __repr__(self):
        unstable = sum(1 for s in self.stable if s is False)
        return (f"FloquetSweep(param={self.param!r}, {len(self.value)} values: {self._counts_text()}; "
                f"{unstable} unstable)")

    @classmethod
    def of(cls, records, ctx, **run):
        mus = records["multipliers"]
        have = ~np.isnan(mus[:, 0]) if mus.shape[1] else np.zeros(len(mus), dtype=bool)
        trivial = np.zeros(mus.shape, dtype=bool)
        trivial[:, :1] = have[:, None]
        stable = np.array([bool(s == "ok" and m < 1) if h else None for s, m, h in
                           zip(records["status"], records["max_nontrivial_modulus"], have)], dtype=object)
        return cls._of(Floquet, records, ctx, run, label=_str_array(records["label"]),
                       multipliers=mus, trivial=trivial, stable=stable)


@dataclass(repr=False)
class LyapunovSweep(_ValueSweep):
    """Lyapunov exponents over a range of one parameter (``vimpact.lyapunov_sweep``, the
    command ``lyapunov --param P --range a:b:n``; the paper's Figures 16 and 17).

    Attributes
    ----------
    param, value, results (of Lyapunov: no interval history), points, point_run, stats, jobs, records
        As every stability sweep's (``_ValueSweep``; the points those of each averaging
        window, with ``record > 0``).
    exponents : ndarray, float64, shape (n, dim)
    lle : ndarray, float64, shape (n,)
    lle_standard_error : ndarray, float64, shape (n,)
    positive_exponent : ndarray, bool, shape (n,)
        The library's verdict per value: the largest exponent lies more than 3 standard
        errors above 0 (``positive`` counts them).
    settled : ndarray, bool, shape (n,)
        False where the largest exponent drifts between the halves of the averaging.
    status : ndarray, str, shape (n,)
    tdm : str
    """
    exponents: np.ndarray = None
    lle_standard_error: np.ndarray = None
    positive_exponent: np.ndarray = None
    settled: Optional[np.ndarray] = None
    status: np.ndarray = None
    tdm: str = "saltation"

    @property
    def lle(self):
        return self.exponents[:, 0] if len(self.exponents) else np.empty(0)

    @property
    def positive(self):
        """How many values have a positive largest exponent (``positive_exponent``)."""
        return int(np.sum(self.positive_exponent))

    def __repr__(self):
        return (f"LyapunovSweep(param={self.param!r}, {len(self.value)} values, tdm {self.tdm}: {self.positive} "
                f"with a positive largest exponent)")

    @classmethod
    def of(cls, records, ctx, **run):
        return cls._of(Lyapunov, records, ctx, run, exponents=records["exponents"],
                       lle_standard_error=records["lle_standard_error"], positive_exponent=records["positive"],
                       settled=records["settled"], status=_str_array(records["status"]))


# ---------------------------------------------------------------- correlation dimension

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
    columns : tuple of str or None
        The state variables used, when the points came from a result.
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
    columns: Optional[tuple] = None
    options: dict = field(default_factory=dict)

    @property
    def c(self):
        """ndarray, float64, shape (k,): the correlation C(r)."""
        return self.pairs / self.total_pairs if self.total_pairs else np.zeros(len(self.pairs))

    def __repr__(self):
        return (f"Dimension({self.dimension:.4g} +- {self.slope_error:.2g}, {self.estimator} over {self.points} "
                f"points in {self.embedding} coordinates, fit r = {self.fit_range[0]:.3g} .. {self.fit_range[1]:.3g}"
                f"{'' if self.found else ', tolerance NOT met'})")


# ---------------------------------------------------------------- clearance design

@dataclass(repr=False)
class Clearance(_Context, _Labels):
    """Clearance design over a flow parameter (``vimpact.clearance``, the command ``clearance``):
    the smallest gap to the surface without impact at each value (the grazing line), the gaps
    where the response is aperiodic, and the design chart (a period label and the impact
    statistics at each gap).

    Gaps are distances from the rest state to the surface (``-sigma`` for the wake model). The
    arrays ``*_si`` are in SI (metres, m/s, Hz, J/m, W/m for a cylinder) when the run had
    physical units, else None.

    Attributes
    ----------
    param : str
        The flow parameter (``Ur``).
    x : str
        The chart's horizontal quantity: ``U`` with speeds, else ``param``.
    gap_param, surface : str
        The parameter that moves the surface (``sigma``) and the surface.
    value : ndarray, float64, shape (n,)
        The flow parameter's values.
    speed : ndarray, float64, shape (n,), or None
        The flow speeds [m/s].
    grazing_value : ndarray, float64, shape (n,)
        ``gap_param`` at grazing.
    clearance, clearance_si : ndarray, float64, shape (n,)
        The smallest gap without impact (model units, metres).
    converged : ndarray, bool, shape (n,)
        The grazing run converged.
    aperiodic, aperiodic_si : ndarray, float64, shape (n, 2)
        The smallest and largest chart gap with an aperiodic response (NaN where none).
    gap, gap_si : ndarray, float64, shape (n, k)
        The chart's gaps at each value (NaN-padded where a value has fewer).
    label : ndarray, str, shape (n, k)
        The regime at each chart gap: ``P0`` (no impact), ``PN``, ``aperiodic``, or a failed
        run's outcome ("" where padded).
    period, impacts : ndarray, int64, shape (n, k)
    outcome : ndarray, str, shape (n, k)
    statistics, statistics_si : dict
        The impact statistics at each chart gap, name -> ndarray float64 (n, k).
    jobs : JobReport
    """
    param: str = ""
    x: str = ""
    gap_param: str = ""
    surface: str = ""
    value: np.ndarray = None
    speed: Optional[np.ndarray] = None
    grazing_value: np.ndarray = None
    clearance: np.ndarray = None
    clearance_si: Optional[np.ndarray] = None
    converged: np.ndarray = None
    aperiodic: np.ndarray = None
    aperiodic_si: Optional[np.ndarray] = None
    gap: np.ndarray = None
    gap_si: Optional[np.ndarray] = None
    label: np.ndarray = None
    period: np.ndarray = None
    impacts: np.ndarray = None
    outcome: np.ndarray = None
    statistics: dict = field(default_factory=dict)
    statistics_si: Optional[dict] = None
    warnings: tuple = ()
    stats: dict = field(default_factory=dict)
    jobs: Optional[JobReport] = None

    @property
    def x_values(self):
        """The chart's horizontal values: the speeds, else the parameter's values."""
        return self.speed if self.speed is not None else self.value

    @property
    def label_counts(self):
        """How many chart cells carry each label (padding left out)."""
        return label_counts([lab for lab in np.asarray(self.label).ravel() if lab])

    def __repr__(self):
        unit = " m" if self.clearance_si is not None else ""
        c = self.clearance_si if self.clearance_si is not None else self.clearance
        pairs = ", ".join(f"{x:g}: {g:.4g}{unit}" for x, g in zip(self.x_values, c))
        return f"Clearance({self.x} -> gap without impact: {pairs}; chart {self._counts_text()})"

    @staticmethod
    def chart(point, values, n):
        """Per-cell values (cell order: value after value) as an (n, k) array, padded."""
        point = np.asarray(point, dtype=np.int64)
        k = int(np.bincount(point, minlength=n).max()) if len(point) else 0
        values = np.asarray(values)
        pad = "" if values.dtype.kind in "US" else (-1 if values.dtype.kind in "iu" else np.nan)
        out = np.full((n, k), pad, dtype=values.dtype if values.dtype.kind not in "US" else object)
        col = np.zeros(n, dtype=np.int64)
        for p, v in zip(point, values):
            out[p, col[p]] = v
            col[p] += 1
        return out.astype(str) if values.dtype.kind in "US" else out

    @classmethod
    def load(cls, directory):
        """The result of ``vimpact clearance --out DIR``."""
        ctx, res = _loaded(directory)
        param, gname = res["param"], res["gap_param"]
        by_speed = res.get("x") == "U"
        si = res.get("units") == "si"
        cl = read_table(os.path.join(directory, "clearance.csv"))
        ch = read_table(os.path.join(directory, "chart.csv"))

        def num(table, key):
            return np.array([_num(None if v in ("", "nan") else v) for v in table[key]], dtype=float)

        value = num(cl, param)
        n = len(value)
        # Cells are written value after value; their value index from the parameter column.
        cell_value = num(ch, param)
        point = np.searchsorted(value, cell_value) if n and np.all(np.diff(value) > 0) else \
            np.array([int(np.argmin(np.abs(value - v))) for v in cell_value], dtype=np.int64)
        names = res.get("statistics_columns") or ()
        stats = {k: cls.chart(point, v, n) for k, v in _statistics_columns(ch, names).items()}
        stats_si = {k: cls.chart(point, num(ch, k + "_si"), n) for k in names if k + "_si" in ch} if si else None
        return cls(param=param, x=res.get("x", param), gap_param=gname, surface=res.get("surface", ""), value=value,
                   speed=num(cl, "U") if by_speed else None, grazing_value=num(cl, gname + "_graze"),
                   clearance=num(cl, "clearance"), clearance_si=num(cl, "clearance_si") if si else None,
                   converged=num(cl, "converged") > 0.5,
                   aperiodic=np.column_stack([num(cl, "aperiodic_min"), num(cl, "aperiodic_max")]),
                   aperiodic_si=np.column_stack([num(cl, "aperiodic_min_si"), num(cl, "aperiodic_max_si")])
                   if si else None,
                   gap=cls.chart(point, num(ch, "gap"), n),
                   gap_si=cls.chart(point, num(ch, "gap_si"), n) if si else None,
                   label=cls.chart(point, _str_array(ch["label"]), n),
                   period=cls.chart(point, np.array(ch["period"], dtype=float).astype(np.int64), n),
                   impacts=cls.chart(point, np.array(ch["impacts"], dtype=float).astype(np.int64), n),
                   outcome=cls.chart(point, _str_array(ch["outcome"]), n), statistics=stats, statistics_si=stats_si,
                   warnings=tuple(res.get("warnings") or ()), **ctx)
