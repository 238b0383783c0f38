"""Results as pandas DataFrames and xarray Datasets (vimpact/frames.py): every row of a result
in its table, the grids with their axes as named coordinates; a cell of a map read through
to_xarray is the label of the same run alone (vimpact.period)."""
import importlib.util

import numpy as np
import pytest

import vimpact
from capabilities import need

HAVE = all(importlib.util.find_spec(m) for m in ("pandas", "xarray"))
W = vimpact.WakeImpact()
QUICK = dict(transient=50, record=20)


@pytest.fixture(autouse=True, scope="module")
def frames_capability():
    need("frames", HAVE, "pandas and xarray are not installed (python3-pandas, python3-xarray: "
         "scripts/install-deps.sh tests)")


@pytest.fixture(scope="module")
def sweep():
    return vimpact.sweep(W, "Ur", vimpact.grid(15, 17, 3), **QUICK)


@pytest.fixture(scope="module")
def grid():
    return vimpact.map(W, ("Ur", [15.0, 16.0]), ("sigma", [-0.16, -0.1, -0.05]), **QUICK)


def test_a_sweep_has_a_row_per_run_and_a_column_per_field(sweep):
    df = sweep.to_pandas()
    assert len(df) == len(sweep.value) == 3
    assert list(df["value"]) == list(sweep.value) and list(df["label"]) == list(sweep.label)
    # A per-surface field: a column per surface, named after it.
    assert list(df["impacts_by_surface_barrier"]) == list(sweep.impacts_by_surface[:, 0])
    assert list(df["final_state_ydot"]) == list(sweep.final_state[:, 1])


def test_a_sweeps_points_have_their_run_and_value(sweep):
    df = sweep.to_pandas("points")
    assert list(df.columns) == ["run", "Ur", "y", "ydot", "x", "xdot"]
    assert len(df) == len(sweep.points)
    assert np.array_equal(df["run"], sweep.point_run) and np.array_equal(df["Ur"], sweep.point_value)
    assert np.array_equal(df[["y", "ydot", "x", "xdot"]].to_numpy(), sweep.points)


def test_a_maps_rows_are_its_cells_in_job_order(grid):
    df = grid.to_pandas()
    assert len(df) == 6
    assert list(df["Ur"]) == [15.0, 16.0] * 3 and list(df["sigma"]) == [-0.16, -0.16, -0.1, -0.1, -0.05, -0.05]
    assert list(df["label"]) == list(np.ravel(grid.label))


def test_a_map_as_a_dataset_is_indexed_by_its_parameters(grid):
    ds = grid.to_xarray()
    assert ds.label.dims == ("sigma", "Ur")
    assert list(ds.Ur.values) == [15.0, 16.0] and list(ds.sigma.values) == [-0.16, -0.1, -0.05]
    assert ds.impacts_by_surface.dims == ("sigma", "Ur", "surface") and list(ds.surface.values) == ["barrier"]
    # The cell at (Ur, sigma) is the run alone at those values.
    for ur, sigma in ((16.0, -0.1), (15.0, -0.16)):
        alone = vimpact.period(W.with_(Ur=ur, sigma=sigma), **QUICK)
        assert str(ds.label.sel(Ur=ur, sigma=sigma).values) == alone.label


def test_basins_are_indexed_by_their_state_variables():
    b = vimpact.basins(W, ("y", [-0.1, 0.0, 0.1]), ("ydot", [-0.05, 0.05]), **QUICK)
    ds = b.to_xarray()
    assert ds.attractor.dims == ("ydot", "y")
    assert np.array_equal(ds.attractor.values, b.attractor)


def test_a_sweep_is_not_a_grid(sweep):
    with pytest.raises(TypeError, match="not a grid"):
        sweep.to_xarray()
    with pytest.raises(ValueError, match="'runs' or 'points'"):
        sweep.to_pandas("cells")


def test_a_simulations_impacts_sections_and_samples():
    s = vimpact.simulate(W.with_(Ur=19), sample_dt=0.5, **QUICK)
    impacts = s.to_pandas()
    assert len(impacts) == len(s.impact_t) > 0
    assert set(impacts["surface"]) == {"barrier"}
    assert np.array_equal(impacts[["y_pre", "ydot_pre", "x_pre", "xdot_pre"]].to_numpy(), s.impact_pre)
    assert np.array_equal(impacts["ydot_post"].to_numpy(), s.impact_post[:, 1])
    sections = s.to_pandas("sections")
    assert np.array_equal(sections["t"], s.section_t) and np.array_equal(sections["y"], s.section[:, 0])
    assert len(s.to_pandas("series")) == len(s.series_t) > 0


def test_a_continuations_branches_and_bifurcations():
    c = vimpact.continuation(W, "Ur", (12, 16), switch=1, **QUICK)  # a period doubling near 15
    branches = c.to_pandas()
    assert len(branches) == sum(len(b.param) for b in c.branches)
    assert set(branches["branch"]) == {b.index for b in c.branches}
    first = branches[branches["branch"] == c.branches[0].index]
    assert np.array_equal(first["Ur"], c.branches[0].param) and np.array_equal(first["stable"], c.branches[0].stable)
    bifurcations = c.to_pandas("bifurcations")
    assert len(bifurcations) == len(c.bifurcations) > 0 and len(c.branches) == 2
    assert list(bifurcations["type"]) == [b.type for b in c.bifurcations]
    assert list(bifurcations["Ur"]) == [b.param for b in c.bifurcations]


