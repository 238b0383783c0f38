"""Results as tables and labelled grids: ``to_pandas()`` gives a pandas DataFrame of a result's
rows, ``to_xarray()`` an xarray Dataset of a grid with named coordinates. Both are built from
what a result already holds (its records, section points, impacts, branches), so a field the
library adds to a record appears in them with no change here. pandas and xarray are imported
on first use (Debian's python3-pandas and python3-xarray)."""
import importlib

import numpy as np


def _module(name):
    try:
        return importlib.import_module(name)
    except ImportError as e:
        raise ImportError(f"{name} is not installed: Debian's python3-{name} provides it "
                          f"(bash scripts/install-deps.sh tests)") from e


def _columns(name, values, rows, labels):
    """The columns of one field over `rows` rows: itself, or one per label (NAME_LABEL: the
    surface, state variable or index its described span gives) for a field with a value per
    row and something else."""
    a = np.asarray(values)
    if a.ndim == 0 or a.shape[0] != rows:
        return {}
    if a.ndim == 1:
        return {name: a}
    a = a.reshape(rows, -1)
    names = labels if len(labels) == a.shape[1] else [str(k) for k in range(a.shape[1])]
    return {f"{name}_{n}": a[:, k] for k, n in enumerate(names)}


def _state_frame(states, names, lead):
    """The `lead` columns, then one per state variable."""
    columns = dict(lead)
    states = np.asarray(states, dtype=float).reshape(-1, len(names))
    columns.update({n: states[:, k] for k, n in enumerate(names)})
    return _module("pandas").DataFrame(columns)


class RunFrames:
    """For a result of many runs (``records``): one row per run or cell, and its section points.
    ``_spans()`` gives the described span of each field (name, or (group, name) for a group's)."""

    def _run_count(self):
        shape = self._grid()
        return int(np.prod(shape)) if shape else len(np.asarray(self.records.get("label", self.records.get("value"))))

    def _labels(self, span):
        """The names of the columns of a field of this span: its surfaces, switches or state
        variables."""
        return list({"per_surface": self.surfaces, "per_switch": self.switches,
                     "per_state": self.state_names}.get(span, ()))

    def to_pandas(self, table="runs"):
        """A pandas DataFrame: ``"runs"`` (default), one row per run or grid cell in job order,
        with the grid's coordinates first (named after its axes) and a column per field of the
        record (a field with a value per surface or state variable as NAME_SURFACE,
        NAME_STATE); or ``"points"``, one row per section point with its run, the run's
        parameter value where the result has one, and the state."""
        pd = _module("pandas")
        if table == "points":
            lead = {"run": self.point_run}
            if hasattr(self, "param") and getattr(self, "param", ""):
                lead[self.param] = self.point_value
            return _state_frame(self.points, self.state_names, lead)
        if table != "runs":
            raise ValueError(f"table must be 'runs' or 'points' (got {table!r})")
        rows = self._run_count()
        columns = {}
        shape = self._grid()
        if shape and hasattr(self, "x_values"):
            ny, nx = shape
            columns[self.x] = np.tile(np.asarray(self.x_values, dtype=float), ny)
            columns[self.y] = np.repeat(np.asarray(self.y_values, dtype=float), nx)
        spans = self._spans()

        def flat(values):  # a grid's cells in job order
            a = np.asarray(values)
            return a.reshape(rows, *a.shape[2:]) if shape and a.shape[:2] == tuple(shape) else a

        for name, values in self.records.items():
            fields = values.items() if isinstance(values, dict) else [(None, values)]  # a group: GROUP_FIELD
            for key, v in fields:
                labels = self._labels(spans.get((name, key) if key else name))
                columns.update(_columns(name if key is None else f"{name}_{key}", flat(v), rows, labels))
        return pd.DataFrame(columns)

    def to_xarray(self):
        """An xarray Dataset of a grid (Map, Basins): dimensions named after the y and x axes
        with their values as coordinates, and every field of the cells' record as a variable
        (a field with a value per surface or state variable with a dimension of its own)."""
        shape = self._grid()
        if not (shape and hasattr(self, "x_values")):
            raise TypeError(f"{type(self).__name__} is not a grid: use to_pandas()")
        xr = _module("xarray")
        dims = (self.y, self.x)
        data, spans = {}, self._spans()
        for name, values in self.records.items():
            a = np.asarray(values)
            if isinstance(values, dict) or a.shape[:2] != tuple(shape):
                continue
            if a.ndim == 2:
                data[name] = (dims, a)
            elif a.ndim == 3:
                extra = {"per_surface": "surface", "per_switch": "switch", "per_state": "state"}.get(spans.get(name),
                                                                                                   f"{name}_index")
                data[name] = (dims + (extra,), a)
        coords = {self.y: np.asarray(self.y_values, dtype=float), self.x: np.asarray(self.x_values, dtype=float)}
        if any(d[0][-1] == "surface" for d in data.values()):
            coords["surface"] = list(self.surfaces)
        if any(d[0][-1] == "switch" for d in data.values()):
            coords["switch"] = list(self.switches)
        if any(d[0][-1] == "state" for d in data.values()):
            coords["state"] = list(self.state_names)
        return xr.Dataset(data, coords=coords)


