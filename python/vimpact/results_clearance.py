"""The result of clearance design (``vimpact.clearance``, the command ``clearance``), built from
the records of its values and chart cells (analysis/clearance.hpp). ``vimpact.results`` names
it too. Pure Python and numpy."""
import functools
import os
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .frames import ClearanceFrames
from .results import (_a, _Context, _documented, _Labels, _loaded, _reader, _str_array, JobReport, label_counts,
                      read_table, read_tables)


_CHART = "ndarray, float64, shape (n, k)"


@_documented()
@dataclass(repr=False)
class Clearance(_Context, _Labels, ClearanceFrames):
    """Clearance design over a flow parameter (``vimpact.clearance``, the command ``clearance``):
    the smallest gap to the surface without impact at each value (the grazing line), the gaps
    where the response is aperiodic, and the design chart (a period label and the impact
    statistics at each gap).

    Gaps are distances from the rest state to the surface (``-sigma`` for the wake model). The
    arrays ``*_si`` are in SI (metres, m/s, Hz, J/m, W/m for a cylinder) when the run had
    physical units, else None. The chart's arrays (n, k) are NaN-, -1- or ""-padded where a
    value has fewer gaps than k."""
    param: str = _a("str", "The flow parameter (``Ur``).", "")
    x: str = _a("str", "The chart's horizontal quantity: ``U`` with speeds, else ``param``.", "")
    gap_param: str = _a("str", "The parameter that moves the surface (``sigma``).", "")
    surface: Optional[str] = _a("str or None", "The surface the gap parameter moves (None: it moves a switch).", "")
    switch: Optional[str] = _a("str or None", "The switch the gap parameter moves when it moves no surface (a "
                               "compliant barrier: the clearance is the smallest gap without crossing).")
    value: np.ndarray = _a("ndarray, float64, shape (n,)", "The flow parameter's values.")
    speed: Optional[np.ndarray] = _a("ndarray, float64, shape (n,), or None", "The flow speeds [m/s].")
    grazing_value: np.ndarray = _a("ndarray, float64, shape (n,)", "``gap_param`` at grazing.")
    clearance: np.ndarray = _a("ndarray, float64, shape (n,)", "The smallest gap without impact.")
    clearance_si: Optional[np.ndarray] = _a("ndarray, float64, shape (n,)", "The same in metres.")
    converged: np.ndarray = _a("ndarray, bool, shape (n,)", "The grazing run converged.")
    aperiodic: np.ndarray = _a("ndarray, float64, shape (n, 2)", "The smallest and largest chart gap with an "
                               "aperiodic response (NaN where none).")
    aperiodic_si: Optional[np.ndarray] = _a("ndarray, float64, shape (n, 2)", "The same in metres.")
    gap: np.ndarray = _a(_CHART, "The chart's gaps at each value.")
    gap_si: Optional[np.ndarray] = _a(_CHART, "The same in metres.")
    label: np.ndarray = _a("ndarray, str, shape (n, k)", "The regime at each chart gap: ``P0`` (no impact), "
                           "``PN``, ``aperiodic``, or a failed run's outcome.")
    period: np.ndarray = _a("ndarray, int64, shape (n, k)")
    impacts: np.ndarray = _a("ndarray, int64, shape (n, k)")
    outcome: np.ndarray = _a("ndarray, str, shape (n, k)")
    statistics: dict = _a("dict", "The impact statistics at each chart gap, name -> ndarray float64 (n, k).",
                          dict)
    statistics_si: Optional[dict] = _a("dict", "The same in SI.")
    warnings: tuple = ()
    stats: dict = field(default_factory=dict)
    jobs: Optional[JobReport] = _a("JobReport")

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
        point, values = np.asarray(point, dtype=np.int64), np.asarray(values)
        col = np.arange(len(point)) - np.searchsorted(point, point)  # its place among its value's cells
        text = values.dtype.kind in "US"
        out = np.full((n, col.max() + 1 if len(col) else 0), "" if text else -1 if values.dtype.kind in "iu" else
                      np.nan, dtype=object if text else values.dtype)
        out[point, col] = values
        return out.astype(str) if text else out

    @classmethod
    def of(cls, d, si=None, **run):
        """From the records of the values (``records``) and of the chart's cells (``cells``,
        value after value; ``cell_point``: each one's value index), as the bindings give them
        and ``read_tables`` reads clearance.csv and chart.csv; ``si`` the same in SI units (the
        attributes ``*_si``) or None."""
        chart = functools.partial(cls.chart, d["cell_point"], n=len(d["records"]["value"]))

        def quantities(p, c):  # what has an SI form
            return dict(clearance=p["clearance"], aperiodic=np.column_stack([p["aperiodic_min"], p["aperiodic_max"]]),
                        gap=chart(c["gap"]),
                        statistics={k: chart(v) for k, v in c["statistics"].items() if np.ndim(v) == 1})
        p, c = d["records"], d["cells"]
        return cls(value=p["value"], grazing_value=p["grazing_value"], converged=p["converged"],
                   label=chart(_str_array(c["label"])), period=chart(c["period"]), impacts=chart(c["impacts"]),
                   outcome=chart(_str_array(c["outcome"])), **quantities(p, c),
                   **({k + "_si": v for k, v in quantities(si["records"], si["cells"]).items()} if si else {}), **run)

    @_reader
    def load(cls, directory):
        """The result of ``vimpact clearance --out DIR``."""
        ctx, res = _loaded(directory)
        tables = read_tables(directory)
        cl, ch = (read_table(os.path.join(directory, f)) for f in ("clearance.csv", "chart.csv"))

        def column(table, key):
            return np.array(table[key], dtype=float)
        value = tables["clearance.csv"]["value"]
        # Cells are written value after value; their value index from the parameter column.
        point = np.array([int(np.argmin(np.abs(value - v))) for v in column(ch, res["param"])], dtype=np.int64)
        si = dict(records={k: column(cl, k + "_si") for k in ("clearance", "aperiodic_min", "aperiodic_max")},
                  cells=dict(gap=column(ch, "gap_si"),
                             statistics={k: column(ch, k + "_si") for k in res["statistics_columns"]}))
        return cls.of(dict(records=tables["clearance.csv"], cells=tables["chart.csv"], cell_point=point),
                      si if res["units"] == "si" else None,
                      param=res["param"], x=res["x"], gap_param=res["gap_param"], surface=res.get("surface"),
                      switch=res.get("switch"),
                      speed=column(cl, "U") if res["x"] == "U" else None, warnings=tuple(res["warnings"]), **ctx)
