"""Result objects of vimpact's analyses, and readers that load the command line's output
directories (``vimpact COMMAND ... --out DIR``) into the same objects.

Pure Python and numpy (no matplotlib): the plotting modules import this one, never the reverse,
and the command line's pictures are drawn through it without the compiled module. Where that
module is there, the classes document the library's records from its description of them
(``vimpact._vimpact.described``), which is also run.json's schema of each table.

Every result carries the model's ``parameters`` (a dict), its ``state_names`` (state columns
of every array of states are in this order), its ``surfaces``, the meaning and unit of each
state variable (``state_info``) and parameter (``parameter_info``), the ``plot_variable`` its
pictures show, the effective ``options`` of the run, its ``stats`` and numpy arrays. Arrays of
a grid are indexed ``[iy, ix]`` (rows follow the y axis). A result of many runs holds every
field of the library's record of each run in ``records`` and gives each as an attribute.
"""
import csv
import functools
import inspect
import json
import os
import re
import textwrap
from dataclasses import dataclass, field, fields
from typing import Optional

import numpy as np

from .frames import CurveFrames, ImpactFrames, RunFrames, SurfaceFrames

try:  # the records' descriptions, for the documentation only
    from ._vimpact import described as _DESCRIBED
except ImportError:
    _DESCRIBED = None


# ---------------------------------------------------------------- reading the command line's files

def read_csv(path):
    """A vimpact CSV of numbers (a header line, then rows) as a dict of float64 column arrays."""
    with open(path) as f:
        header = [h.strip() for h in f.readline().strip().split(",")]
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2).reshape(-1, len(header))
    return {name: data[:, i] for i, name in enumerate(header)}


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
    flat = [str(x) for x in np.asarray(labels).ravel()]
    return {lab: flat.count(lab) for lab in label_order(flat)}


def _num(v):
    return np.nan if v is None else float(v)


def _str_array(items, shape=None):
    a = np.array(list(items), dtype=str)
    if a.size == 0:
        a = np.array([], dtype="<U1")
    return a.reshape(shape) if shape is not None else a


def _older(what):
    """What a directory that lacks something this vimpact writes raises."""
    return ValueError(f"{what}: it was written by an older vimpact; run the command again")


def _reader(load):
    """A result's ``load(directory)``, saying so when the directory lacks a key or column."""
    @functools.wraps(load)
    def read(cls, directory):
        try:
            return load(cls, directory)
        except KeyError as e:
            raise _older(f"{directory} has no {e}") from None
    return classmethod(read)


def model_quantities(state, parameters):
    """(state_info, parameter_info) of a result from a model's description of its state
    variables and parameters, each a list of dicts with a name (``Model.info``, run.json's
    ``state_info``) or a dict by name (run.json's ``parameter_info``): ``state_info`` a tuple
    of dicts name, meaning, unit in the model's order, ``parameter_info`` name -> {meaning, unit}."""
    def described(entries):
        entries = [dict(e, name=n) for n, e in entries.items()] if isinstance(entries, dict) else entries or ()
        return {e["name"]: {"meaning": e.get("meaning") or "", "unit": e.get("unit") or ""} for e in entries}
    return tuple(dict(name=n, **e) for n, e in described(state).items()), described(parameters)


def _context(record):
    """What every loaded result carries, from run.json: the model's parameters, state names,
    surfaces, plot variable, options and preset (all empty for a run of no model, such as the
    dimension of a points file)."""
    cfg, model = record.get("config") or {}, record.get("model") or {}
    state = tuple(model.get("state_names", ()))
    state_info, parameter_info = model_quantities(model.get("state_info"), model.get("parameter_info"))
    return dict(parameters=dict(model.get("parameters", {})), state_names=state,
                surfaces=tuple(model.get("surfaces", ())), switches=tuple(model.get("switches", ())), state_info=state_info, parameter_info=parameter_info,
                plot_variable=record.get("plot_variable"), options=cfg, preset=cfg.get("preset"),
                model_name=model.get("name"))


def _loaded(directory):
    """What a result loaded from DIR starts from: its context (``_context``) and the result
    summary of its run.json."""
    record = read_record(directory)
    return _context(record), record["result"]


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
        if "surface" in c or "state" in c or "switch" in c:
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
    """Columns of records with text columns as str arrays and, for a grid, their first axis
    made the grid's ``shape`` (rows follow y)."""
    out = {}
    for name, c in columns.items():
        if isinstance(c, dict):
            out[name] = _shaped(c, shape)
        elif isinstance(c, list):
            out[name] = _str_array(c, shape)
        else:
            out[name] = c if shape is None else np.asarray(c).reshape(tuple(shape) + np.shape(c)[1:])
    return out