# Two state variables and two surfaces: a van der Pol oscillator between two stops.
TWO_BY_TWO = """
name = "two_by_two"
state = [{ name = "x" }, { name = "v" }]
initial_state = [0.5, 0.0]
[parameters]
mu = { default = 1.0 }
d = { default = 1.5, above = 0 }
[derivatives]
x = "v"
v = "mu*(1 - x^2)*v - x"
[[surfaces]]
name = "right"
gap = "d - x"
reset = { v = "-0.8*v" }
[[surfaces]]
name = "left"
gap = "x + d"
reset = { v = "-0.8*v" }
[[sections]]
name = "maxima"
when = "v"
direction = "down"
"""


def test_columns_follow_the_span_when_surfaces_and_states_are_as_many():
    m = vimpact.Model.from_toml(TWO_BY_TWO)
    assert len(m.surfaces) == len(m.state_names) == 2
    s = vimpact.sweep(m, "mu", [0.8, 1.0], ic=[0.5, 0.0], transient=20, record=10)
    df = s.to_pandas()
    assert list(df["final_state_x"]) == list(s.final_state[:, 0])
    assert list(df["final_state_v"]) == list(s.final_state[:, 1])
    assert list(df["impacts_by_surface_left"]) == list(s.impacts_by_surface[:, 1])
    g = vimpact.map(m, ("mu", [0.8, 1.0]), ("d", [1.5, 1.8]), ic=[0.5, 0.0], transient=20, record=10)
    ds = g.to_xarray()
    assert ds.impacts_by_surface.dims == ("d", "mu", "surface") and list(ds.surface.values) == ["right", "left"]


def test_clearance_values_and_chart_cells_are_the_command_lines_tables(cli, tmp_path):
    # The command line writes clearance.csv and chart.csv from the library's records; the frames
    # are built from the Python result's arrays: the same run, two writers.
    c = vimpact.clearance(W, "Ur", [15.0, 16.0], fractions=[0.5, 1.2], **QUICK)
    out = tmp_path / "c"
    p = cli("clearance", "--param", "Ur", "--range", "15:16:2", "--fractions", "0.5:1.2:2", "--transient", 50,
            "--record", 20, "--out", out, "--no-plot")
    assert p.returncode == 0, p.stderr
    pd = importlib.import_module("pandas")
    values, chart = c.to_pandas(), c.to_pandas("chart")
    # pandas reads decimals exactly only when asked (its fast parser is off by an ulp at times).
    written_values, written_chart = (pd.read_csv(out / f, float_precision="round_trip")
                                     for f in ("clearance.csv", "chart.csv"))
    assert len(values) == 2 and len(chart) == 4  # two values, two gaps each
    for frame, written in ((values, written_values), (chart, written_chart)):
        assert set(frame.columns) <= set(written.columns)  # named as the tables name them
        for name in frame.columns:
            if frame[name].dtype == object:
                assert list(frame[name]) == list(written[name]), name
            else:
                assert np.array_equal(frame[name].astype(float), written[name].astype(float), equal_nan=True), name
    assert {"sigma_graze", "clearance", "aperiodic_min"} <= set(values.columns)
    assert {"gap", "label", "impact_rate", "energy_per_impact"} <= set(chart.columns)
    assert list(chart["label"][1::2]) == ["P0", "P0"]  # 1.2 times the clearance: no impact


def test_a_dimensions_curve_and_grazings_surfaces_are_rows():
    rng = np.random.default_rng(3)
    d = vimpact.dimension(rng.random((2000, 2)))
    df = d.to_pandas()
    assert len(df) == len(d.r) and np.array_equal(df["c"], d.pairs / d.total_pairs)
    assert df["fitted"].sum() == d.fitted  # the radii of the fit, as many as it says
    g = vimpact.grazing(vimpact.Model("two_sided_impact_oscillator"), param="d")
    df = g.to_pandas()
    assert list(df["surface"]) == ["right", "left"] and list(df.columns[-3:]) == ["x", "v", "phi"]
    assert np.array_equal(df["value"], g.value) and np.array_equal(df[["x", "v", "phi"]].to_numpy(), g.x)


def test_a_floquet_results_impacts_and_orbit():
    f = vimpact.floquet(W.with_(Ur=16), sample_dt=0.05, **QUICK)
    assert f.period > 0 and len(f.impact_t) > 0
    df = f.to_pandas()
    assert np.array_equal(df["t"], f.impact_t) and np.array_equal(df[["y_pre", "ydot_pre"]].to_numpy(),
                                                                 f.impact_pre[:, :2])
    orbit = f.to_pandas("orbit")
    assert list(orbit.columns) == ["t", "y", "ydot", "x", "xdot"] and len(orbit) == len(f.orbit_t)
    # The samples span one period of the refined orbit.
    assert orbit["t"].iloc[-1] - orbit["t"].iloc[0] == pytest.approx(f.period, abs=0.05 + 1e-12)
    with pytest.raises(ValueError, match="'impacts', 'orbit'"):
        f.to_pandas("series")
