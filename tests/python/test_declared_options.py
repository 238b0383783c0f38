"""The grid analyses' options declared once in the library (core/option.hpp): the keyword
arguments of vimpact.sweep, map, basins, response, grazing, clearance and dimension, their defaults and their
documentation follow the declaration, the library refuses a value out of its range naming the
keyword, and the command line gives the same refusal naming --key (where it is built)."""
import inspect

import pytest

import vimpact

W = vimpact.WakeImpact()
GRID = vimpact.grid(15, 16, 2)

# What each analysis declared before the declarations existed (today's keywords): the same
# names, defaults and ranges the front ends checked by hand.
KEYWORDS = {
    "sweep": {"ic_mode": "fixed", "direction": "up", "tol": 1e-8},
    "map": {"tol": 1e-8, "grazing": False},
    "basins": {"tol": 1e-8, "match_tol": 1e-6, "box_fraction": 0.05},
    "grazing": {"transient_time": 1000.0, "tol": 1e-11, "block": 16, "t_max": 1e5},
    "response": {"transient_time": 1000.0, "tol": 1e-11, "block": 16, "t_max": 1e5},
    "clearance": {"tol": 1e-8, "transient_time": 1000.0},
    "dimension": {"estimator": "correlation_sum", "theiler": 0, "centres": 15, "slope_tolerance": 0.1,
                  "slope_window": 4.0, "min_extent": 4.0, "min_pairs": 100, "max_correlation": 0.5,
                  "r_max": float("inf"), "max_pairs": 100000000, "bins_per_octave": 16, "search": "grid"},
}

CALLS = {
    "sweep": lambda **kw: vimpact.sweep(W, "Ur", GRID, **kw),
    "map": lambda **kw: vimpact.map(W, ("Ur", GRID), ("sigma", [-0.16, -0.15]), **kw),
    "basins": lambda **kw: vimpact.basins(W, ("y", [-0.1, 0.1]), ("ydot", [-0.1, 0.1]), **kw),
    "grazing": lambda **kw: vimpact.grazing(W, **kw),
    "response": lambda **kw: vimpact.response(W, "Ur", GRID, **kw),
    "clearance": lambda **kw: vimpact.clearance(W, "Ur", GRID, **kw),
    "dimension": lambda **kw: vimpact.dimension([[0.1 * i, (0.37 * i) % 1.0] for i in range(50)], **kw),
}

# The same run on the command line.
COMMANDS = {
    "grazing": ["grazing"],
    "sweep": ["sweep", "--param", "Ur", "--range", "15:16:2"],
    "map": ["map", "--x", "Ur:15:16:2", "--y", "sigma:-0.16:-0.15:2"],
    "basins": ["basins", "--x", "y:-0.1:0.1:2", "--y", "ydot:-0.1:0.1:2"],
    "response": ["response", "--param", "Ur", "--range", "15:16:2"],
    "clearance": ["clearance", "--param", "Ur", "--range", "15:16:2"],
    "dimension": ["dimension"],  # refused before its run
}

# A value just outside each bounded range, and the range as the message gives it.
OUT_OF_RANGE = [
    ("sweep", "tol", 0, "> 0"),
    ("map", "tol", -1e-8, "> 0"),
    ("basins", "tol", 0, "> 0"),
    ("basins", "match_tol", 0, "> 0"),
    ("basins", "box_fraction", -0.5, ">= 0"),
    ("grazing", "transient_time", -1, ">= 0"),
    ("grazing", "block", 0, ">= 1"),
    ("response", "transient_time", -1, ">= 0"),
    ("response", "tol", 0, "> 0"),
    ("response", "block", 0, ">= 1"),
    ("response", "t_max", 0, "> 0"),
    ("clearance", "tol", 0, "> 0"),
    ("clearance", "transient_time", -1, ">= 0"),
    ("dimension", "theiler", -1, ">= 0"),
    ("dimension", "centres", 0, ">= 1"),
    ("dimension", "slope_tolerance", 0, "> 0"),
    ("dimension", "slope_window", 1, "> 1"),
    ("dimension", "min_extent", 0.5, "> 1"),
    ("dimension", "max_correlation", 1.5, "(0, 1]"),
    ("dimension", "r_max", 0, "(0, inf]"),
    ("dimension", "bins_per_octave", 256, "[2, 128]"),
]


@pytest.mark.parametrize("kind", sorted(KEYWORDS))
def test_keywords_are_the_librarys_declaration(kind):
    declared = vimpact._vimpact.declared[kind]
    assert {e["key"]: e["default"] for e in declared} == KEYWORDS[kind]
    f = getattr(vimpact, kind)
    sig = inspect.signature(f)
    assert "declared" not in sig.parameters
    for e in declared:
        p = sig.parameters[e["key"]]
        assert p.kind == p.KEYWORD_ONLY and p.default == e["default"], e
        assert f"    {e['key']} : " in f.__doc__, e["key"]
        if e["range"] and not isinstance(e["default"], str):
            assert f"In {e['range']}." in f.__doc__, e["key"]


def test_names_of_an_enumeration_are_the_declarations():
    by_key = {e["key"]: e for e in vimpact._vimpact.declared["sweep"]}
    assert by_key["ic_mode"]["range"] == "fixed, follow"
    assert by_key["direction"]["range"] == "up, down, both"
    with pytest.raises(vimpact.InputError, match=r"^ic_mode 'chase' is not one of fixed, follow$"):
        CALLS["sweep"](ic_mode="chase")
    with pytest.raises(vimpact.InputError, match="^direction = both needs ic_mode follow"):
        CALLS["sweep"](direction="both")