def read_tables(directory):
    """The tables of ``vimpact COMMAND --out DIR`` as run.json's ``tables`` describes them:
    file name -> the columns of its records, as the Python API's calls return them."""
    record = read_record(directory)
    if "tables" not in record:
        raise _older(f"{directory}/run.json does not describe its tables")
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


def _impacts(directory, ctx):
    """DIR/impacts.csv as the bindings give a run's impacts: their times, surfaces (indices),
    states before and after (a variable an impact changes has columns NAME_before and
    NAME_after, the others one column) and normal and rebound velocities and energies."""
    path = os.path.join(directory, "impacts.csv")
    table = read_table(path) if os.path.exists(path) else {"t": [], "surface": []}
    num = {k: np.array(v, dtype=float) for k, v in table.items() if k != "surface"}
    n, names = len(num["t"]), ctx["state_names"]

    def states(when):
        return _states({k: num.get(f"{k}_{when}", num.get(k)) for k in names}, names, n)

    def column(name):  # NaN where the directory has no such column
        return num.get(name, np.full(n, np.nan))
    return dict(impact_t=num["t"], impact_surface=np.array([ctx["surfaces"].index(s) for s in table["surface"]],
                                                           dtype=np.int64),
                impact_pre=states("before"), impact_post=states("after"), impact_velocity=column("normal_velocity"),
                impact_rebound=column("rebound_velocity"), impact_energy=column("energy"))


def _switchings(directory, ctx):
    """DIR/switchings.csv as the bindings give a run's crossings of switches: their times,
    switches (indices into ``switches``) and states before and after (NAME, NAME_after)."""
    path, names = os.path.join(directory, "switchings.csv"), ctx["state_names"]
    table = read_table(path) if os.path.exists(path) else {"t": [], "switch": []}
    num = {k: np.array(v, dtype=float) for k, v in table.items() if k != "switch"}
    n = len(num["t"])
    return dict(switching_t=num["t"], switching_surface=np.array([ctx["switches"].index(s) for s in table["switch"]],
                                                                 dtype=np.int64),
                switching_pre=_states({k: num[k] for k in names if k in num}, names, n),
                switching_post=_states({k: num[f"{k}_after"] for k in names if f"{k}_after" in num}, names, n))


def _picked(cls, values):
    """Those of ``values`` that are fields of dataclass ``cls``, by name: run.json's result
    (null NaN where the field is a number, lists as arrays), loaded files."""
    return {f.name: np.nan if values[f.name] is None and isinstance(f.default, float) else np.array(
        values[f.name], dtype=float) if isinstance(values[f.name], list) else values[f.name]
        for f in fields(cls) if f.name in values}


def _si(res, extra):
    """run.json's ``si`` of a run in SI units with its result's ``extra`` key, else None."""
    return dict(res["si"], **{extra: res.get(extra)}) if res.get("si") else None


# ---------------------------------------------------------------- attributes described once

def _a(what, doc="", default=None):
    """A result's attribute declared with its documentation, once: what it is (type, shape),
    what it means, and its default (a type, such as dict, is called for each result)."""
    made = dict(default_factory=default) if isinstance(default, type) else dict(default=default)
    return field(**made, metadata={"what": what, "doc": doc})


def _kind(f, shape):
    """What the attribute of a record's field ``f`` is: for one run (``shape`` "") a value,
    for many runs an array whose first axes are ``shape`` ("runs", "ny, nx")."""
    scalar = {"text": "str"}.get(f["type"], f["type"])
    if f["type"] == "group" or f["span"] == "series":
        return "dict" if f["type"] == "group" else "ndarray, float64, shape (points, dim)"
    if not shape and f["span"] in ("per_surface", "per_switch"):
        return f"dict, {f['span'][4:]} name -> {scalar}"
    dims = ", ".join(d for d in (shape, {"per_surface": "surfaces", "per_switch": "switches", "per_state": "dim",
                                         "spectrum": "dim"}.get(f["span"])) if d)
    dtype = {"int": "int64", "float": "float64", "complex": "complex128"}.get(f["type"], scalar)
    return f"ndarray, {dtype}, shape ({dims}{'' if ',' in dims else ','})" if dims else scalar


def _meaning(f):
    return f["meaning"] + (f" [{f['unit']}]" if f["unit"] else "")


