"""What the pictures must show: each axis names its quantity with the model's symbol and unit,
every legend lies outside the data, every label and legend fits in the figure, and a
bifurcation diagram coloured by period gives each label one colour and lists exactly the
labels of the result."""
import json
import re
from types import SimpleNamespace

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

import vimpact  # noqa: E402
import vimpact.plot as plot  # noqa: E402
import vimpact.plot_dimension as plot_dimension  # noqa: E402
from matplotlib.colors import to_rgba  # noqa: E402

W = vimpact.WakeImpact()
Q = dict(transient=60, record=24)
INFO = {e["name"]: e for e in W.info["state"] + W.info["parameters"]}

# picture -> (draw, make, [(axes index, axis, quantity of the model it must name)])
PICTURES = {
    "phase": (plot.phase, lambda: vimpact.simulate(W, sample_dt=0.1, **Q),
              [(0, "y", "y"), (1, "x", "y"), (1, "y", "ydot")]),
    "sections": (plot.sections, lambda: vimpact.period(W, **Q), [(0, "x", "y"), (0, "y", "x")]),
    "bifurcation": (plot.bifurcation, lambda: vimpact.sweep(W, "Ur", [16, 17], grazing=True, **Q),
                    [(0, "x", "Ur"), (0, "y", "y"), (1, "y", "sigma")]),
    "map": (plot.map, lambda: vimpact.map(W, x=("Ur", [16, 20]), y=("sigma", [-0.16, -0.1]), grazing=True, **Q),
            [(0, "x", "Ur"), (0, "y", "sigma")]),
    "basins": (plot.basins, lambda: vimpact.basins(W, x=("y", [-0.2, 0.1]), y=("ydot", [0, 0.1]), **Q),
               [(0, "x", "y"), (0, "y", "ydot")]),
    "response": (plot.response, lambda: vimpact.response(W, "Ur", [5, 6], transient_time=200),
                 [(0, "y", "y"), (1, "x", "Ur")]),
    "floquet": (plot.floquet, lambda: vimpact.floquet(W, sample_dt=0.1, **Q), [(1, "x", "y"), (1, "y", "ydot")]),
    "lyapunov": (plot.lyapunov, lambda: vimpact.lyapunov(W, impacts=30, transient=60), []),
    "floquet_sweep": (plot.floquet_sweep, lambda: vimpact.floquet_sweep(W, "Ur", [16, 17], **Q),
                      [(1, "x", "Ur"), (1, "y", "y")]),
    "lyapunov_sweep": (plot.lyapunov_sweep,
                       lambda: vimpact.lyapunov_sweep(W, "Ur", [16, 17], impacts=20, transient=40, record=5),
                       [(1, "x", "Ur"), (1, "y", "y")]),
}
# The pictures that explain their marks in a legend.
WITH_LEGEND = {"phase", "bifurcation", "map", "basins", "response", "floquet", "lyapunov", "floquet_sweep"}

_drawn = {}


def drawn(name, tmp_path_factory):
    """The Figure of a picture, drawn once and written (so laid out as in the file)."""
    if name not in _drawn:
        draw, make, _ = PICTURES[name]
        path = tmp_path_factory.mktemp(name) / "p.png"
        _drawn[name] = draw(make(), str(path))
    return _drawn[name]


def names_quantity(label, name):
    """The label names the quantity by its symbol, with the model's unit in brackets (none for a
    dimensionless one)."""
    unit = INFO[name]["unit"]
    assert re.search(rf"(?<!\w){re.escape(name)}(?!\w)", label), (name, label)
    if unit:
        assert f"[{unit}]" in label, (name, unit, label)
    else:
        assert "[" not in label, (name, label)


def legends(fig):
    return [a.get_legend() for a in fig.axes if a.get_legend() is not None]


def check_layout(fig):
    """Every legend outside every axes' data area and clear of its tick labels and axis labels
    (a twin axis's on the right too); labels, titles and legends inside the figure."""
    fig.draw_without_rendering()
    page = fig.bbox
    for leg in legends(fig):
        box = leg.get_window_extent()
        for a in fig.axes:
            assert not box.overlaps(a.get_window_extent()), ([t.get_text() for t in leg.get_texts()], a.get_title())
            lo, hi = sorted(a.get_ylim())
            ticks = [t for t, v in zip(a.get_yticklabels(), a.get_yticks()) if lo <= v <= hi]
            for text in ticks + [a.xaxis.label, a.yaxis.label]:
                if text.get_visible() and text.get_text():
                    assert not box.overlaps(text.get_window_extent()), text.get_text()
        assert page.x0 - 1 <= box.x0 and box.x1 <= page.x1 + 1 and page.y0 - 1 <= box.y0 and box.y1 <= page.y1 + 1
    for a in fig.axes:
        for text in (a.xaxis.label, a.yaxis.label, a.title):
            if text.get_text():
                b = text.get_window_extent()
                assert page.x0 - 1 <= b.x0 and b.x1 <= page.x1 + 1 and page.y0 - 1 <= b.y0 and b.y1 <= page.y1 + 1, \
                    text.get_text()