class ImpactFrames:
    """For a single run: its impacts, and its states over time (``_state_tables``: a table's
    name -> the attributes of its times and states) as rows."""
    _state_tables = {"sections": ("section_t", "section"), "series": ("series_t", "series")}

    def to_pandas(self, table="impacts"):
        """A pandas DataFrame: ``"impacts"`` (default; time, surface, the state before and
        after as NAME_pre, NAME_post), or time and state of each row of a state table:
        ``"sections"`` (the section points) and ``"series"`` (the samples) of a Simulation,
        ``"orbit"`` (the refined orbit's samples) of a Floquet result."""
        names = list(self.state_names)
        if table == "impacts":
            columns = {"t": self.impact_t, "surface": [self.surfaces[int(i)] for i in self.impact_surface]}
            for when, states in (("pre", self.impact_pre), ("post", self.impact_post)):
                states = np.asarray(states, dtype=float).reshape(-1, len(names))
                columns.update({f"{n}_{when}": states[:, k] for k, n in enumerate(names)})
            return _module("pandas").DataFrame(columns)
        if table in self._state_tables:
            t, states = (getattr(self, a) for a in self._state_tables[table])
            return _state_frame(np.asarray(states).reshape(len(t), len(names)), names, {"t": t})
        tables = ", ".join(repr(k) for k in ("impacts", *self._state_tables))
        raise ValueError(f"table must be one of {tables} (got {table!r})")


class BranchFrames:
    """For a continuation: its branches' points and its bifurcations as rows."""

    def to_pandas(self, table="branches"):
        """A pandas DataFrame: ``"branches"`` (default; one row per point of every branch: the
        branch, the parameter, period, stability, impacts, closure and state) or
        ``"bifurcations"`` (type, parameter, branch, surface and state of each)."""
        pd = _module("pandas")
        names = list(self.state_names)
        if table == "branches":
            frames = []
            for b in self.branches:
                lead = {"branch": np.full(len(b.param), b.index), self.param: b.param, "period": b.period,
                        "stable": b.stable, "impacts": b.impacts, "closure": b.closure}
                frames.append(_state_frame(b.state, names, lead))
            return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame(
                columns=["branch", self.param, "period", "stable", "impacts", "closure", *names])
        if table == "bifurcations":
            rows = [dict(type=f.type, **{self.param: f.param}, branch=f.branch, surface=f.surface,
                         **{n: f.state[k] for k, n in enumerate(names)}) for f in self.bifurcations]
            return pd.DataFrame(rows, columns=["type", self.param, "branch", "surface", *names])
        raise ValueError(f"table must be 'branches' or 'bifurcations' (got {table!r})")


class ClearanceFrames:
    """For clearance design: its values (the grazing line) and its chart's cells as rows."""

    def to_pandas(self, table="values"):
        """A pandas DataFrame with the columns of the command line's tables: ``"values"``
        (default; clearance.csv: one row per value of the flow parameter: the value, the speed
        U with SI units, the grazing value GAP_PARAM_graze, the clearance, whether it converged,
        the aperiodic band's ends, with their SI columns NAME_si) or ``"chart"`` (chart.csv:
        one row per chart cell: its value, U, gap, label, period, impacts, outcome and impact
        statistics, with SI columns)."""
        pd = _module("pandas")
        lead = {self.param: np.asarray(self.value, dtype=float)}
        if self.speed is not None:
            lead["U"] = np.asarray(self.speed, dtype=float)
        if table == "values":
            columns = dict(lead, **{self.gap_param + "_graze": self.grazing_value}, clearance=self.clearance,
                           converged=self.converged, aperiodic_min=self.aperiodic[:, 0],
                           aperiodic_max=self.aperiodic[:, 1])
            if self.clearance_si is not None:
                columns.update(clearance_si=self.clearance_si, aperiodic_min_si=self.aperiodic_si[:, 0],
                               aperiodic_max_si=self.aperiodic_si[:, 1])
            return pd.DataFrame(columns)
        if table != "chart":
            raise ValueError(f"table must be 'values' or 'chart' (got {table!r})")
        cells = np.asarray(self.label) != ""  # the padding left out, cells value after value
        point = np.nonzero(cells)[0]
        columns = {k: v[point] for k, v in lead.items()}
        columns.update(gap=np.asarray(self.gap)[cells], label=np.asarray(self.label)[cells],
                       period=np.asarray(self.period)[cells], impacts=np.asarray(self.impacts)[cells],
                       outcome=np.asarray(self.outcome)[cells])
        columns.update({k: np.asarray(v)[cells] for k, v in self.statistics.items()})
        if self.gap_si is not None:
            columns["gap_si"] = np.asarray(self.gap_si)[cells]
            columns.update({k + "_si": np.asarray(v)[cells] for k, v in (self.statistics_si or {}).items()})
        return pd.DataFrame(columns)


class CurveFrames:
    """For a correlation dimension: its correlation curve as rows."""

    def to_pandas(self):
        """A pandas DataFrame, one row per radius: r, pairs, C(r), the local slope and whether
        the radius is in the fit."""
        k = np.arange(len(self.r))
        return _module("pandas").DataFrame(dict(r=self.r, pairs=self.pairs, c=self.c, local_slope=self.local_slope,
                                                fitted=(k >= self.fit_first) & (k <= self.fit_last)))


class SurfaceFrames:
    """For grazing: one row per surface."""

    def to_pandas(self):
        """A pandas DataFrame, one row per surface: its name, the parameter that moves it and
        its grazing value, the margin, whether it converged, the last change, and the time and
        state (NAME columns) of the minimum gap."""
        lead = dict(surface=list(self.surfaces), param=list(self.param), value=self.value, margin=self.margin,
                    converged=self.surface_converged, change=self.change, minima=self.minima, t=self.t)
        return _state_frame(self.x, list(self.state_names), lead)