def _documented(record=None, shape="", **renamed):
    """Writes a result class's Attributes: its fields declared with ``_a``, then the fields of
    the library's record ``record`` (a name in ``_vimpact.described``, or a list of fields),
    each under the name the class gives it (``renamed``: field -> attribute, None for none)."""
    def entry(name, what, doc):
        return [f"{name} : {what}"] + textwrap.wrap(doc, 92, initial_indent="    ", subsequent_indent="    ",
                                                   break_on_hyphens=False)

    def document(cls):
        cls._record = record if isinstance(record, str) else None
        cls._aliases = {new: old for old, new in renamed.items() if new} | {
            new + "_t": old + "_t" for old, new in renamed.items() if new and not shape}
        lines = ["", "Attributes", "----------"]
        for f in fields(cls):
            lines += entry(f.name, f.metadata["what"], f.metadata["doc"]) if "what" in f.metadata else []
        described = (_DESCRIBED or {}).get(record, ()) if isinstance(record, str) else record or ()
        if isinstance(record, str) and not _DESCRIBED:
            lines.append(f"The fields of the library's record {record} (the compiled module describes them).")
        for f in described:
            name = renamed.get(f["name"], f["name"])
            doc = _meaning(f)
            if f["type"] == "group":
                doc += ": " + "; ".join(f"{g['name']} ({_meaning(g)})" for g in f["fields"])
            if shape and not f["tabular"]:
                doc += " (not a column: None when loaded)"
            lines += entry(name, _kind(f, shape), doc) if name else []
            if name and f["span"] == "series" and not shape:
                lines += entry(name + "_t", "ndarray, float64, shape (points,)", "Their times.")
        cls.__doc__ = inspect.cleandoc(cls.__doc__) + "\n" + "\n".join(lines) + "\n"
        return cls
    return document


class _ByName:
    """The fields of the library's record of a run (``record``) or of each run (``records``)
    by name, each an attribute of the same name or of the name the class documents it under
    (``_documented``), else of the result ``_then`` names."""
    _store, _aliases, _record, _then = "records", {}, None, None

    def __getattr__(self, name):
        store, key = self.__dict__.get(self._store) or {}, self._aliases.get(name, name)
        if key in store and not name.startswith("__"):
            return store[key]
        if self._store == "records" and any(f["name"] == key for f in (_DESCRIBED or {}).get(self._record, ())):
            return None  # a field that is not a column, of a loaded result
        if self._then and not name.startswith("__") and name != self._then:
            return getattr(getattr(self, self._then), name)
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def __dir__(self):
        described = {f["name"] for f in (_DESCRIBED or {}).get(self._record, ())} if self._store == "records" else ()
        return sorted(set(super().__dir__()) | set(self._aliases) | set(self.__dict__.get(self._store) or ()) |
                      set(described))


def _loaded_record(cls, res, held=(), **mapped):
    """The record of a single run loaded from run.json's result: its values by name (JSON
    null, a number the run does not have, as NaN; lists as arrays) but those the class (or
    ``held``) holds otherwise, with ``mapped`` where the command writes a field in another form."""
    own = {f.name for f in fields(cls)} | set(held) | {"command", "out", "si"}
    return dict({k: np.nan if v is None else np.array(v, dtype=float) if isinstance(v, list) else v
                 for k, v in res.items() if k not in own and not hasattr(cls, k) and not k.endswith("_si")}, **mapped)


# ---------------------------------------------------------------- run statistics and job reports

@_documented("run_stats")
@dataclass(frozen=True, repr=False)
class RunStats(_ByName):
    """Counters of one run, whatever its outcome."""
    _store = "record"
    record: dict = _a("dict", "The counters by name (below).", dict)

    @classmethod
    def from_dict(cls, d):
        """From the counters by name (the bindings', run.json's; no smallest step, null, is infinite)."""
        d = dict(d or {})
        return cls(dict(d, h_min=np.inf if d.get("h_min") is None else d["h_min"]))

    def __repr__(self):
        return f"RunStats({', '.join(f'{k}={v!r}' for k, v in self.record.items())})"