@pytest.mark.parametrize("name", list(PICTURES))
def test_axes_name_the_models_quantities_with_units(name, tmp_path_factory):
    fig = drawn(name, tmp_path_factory)
    for i, axis, quantity in PICTURES[name][2]:
        a = fig.axes[i]
        names_quantity(a.get_xlabel() if axis == "x" else a.get_ylabel(), quantity)
    for a in fig.axes:
        if a.get_visible() and a.axison:
            assert a.get_xlabel() or a.get_shared_x_axes().get_siblings(a) != [a], (name, a.get_title())
            assert a.get_ylabel(), (name, a.get_title())


def test_a_short_meaning_joins_the_symbol_where_it_fits(tmp_path_factory):
    fig = drawn("bifurcation", tmp_path_factory)
    meaning = INFO["Ur"]["meaning"].split(" (")[0]
    assert fig.axes[0].get_xlabel() == f"Ur, {meaning}"
    assert fig.axes[0].get_ylabel() == f"y at the section (maxima) [{INFO['y']['unit']}]"


def test_time_and_rates_are_labelled(tmp_path_factory):
    assert drawn("phase", tmp_path_factory).axes[0].get_xlabel() == "t"
    fig = drawn("lyapunov", tmp_path_factory)
    assert all("per unit t" in a.get_ylabel() for a in fig.axes)
    assert fig.axes[1].get_xlabel().startswith("t - t_start")


@pytest.mark.parametrize("name", list(PICTURES))
def test_legends_lie_outside_the_data_and_everything_fits(name, tmp_path_factory):
    fig = drawn(name, tmp_path_factory)
    assert bool(legends(fig)) == (name in WITH_LEGEND)
    check_layout(fig)


def test_a_dollar_in_a_meaning_is_drawn_as_text(tmp_path):
    """A model's meaning is text, never mathtext (an odd '$' would fail to draw)."""
    s = vimpact.sweep(W, "Ur", [16, 17], **Q)
    s.parameter_info = dict(s.parameter_info, Ur={"meaning": "costs $5", "unit": "$"})
    fig = plot.bifurcation(s, str(tmp_path / "p.png"))
    assert fig.axes[0].get_xlabel() == r"Ur, costs \$5 [\$]"


def test_the_correlation_dimension_picture(cli, tmp_path, monkeypatch):
    out = tmp_path / "dim"
    p = cli("dimension", "--set", "Ur=21", "--transient", "100", "--record", "400", "--estimator", "centres",
            "--no-plot", "--out", out)
    assert p.returncode == 0, p.stderr
    figures = []
    save_in = plot_dimension.save_in
    monkeypatch.setattr(plot_dimension, "save_in", lambda fig, *a, **k: (figures.append(fig), save_in(fig, *a, **k)))
    plot_dimension.dimension(str(out))
    fig, = figures
    # Coordinates that vary first: ydot is 0 on the maxima.
    names_quantity(fig.axes[0].get_xlabel(), "y")
    names_quantity(fig.axes[0].get_ylabel(), "x")
    names_quantity(fig.axes[1].get_ylabel(), "xdot")
    assert len(legends(fig)) == 4  # the centres in both projections, C(r) and its slope
    check_layout(fig)


# ---------------------------------------------------------------- colour by period

def point_colours(ax):
    """(x, y) -> colour of every point drawn as a marker without a line."""
    out = {}
    for line in ax.lines:
        if line.get_linestyle() in ("None", "none", "") and line.get_marker() not in (None, "None", ""):
            for x, y in zip(line.get_xdata(), line.get_ydata()):
                out[(float(x), float(y))] = to_rgba(line.get_color())
    return out