@pytest.mark.parametrize("kind,key,value,where", OUT_OF_RANGE)
def test_the_library_refuses_a_value_out_of_range_naming_the_keyword(kind, key, value, where):
    with pytest.raises(vimpact.InputError) as e:
        CALLS[kind](**{key: value})
    assert str(e.value) == f"{key} = {value:g} is outside its valid range {where}"


@pytest.mark.parametrize("kind,key,value,where", [c for c in OUT_OF_RANGE if c[0] in COMMANDS])
def test_the_command_line_gives_the_same_refusal_naming_the_option(cli, tmp_path, kind, key, value, where):
    option = "--" + key.replace("_", "-")
    p = cli(*COMMANDS[kind], f"{option}={value}", cwd=tmp_path)
    assert p.returncode == 2, p.stderr
    assert p.stderr.strip() == f"vimpact: error: {option} = {value:g} is outside its valid range {where}"


@pytest.mark.parametrize("kind", sorted(COMMANDS))
def test_the_command_lines_help_lists_every_declared_option(cli, kind):
    p = cli(COMMANDS[kind][0], "--help")
    assert p.returncode == 0, p.stderr
    text = " ".join(p.stdout.split())
    for e in vimpact._vimpact.declared[kind]:
        option = "--" + e["key"].replace("_", "-")
        assert option in text, option
        help_text = e["help"][0].upper() + e["help"][1:]
        if isinstance(e["default"], bool):
            assert f"{option} {help_text}" in text, option  # a flag
        elif isinstance(e["default"], str):
            assert f"{help_text} (default {e['default']}; one of {e['range']})" in text, option
        else:
            assert f"{help_text} (default " in text and f"; {e['range']})" in text, option


def test_declared_options_reach_the_run(cli_json):
    # The same declared options from both front ends give the same labels.
    j = cli_json(*COMMANDS["sweep"], "--ic-mode", "follow", "--direction", "down", "--tol", "1e-5",
                 "--transient", "80", "--record", "40")
    s = vimpact.sweep(W, "Ur", GRID, ic_mode="follow", direction="down", tol=1e-5, transient=80, record=40)
    assert j["ic_mode"] == "follow" and j["direction"] == "down"
    assert [v for v, _ in j["labels"]] == list(s.value) == [16.0, 15.0]  # downwards
    assert [label for _, label in j["labels"]] == list(s.label)


# The protocol's keywords as users had them before the declaration (every function repeated
# them by hand): the same names and defaults; max_step (none: inf) is new to Python.
PROTOCOL = {"transient": 500, "record": 200, "method": "dop853", "rtol": 1e-10, "atol": 1e-10, "hold_band": None,
            "max_step": float("inf"), "quiet_time": 2000.0, "t_max": 1e6}
WITH_PROTOCOL = ("simulate", "period", "sweep", "map", "basins", "clearance", "floquet", "floquet_sweep",
                 "continuation")


def test_the_protocols_declaration_is_the_keywords_users_had():
    assert {e["key"]: e["default"] for e in vimpact._vimpact.declared["protocol"]} == PROTOCOL


@pytest.mark.parametrize("name", WITH_PROTOCOL + ("lyapunov", "lyapunov_sweep"))
def test_protocol_keywords_and_defaults_are_the_declarations(name):
    f = getattr(vimpact, name)
    sig = inspect.signature(f)
    assert "declared" not in sig.parameters
    for e in vimpact._vimpact.declared["protocol"]:
        p = sig.parameters[e["key"]]
        assert p.kind == p.KEYWORD_ONLY, (name, e["key"])
        if name.startswith("lyapunov") and e["key"] == "record":
            assert p.default == 0  # the Lyapunov analysis records no points unless asked
            continue
        assert p.default == e["default"], (name, e)
        assert f"    {e['key']} : " in f.__doc__, (name, e["key"])
        if e["range"] and not isinstance(e["default"], str):
            assert f"In {e['range']}." in f.__doc__, (name, e["key"])
    assert "    section : str, optional" in f.__doc__, name


@pytest.mark.parametrize("key,value,where", [
    ("transient", -1, "[0, 1e+09]"),
    ("record", 0, "[1, 1e+07]"),
    ("rtol", 2, "[1e-15, 1)"),
    ("atol", 0, "[1e-300, 1)"),
    ("hold_band", 1, "[0, 1)"),
    ("max_step", 0, "(0, inf]"),
    ("quiet_time", 0, "(0, inf]"),
    ("t_max", -1, "(0, inf]"),
])
def test_a_protocol_keyword_out_of_range_is_refused_by_name(key, value, where):
    for call in (lambda **kw: vimpact.simulate(W, **kw), CALLS["sweep"]):
        with pytest.raises(vimpact.InputError) as e:
            call(**{key: value})
        assert str(e.value) == f"{key} = {value:g} is outside its valid range {where}"


def test_hold_band_none_is_the_methods_and_a_value_reaches_the_run():
    q = dict(transient=20, record=10, method="dopri5")
    default = vimpact.simulate(W, **q).stats.steps
    assert vimpact.simulate(W, hold_band=None, **q).stats.steps == default
    assert vimpact.simulate(W, hold_band=0.1, **q).stats.steps == default  # DOPRI5's own band (docs/performance.md)
    assert vimpact.simulate(W, hold_band=0.0, **q).stats.steps != default


def test_max_step_reaches_the_run():
    q = dict(transient=20, record=10)
    s = vimpact.simulate(W, max_step=0.01, **q)
    assert s.stats.h_max <= 0.01 < vimpact.simulate(W, **q).stats.h_max