@_documented()
@dataclass(repr=False)
class JobReport:
    """What a many-job run did, and all it returns when it is not complete: a shard whose
    partners have not finished (run again with ``resume=True`` and the same journal, without
    ``shard``, once they have: that call computes nothing and returns the whole result)."""
    jobs: int = _a("int", "Jobs of the whole run.")
    owned: int = _a("int", "Jobs of this shard.")
    resumed: int = _a("int", "Of them, found in the journal.")
    computed: int = _a("int", "Computed by this call.")
    done: int = _a("int", "Jobs of the whole run with a result.")
    complete: bool = _a("bool")
    threads: int = _a("int")
    stopped: bool = _a("bool", "Ctrl-C (or an exception from ``progress``) ended the call early.", False)
    written_elsewhere: bool = _a("bool", "A shard that found the journal removed at its end: another shard "
                                 "completed the run (and its caller wrote the outputs and removed the journal).", False)
    journal: Optional[str] = _a("str or None")

    @classmethod
    def from_dict(cls, d, journal=None):
        return cls(**_picked(cls, dict(d, journal=journal)))

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
    switches: tuple = ()  #: the model's switching surfaces (the field changes across them)
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
    _series = "points"  # the record's field of section points

    @property
    def point_run(self):
        """ndarray, int64, shape (points,): the run of each section point."""
        return self.records[self._series + "_run"]

    @property
    def point_value(self):
        """ndarray, float64, shape (points,): the parameter value of each section point."""
        return self.value[self.point_run]


class _Loads:
    """A single run's ``load(DIR)``: run.json's result and the model's context by name, the
    impacts (impacts.csv), the timed states of each file of ``_timed_files`` (attributes NAME
    and NAME_t), run.json's ``si`` with its key ``_si_key`` (``--si``), and what ``_read`` adds."""
    _timed_files, _si_key = {}, None

    @_reader
    def load(cls, directory):
        """The result of ``vimpact COMMAND --out DIR``."""
        ctx, res = _loaded(directory)
        values = dict(res, **ctx, **_impacts(directory, ctx), **_switchings(directory, ctx), si=_si(res, cls._si_key))
        for name, file in cls._timed_files.items():  # none where the run wrote no such file
            path = os.path.join(directory, file)
            c = read_csv(path) if os.path.exists(path) else {"t": np.empty(0)}
            values[name + "_t"], values[name] = c["t"], _states(c, ctx["state_names"], len(c["t"]))
        return cls(**_picked(cls, dict(values, **cls._read(res, directory))))


@dataclass(repr=False)
class _Impacts:
    """The impacts of a run (impacts.csv)."""
    impact_t: np.ndarray = _a("ndarray, float64, shape (k,)", "Times of the impacts.")
    impact_surface: np.ndarray = _a("ndarray, int64, shape (k,)", "The surface hit (an index into ``surfaces``).")
    impact_pre: np.ndarray = _a("ndarray, float64, shape (k, dim)", "States just before each impact.")
    impact_post: np.ndarray = _a("ndarray, float64, shape (k, dim)", "States just after each impact.")


# ---------------------------------------------------------------- single runs

@_documented([dict(name="statistics", type="group", span="one", unit="", tabular=True,
                   meaning="the impact statistics of the recorded window (docs/model.md; NaN where undefined, "
                           "a per-surface one a list)", fields=(_DESCRIBED or {}).get("impact_statistics", []))])