def check_colour_by_period(result, fig):
    ax = fig.axes[0]
    labels = [str(x) for x in result.label]
    legend = ax.get_legend()
    assert legend is not None
    entries = [t.get_text() for t in legend.get_texts()]
    assert sorted(e for e in entries if e in labels) == sorted(set(labels))
    assert [e for e in entries if e in labels] == vimpact.results.label_order(labels)
    # legend_handles from matplotlib 3.7, legendHandles before
    handles = getattr(legend, "legend_handles", None) or legend.legendHandles
    handle_colour = {t.get_text(): to_rgba(h.get_color()) for t, h in zip(legend.get_texts(), handles)
                     if t.get_text() in labels}
    assert len(set(handle_colour.values())) == len(handle_colour), handle_colour
    colours = point_colours(ax)
    k = result.plot_index if hasattr(result, "plot_index") else 0
    for run, lab in enumerate(labels):
        for p in np.asarray(result.points)[np.asarray(result.point_run) == run]:
            assert colours[(float(result.value[run]), float(p[k]))] == handle_colour[lab], (run, lab)


def test_colour_by_period_of_a_computed_sweep(tmp_path):
    s = vimpact.sweep(W, "Ur", vimpact.grid(14, 22, 9), transient=100, record=24)
    assert len(set(s.label.tolist())) >= 3, s.label  # the test needs several labels
    fig = plot.bifurcation(s, str(tmp_path / "p.png"), color_by="period")
    check_colour_by_period(s, fig)
    check_layout(fig)


def test_colour_by_period_lists_failed_runs_too(tmp_path):
    """Runs that end early have no section points; their outcome is still a label of the
    result, and the legend lists it."""
    labels = np.array(["P1", "P2", "aperiodic", "chattering", "P1", "time_limit"])
    value = np.arange(16.0, 22.0)
    point_run = np.array([0, 1, 1, 2, 2, 2, 4])
    s = SimpleNamespace(param="Ur", ic_mode="fixed", label=labels, value=value, point_run=point_run,
                        point_value=value[point_run], point_branch=np.zeros(len(point_run), dtype=int),
                        points=np.column_stack([np.linspace(0.1, 0.2, len(point_run)), np.zeros((len(point_run), 3))]),
                        grazing=np.full((len(value), 1), np.nan), parameters={}, state_names=("y", "ydot", "x", "xdot"),
                        plot_variable="y", state_info=W.info["state"])
    fig = plot.bifurcation(s, str(tmp_path / "p.png"), color_by="period")
    check_colour_by_period(s, fig)
    assert [t.get_text() for t in fig.axes[0].get_legend().get_texts()] == \
        ["P1", "P2", "aperiodic", "chattering", "time_limit"]


def test_the_default_keeps_black_points_and_no_label_legend(tmp_path):
    s = vimpact.sweep(W, "Ur", vimpact.grid(14, 22, 5), transient=100, record=24)
    fig = plot.bifurcation(s, str(tmp_path / "p.png"))
    assert set(point_colours(fig.axes[0]).values()) == {to_rgba("k")}
    assert fig.axes[0].get_legend() is None


@pytest.mark.parametrize("bad", ["periods", "", 1])
def test_an_unknown_colouring_is_refused(bad):
    s = SimpleNamespace(param="Ur")
    with pytest.raises(ValueError, match=r"color_by must be one of none, period"):
        plot.bifurcation(s, color_by=bad)


def test_the_command_lines_option_reaches_the_picture(cli, tmp_path):
    """sweep --color-by period stores the option in run.json; python3 -m vimpact.plot sweep DIR
    draws with it."""
    out = {}
    for mode in ("period", "none"):
        out[mode] = tmp_path / mode
        p = cli("sweep", "--param", "Ur", "--range", "14:22:9", "--transient", "100", "--record", "24",
                "--color-by", mode, "--no-plot", "--out", out[mode])
        assert p.returncode == 0, p.stderr
        assert json.loads((out[mode] / "run.json").read_text())["plot_options"] == {"color_by": mode}
    loaded = vimpact.Sweep.load(out["period"])
    fig = plot._kinds()["sweep"](str(out["period"]))
    check_colour_by_period(loaded, fig)
    assert loaded.state_info == vimpact.sweep(W, "Ur", [16], **Q).state_info
    assert plot._kinds()["sweep"](str(out["none"])).axes[0].get_legend() is None


def test_coinciding_section_points_show_as_one_point_without_an_offset(tmp_path):
    """A periodic orbit's section points agree to rounding: the axes must not magnify the
    rounding into a cloud under an offset text ("1e-12+0.3963") that covers the labels."""
    p = vimpact.period(vimpact.ForcedImpactOscillator(), section="strobe", transient=100, record=24)
    assert p.label == "P1" and np.ptp(p.simulation.section[:, 0]) > 0  # distinct in the last digits
    fig = plot.sections(p, str(tmp_path / "p.png"))
    fig.draw_without_rendering()
    ax = fig.axes[0]
    assert ax.xaxis.get_offset_text().get_text() == "" and ax.yaxis.get_offset_text().get_text() == ""
    check_layout(fig)