@dataclass(repr=False)
class Simulation(_Context, _Impacts, _Loads, ImpactFrames):
    """A run of the protocol (``vimpact.simulate``, the command ``simulate``; ``load`` reads
    the points of ``period --out DIR`` too): its impacts are those of the recorded window."""
    _timed_files, _si_key = {"section": "sections.csv", "series": "timeseries.csv"}, "impact_statistics_si"
    outcome: str = _a("str", "``ok`` or how the run ended early (``time_limit``, ``step_limit``, ``non_finite``, "
                      "``chattering``, ...).", "ok")
    impacting: Optional[bool] = _a("bool", "False when no impact happened for ``quiet_time``: the recorded points "
                                   "then describe the surface-free steady state (label P0).")
    transient_impacts: Optional[int] = _a("int", "Impacts discarded before recording (None when loaded).")
    t_record_start: Optional[float] = _a("float", "Time at which recording began.")
    final_state: Optional[np.ndarray] = _a("ndarray, float64, shape (dim,)")
    section_t: np.ndarray = _a("ndarray, float64, shape (n,)")
    section: np.ndarray = _a("ndarray, float64, shape (n, dim)", "The recorded section points (states, "
                             "columns as ``state_names``).")
    series_t: np.ndarray = _a("ndarray, float64, shape (m,)")
    series: np.ndarray = _a("ndarray, float64, shape (m, dim)", "The recorded window sampled every ``sample_dt`` "
                            "(empty when ``sample_dt = 0``).")
    stats: RunStats = _a("RunStats", "", RunStats)
    t_record_end: Optional[float] = _a("float", "End of the recorded window (its last point), the end of the "
                                       "statistics' window.")
    statistics: dict = field(default_factory=dict)
    switching_t: np.ndarray = _a("ndarray, float64, shape (c,)", "Times of the crossings of switches in the "
                                 "recorded window (``switchings.csv``).")
    switching_surface: np.ndarray = _a("ndarray, int64, shape (c,)", "The switch crossed (an index into "
                                       "``switches``).")
    switching_pre: np.ndarray = _a("ndarray, float64, shape (c, dim)", "States at each crossing, before its "
                                   "reset.")
    switching_post: np.ndarray = _a("ndarray, float64, shape (c, dim)", "States after it (the same without a "
                                    "reset).")
    impact_velocity: np.ndarray = _a("ndarray, float64, shape (k,)", "Per impact: the normal velocity -dg/dt "
                                     "before the reset.")
    impact_rebound: np.ndarray = _a("ndarray, float64, shape (k,)", "Its rebound velocity dg/dt after the reset.")
    impact_energy: np.ndarray = _a("ndarray, float64, shape (k,)", "The energy it dissipated, (v^2 - u^2)/2 per "
                                   "unit mass.")
    si: Optional[dict] = _a("dict or None", "A run in SI units (``--si``; None otherwise): run.json's ``si`` "
                            "(``values``: the SI value of one model unit, ``length_scale``, ``time_scale``, "
                            "``velocity_scale``, ...; ``columns``: the SI columns of the CSV files and their "
                            "units) and ``impact_statistics_si``. The arrays above stay in the model's units.")

    def __repr__(self):
        return (f"Simulation(outcome={self.outcome!r}, {len(self.section_t)} section points, "
                f"{len(self.impact_t)} impacts recorded, {len(self.series_t)} samples, "
                f"{self.stats.impacts} impacts in all, {self.stats.steps} steps)")

    @classmethod
    def _read(cls, res, directory):
        statistics = {k: [_num(x) for x in v.values()] if isinstance(v, dict) else int(v)
                      if k == "impacts_recorded" else _num(v) for k, v in res.get("impact_statistics", {}).items()}
        return dict(statistics=statistics, stats=RunStats.from_dict(res.get("stats")))


@dataclass(repr=False)
class _Run(_Context, _ByName, _Loads):
    """A single run of an analysis whose record the library describes: the record's fields
    by name in ``record``, each an attribute (below)."""
    _store = "record"
    record: dict = _a("dict", "Every field of the library's record of the run by name (below).", dict)


@_documented("period")
@dataclass(repr=False)
class Period(_ByName):
    """The period label of the attractor (``vimpact.period``, the command ``period``); the
    run's context (``parameters``, ``state_names``, ``outcome``, ``stats``, ...) is its
    ``simulation``'s."""
    _store, _then = "record", "simulation"
    record: dict = _a("dict", "Every field of the library's label by name (below).", dict)
    tol: Optional[float] = _a("float", "The period tolerance used.")
    simulation: Simulation = _a("Simulation", "The run that was classified (its section points, impacts and "
                                "statistics).")

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

    @_reader
    def load(cls, directory):
        """The result of ``vimpact period --out DIR``."""
        res, simulation = read_record(directory)["result"], Simulation.load(directory)
        label = _loaded_record(cls, res, simulation.__dict__, period=-1 if res["period"] is None else res["period"])
        return cls(record=label, tol=res["tolerance"], simulation=simulation)


_PER_SURFACE = "ndarray, float64, shape (surfaces,)"


@_documented()
@dataclass(repr=False)
class Grazing(_Context, SurfaceFrames):
    """Where the attracting surface-free orbit just touches each surface, and the switch-free
    orbit each switch (``vimpact.grazing``, the command ``grazing``)."""
    param: tuple = _a("tuple of (str or None)", "Per surface, the parameter whose grazing value ``value`` gives "
                      "(None: no parameter moves that surface).", ())
    value: np.ndarray = _a(_PER_SURFACE, "The grazing value of ``param`` per surface: a surface just on the "
                           "admissible side of it is never hit, one just beyond it is (NaN where none).")
    margin: np.ndarray = _a(_PER_SURFACE, "The smallest gap on the surface-free orbit (negative: the free orbit "
                            "crosses it).")
    converged: bool = _a("bool", "Every surface's minimum settled within ``tol``.", False)
    surface_converged: np.ndarray = _a("ndarray, bool, shape (surfaces,)")
    change: np.ndarray = _a(_PER_SURFACE, "The last block-to-block change of the minimum gap.")
    t: np.ndarray = _a(_PER_SURFACE, "Time of the minimum gap.")
    x: np.ndarray = _a("ndarray, float64, shape (surfaces, dim)", "State there (NaN before a block completes).")
    minima: np.ndarray = _a("ndarray, int64, shape (surfaces,)")
    variable: Optional[str] = _a("str or None", "The state variable whose response was measured.")
    response_max: float = _a("float", "Its largest maximum over the last block.", np.nan)
    response_min: float = _a("float", "Its smallest minimum over the last block.", np.nan)
    response_omega: float = _a("float", "Its angular frequency.", np.nan)
    outcome: str = _a("str", "", "ok")
    stats: RunStats = _a("RunStats", "", RunStats)
    by_switch: dict = _a("dict", "Switch name -> {param, value, margin, converged, change, t, x, minima}, as "
                         "``by_surface``: the switch-free orbit (the sides of the start held) and its distance side * h "
                         "to each switch (negative: it would cross).", dict)

    @property
    def by_surface(self):
        """dict: surface name -> {param, value, margin, converged, change, t, x, minima}."""
        return {s: dict(param=self.param[i], value=float(self.value[i]), margin=float(self.margin[i]),
                        converged=bool(self.surface_converged[i]), change=float(self.change[i]), t=float(self.t[i]),
                        x=self.x[i], minima=int(self.minima[i])) for i, s in enumerate(self.surfaces)}

    def __repr__(self):
        parts = ", ".join(f"{s}: {p} = {v:.10g}" if p else f"{s}: margin {m:.10g}"
                          for s, p, v, m in zip(self.surfaces, self.param, self.value, self.margin))
        parts += "".join(f", switch {s}: {w['param']} = {w['value']:.10g}" if w["param"] else
                         f", switch {s}: margin {w['margin']:.10g}" for s, w in self.by_switch.items())
        conv = "" if self.converged else ", NOT converged"
        return f"Grazing({parts}{conv}, outcome={self.outcome!r})"


# ---------------------------------------------------------------- many-job analyses

@dataclass(repr=False)
class _Records(_Context, _ByName, RunFrames):
    """A result of many runs: ``records`` holds every field of the library's record of each run
    by name (``read_tables``' form, text as str arrays, a grid's cells shaped), and each field
    is an attribute of the same name unless the class says otherwise."""
    stats: dict = _a("dict", "The run's counters in all and its ``wall_time`` in seconds.", dict)
    jobs: Optional[JobReport] = _a("JobReport")
    records: dict = _a("dict", "Every field of the library's record of each run by name (below), a field added "
                       "to it included.", dict)

    @property
    def steps(self):
        """ndarray, int64: the accepted steps of each run (None when loaded: not a column)."""
        return self.records.get("steps", self.records.get("stats", {}).get("steps"))

    def _grid(self):
        """The shape of the runs where they form a grid, else None."""
        return None

    def _spans(self):
        """The span of each field by name ((group, name) for a group's), from the library's
        description, else from the run.json schema the result was loaded by."""
        fields = (_DESCRIBED or {}).get(self._record, ())
        return {k: v for f in fields for k, v in [(f["name"], f["span"])] + [
            ((f["name"], g["name"]), g["span"]) for g in f.get("fields", ())]} or self.__dict__.get("_schema", {})

    @classmethod
    def of(cls, records, ctx, **run):
        """The result from the columns of its records (``read_tables``', or the bindings'), the
        context of its model and what the run says of itself (param, values, ...)."""
        result = cls(**run, **ctx)
        result.records = _shaped(records, result._grid())
        return result

    @staticmethod
    def _run(res, records, directory):
        """What the run says of itself beyond run.json's result by the attributes' names."""
        return {}

    @_reader
    def load(cls, directory):
        """The result of ``vimpact COMMAND --out DIR``."""
        ctx, res = _loaded(directory)
        records = {k: v for columns in read_tables(directory).values() for k, v in columns.items()}
        run = cls._run(res, records, directory)
        result = cls.of(records, ctx, **_picked(cls, {k: v for k, v in res.items() if k not in run}), **run)
        result._schema = {(c["group"], c["field"]) if "group" in c else c["field"]: "per_surface" if "surface" in c
                          else "per_switch" if "switch" in c else "per_state" if "state" in c else "one"
                          for t in read_record(directory)["tables"].values()
                          for c in t["columns"] if "field" in c}
        return result


@_documented("sweep", "runs", stats=None)
@dataclass(repr=False)
class Sweep(_Records, _Labels, _PointRuns):
    """A bifurcation diagram (``vimpact.sweep``, the command ``sweep``).

    Runs are in job order: the values in the sweep's direction; with ``direction="both"``
    the upward and downward branches interleave (run 2k is the k-th point up, 2k + 1 the k-th
    point down)."""
    param: str = _a("str", "The swept parameter.", "")
    values: np.ndarray = _a("ndarray, float64, shape (n,)", "The values asked for.")
    ic_mode: str = _a("str", "", "fixed")
    direction: str = _a("str", "", "up")
    tol: Optional[float] = _a("float", "Period tolerance.")
    grazing_param: Optional[str] = _a("str or None", "The parameter whose grazing values ``grazing`` holds.")

    @property
    def point_branch(self):
        """ndarray, int64, shape (points,): the branch of each section point."""
        return self.branch[self.point_run]

    def __repr__(self):
        return (f"Sweep(param={self.param!r}, {len(self.values)} values, {self.ic_mode} starts, "
                f"direction {self.direction}: {self._counts_text()}; {len(self.points)} section points)")

    @staticmethod
    def _run(res, records, directory):
        return dict(values=np.unique(records["value"]))


@dataclass(repr=False)
class _Grid(_Records):
    x: str = _a("str", "The quantity on the x axis.", "")
    y: str = _a("str", "The quantity on the y axis.", "")
    x_values: np.ndarray = _a("ndarray, float64, shape (nx,)")
    y_values: np.ndarray = _a("ndarray, float64, shape (ny,)")
    tol: Optional[float] = _a("float", "Period tolerance.")

    def _grid(self):
        return len(self.y_values), len(self.x_values)



@_documented("map", "ny, nx")
@dataclass(repr=False)
class Map(_Grid, _Labels):
    """A periodicity map over two parameters (``vimpact.map``, the command ``map``)."""
    grazing_param: Optional[str] = _a("str or None", "With ``grazing=True``: the axis parameter that moves the "
                                      "surfaces.")
    grazing_other: Optional[np.ndarray] = _a("ndarray, float64, shape (k,)", "Values of the other axis along the "
                                             "grazing line.")
    grazing: Optional[np.ndarray] = _a("ndarray, float64, shape (k, surfaces), or None", "The grazing value of "
                                       "``grazing_param`` per surface at each of them: the boundary between "
                                       "impacting and surface-free motion.")
    switch_grazing: Optional[np.ndarray] = _a("ndarray, float64, shape (k, switches), or None", "The same per "
                                              "switch: the boundary between crossing and switch-free motion.")

    def __repr__(self):
        return f"Map({self.x} x {self.y}, {len(self.x_values)} x {len(self.y_values)}: {self._counts_text()})"

    @staticmethod
    def _run(res, records, directory):
        run, path = {}, os.path.join(directory, "grazing.csv")
        if os.path.exists(path):  # the other axis, then the grazing value per surface, then per switch
            run["grazing_other"], *cols = read_csv(path).values()
            s = len(res["grazing_surfaces"])
            for name, part in (("grazing", cols[:s]), ("switch_grazing", cols[s:])):
                run[name] = np.column_stack(part) if len(run["grazing_other"]) and part else np.empty(
                    (len(run["grazing_other"]), len(part)))
        return run


@_documented()
@dataclass(repr=False)
class Attractor:
    """One attractor of a basins computation."""
    id: int = _a("int", "Numbered in order of first appearance (job order).")
    label: str = _a("str")
    cells: int = _a("int", "Grid cells whose runs reached it.")
    cycle: np.ndarray = _a("ndarray, float64, shape (N, k)", "For a periodic attractor, its N section points in "
                           "the signature's coordinates (the state, with each phase as a (cos, sin) pair scaled "
                           "by its period / 2 pi); empty otherwise.")
    box: Optional[np.ndarray] = _a("ndarray, float64, shape (2, k)", "Bounding box (lower, upper row) of the "
                                   "first run's section points.")

    def __repr__(self):
        return f"Attractor(id={self.id}, label={self.label!r}, cells={self.cells})"


@_documented("basins", "ny, nx")
@dataclass(repr=False)
class Basins(_Grid):
    """Basins of attraction over a grid of initial states (``vimpact.basins``, the command
    ``basins``): the state variables on the axes, the others taken from ``ic``."""
    match_tol: Optional[float] = _a("float", "The tolerance of matching attractors.")
    attractors: list = _a("list of Attractor", "", list)

    @property
    def inadmissible_cells(self):
        return int((self.attractor < 0).sum())

    def __repr__(self):
        found = ", ".join(f"{a.id}: {a.label} ({a.cells} cells)" for a in self.attractors)
        return (f"Basins({self.x} x {self.y}, {len(self.x_values)} x {len(self.y_values)}: "
                f"{len(self.attractors)} attractor(s) {found}; {self.inadmissible_cells} inadmissible)")

    @staticmethod
    def _run(res, records, directory):
        table = res["attractors"]["table"]
        boxes = [np.array(t["box"], dtype=float) for t in table]
        return dict(attractors=[
            Attractor(id=t["id"], label=t["label"], cells=t["cells"], box=box,
                      cycle=np.array(t["section_points"], dtype=float).reshape(-1, box.shape[1]))
            for t, box in zip(table, boxes)])


@_documented("response", "c, n", stats=None, grazing=None)
@dataclass(repr=False)
class Response(_Records):
    """The surface-free response over a parameter (lock-in curves; ``vimpact.response``, the
    command ``response``)."""
    param: str = _a("str", "", "")
    values: np.ndarray = _a("ndarray, float64, shape (n,)")
    curves: list = _a("list of dict", "The parameter values each curve sets (parameter name -> value).", list)
    variable: str = _a("str", "The state variable measured.", "")
    grazing_param: Optional[str] = _a("str or None", "The parameter whose grazing value ``grazing`` holds.")

    def _grid(self):
        return len(self.curves), len(self.values)

    @property
    def grazing(self):
        """ndarray, float64, shape (c, n, surfaces): the grazing value of ``grazing_param`` per
        surface, or without one each surface's ``margin``."""
        return self.records["grazing"] if self.grazing_param else self.margin

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

    @staticmethod
    def _run(res, records, directory):
        curves = [{k: float(v) for k, v in c["parameters"].items()} for c in res["curves"]]
        return dict(values=records["value"][:len(records["value"]) // len(curves)], curves=curves)


# ---------------------------------------------------------------- correlation dimension

@_documented()
@dataclass(repr=False)
class Dimension(CurveFrames):
    """The correlation dimension of a point set (``vimpact.dimension``, the command
    ``dimension``)."""
    dimension: float = _a("float", "The slope of log C against log r over the scaling region (NaN when "
                          "undetermined).")
    found: bool = _a("bool", "The automatic rule met its slope tolerance (or a ``fit_range`` was given).")
    automatic: bool = _a("bool")
    fit_range: tuple = _a("(float, float)", "The radii fitted.")
    r2: float = _a("float")
    slope_error: float = _a("float")
    slope_spread: float = _a("float")
    intercept: float = _a("float")
    fitted: int = _a("int", "Radii in the fit: indices ``fit_first`` .. ``fit_last`` of ``r``.")
    fit_first: int = _a("int")
    fit_last: int = _a("int")
    r: np.ndarray = _a("ndarray, float64, shape (k,)", "Radii of the correlation curve.")
    pairs: np.ndarray = _a("ndarray, int64, shape (k,)", "Pairs closer than each radius; ``c`` = pairs / "
                           "total_pairs.")
    total_pairs: int = _a("int")
    local_slope: np.ndarray = _a("ndarray, float64, shape (k,)", "NaN where not evaluated.")
    centres: np.ndarray = _a("ndarray, int64", "The centres estimator's centre indices (empty for the correlation "
                             "sum).")
    r_cap: float = _a("float", "The correlation sum counted pairs closer than this.")
    all_pairs: bool = _a("bool")
    estimator: str = _a("str")
    points: int = _a("int", "Number of points.")
    embedding: int = _a("int", "Coordinates per point.")
    columns: Optional[tuple] = _a("tuple of str or None", "The state variables used, when the points came from a "
                                  "result.")
    options: dict = field(default_factory=dict)

    @property
    def c(self):
        """ndarray, float64, shape (k,): the correlation C(r)."""
        return self.pairs / self.total_pairs if self.total_pairs else np.zeros(len(self.pairs))

    def __repr__(self):
        return (f"Dimension({self.dimension:.4g} +- {self.slope_error:.2g}, {self.estimator} over {self.points} "
                f"points in {self.embedding} coordinates, fit r = {self.fit_range[0]:.3g} .. {self.fit_range[1]:.3g}"
                f"{'' if self.found else ', tolerance NOT met'})")


# The stability and clearance results live in results_stability.py and results_clearance.py
# (they build on the classes above); vimpact.results still names every result.
from .results_clearance import Clearance  # noqa: E402,F401
from .results_stability import Floquet, FloquetSweep, Lyapunov, LyapunovSweep  # noqa: E402,F401
