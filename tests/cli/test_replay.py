"""Every --out directory holds a config.toml, and `vimpact COMMAND --config DIR/config.toml`
runs the same computation again: every file it writes is byte-identical to the first run's
(run.json differs only in the output directory it names)."""
import json
import os
import shutil
import subprocess

import pytest

from conftest import TWO_SIDED_TOML

SHORT = ["--transient", "40", "--record", "16"]

# (command and its options): each command once, with options away from their defaults so that
# a replay that dropped one would show.
CASES = {
    "simulate": ["simulate", "--set", "Ur=17.5", "--dt", "0.2", *SHORT],
    "period": ["period", "--preset", "facchinetti", "--tol", "1e-7", *SHORT],
    "grazing": ["grazing", "--set", "Ur=14", "--transient-time", "300", "--tol", "1e-9"],
    "sweep": ["sweep", "--param", "Ur", "--range", "14:16:3", "--ic-mode", "follow", "--direction", "both",
              "--grazing", "--set", "sigma=-0.14", "--color-by", "period", *SHORT],
    "map": ["map", "--x", "Ur:14:16:2", "--y", "sigma:-0.16:-0.14:2", "--grazing", "--tol", "1e-5", "--hold-band", "0.1",
            *SHORT],
    "basins": ["basins", "--x", "y:-0.1:0.1:2", "--y", "ydot:-0.1:0.1:2", "--match-tol", "1e-5", *SHORT],
    "response": ["response", "--param", "Ur", "--range", "14:16:2", "--curves", "A=14,eps=0.35;A=12,eps=0.3",
                 "--transient-time", "200"],
    "floquet": ["floquet", "--set", "Ur=12.5", "--newton-tol", "1e-10", *SHORT],
    "floquet-sweep": ["floquet", "--param", "Ur", "--range", "12:12.5:2", *SHORT],
    "lyapunov": ["lyapunov", "--set", "Ur=22.5", "--impacts", "60", "--warmup", "8", "--r0", "1e-5", "--transient", "40"],
    "dimension": ["dimension", "--record", "400", "--transient", "40", "--set", "Ur=22.5", "--theiler", "2"],
    "continue": ["continue", "--param", "Ur", "--range", "14.5:15.2", "--switch", "1", "--diagram", "3", *SHORT],
    "continue-curves": ["continue", "--param", "Ur", "--range", "14.3:15.1", "--param2", "sigma", "--range2",
                        "-0.16:-0.14", "--map", "2,2", "--ds-max", "0.05", *SHORT],
    "model-file": ["sweep", "--model", TWO_SIDED_TOML, "--param", "w", "--range", "0.9:1.1:2", *SHORT],
    "clearance": ["clearance", "--si", "D=0.02,m=0.6,fn=12,zeta=0.002,rho=1000", "--speeds", "4:5:2", "--fractions",
                  "0.6:1.2:2", *SHORT],
    "simulate-si": ["simulate", "--si", "D=0.02,m=0.6,fn=12,zeta=0.002,rho=1000,U=4,gap=0.001", *SHORT],
    "sweep-si": ["sweep", "--si", "D=0.02,m=0.6,fn=12,zeta=0.002,rho=1000,gap=0.001", "--param", "U", "--range",
                 "3.5:4:2", *SHORT],
}


def run(vimpact, args, cwd=None):
    return subprocess.run([vimpact, *args], capture_output=True, text=True, timeout=600, cwd=cwd)


def same_files(a, b):
    names = sorted(os.listdir(a))
    assert names == sorted(os.listdir(b))
    for name in names:
        pa, pb = os.path.join(a, name), os.path.join(b, name)
        if name == "run.json":
            ja, jb = json.load(open(pa)), json.load(open(pb))
            assert ja["result"].pop("out") == a and jb["result"].pop("out") == b
            assert ja == jb
        else:
            assert open(pa, "rb").read() == open(pb, "rb").read(), name


@pytest.mark.parametrize("case", sorted(CASES))
def test_config_toml_replays_the_run(vimpact, tmp_path, case):
    first, again = str(tmp_path / "first"), str(tmp_path / "again")
    p = run(vimpact, [*CASES[case], "--no-plot", "--out", first])
    assert p.returncode == 0, p.stderr
    assert os.path.exists(os.path.join(first, "config.toml"))
    assert "config.toml" in json.load(open(os.path.join(first, "run.json")))["files"]
    # From another directory, so that nothing depends on where the run was started.
    cmd = CASES[case][0]
    p = run(vimpact, [cmd, "--config", os.path.join(first, "config.toml"), "--out", again], cwd="/")
    assert p.returncode == 0, p.stderr
    same_files(first, again)


def test_a_swept_parameter_is_replayed_over_its_range(vimpact, tmp_path):
    # The base value of Ur sits in [parameters]; the sweep's range must still be what runs.
    out = str(tmp_path / "s")
    assert run(vimpact, [*CASES["sweep"], "--no-plot", "--out", out]).returncode == 0
    p = run(vimpact, ["sweep", "--config", os.path.join(out, "config.toml"), "--json"])
    assert p.returncode == 0, p.stderr
    j = json.loads(p.stdout)
    labels = j["labels"]
    with open(os.path.join(out, "labels.csv")) as f:
        rows = [line.split(",")[1:3] for line in f.read().splitlines()[1:]]
    both = labels + j.get("labels_down", [])
    assert sorted((v, lab) for v, lab in both) == sorted((float(v), lab) for v, lab in rows)
    assert sorted({v for v, _ in labels}) == [14.0, 15.0, 16.0]


def test_the_command_line_overrides_the_config(vimpact, tmp_path):
    out = str(tmp_path / "s")
    assert run(vimpact, [*CASES["sweep"], "--no-plot", "--out", out]).returncode == 0
    p = run(vimpact, ["sweep", "--config", os.path.join(out, "config.toml"), "--range", "14:15:2",
                      "--direction", "up", "--json"])
    assert p.returncode == 0, p.stderr
    assert [v for v, _ in json.loads(p.stdout)["labels"]] == [14.0, 15.0]


def test_a_config_of_another_command_is_refused(vimpact, tmp_path):
    out = str(tmp_path / "s")
    assert run(vimpact, [*CASES["sweep"], "--no-plot", "--out", out]).returncode == 0
    p = run(vimpact, ["map", "--config", os.path.join(out, "config.toml")])
    assert p.returncode == 2
    assert "vimpact sweep" in p.stderr and "this is `vimpact map`" in p.stderr


def test_an_unknown_option_in_the_command_table_is_refused(vimpact, tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text("[period]\nbogus = 3\n")
    p = run(vimpact, ["period", "--config", str(cfg)])
    assert p.returncode == 2
    assert "[period] bogus is not an option" in p.stderr


def test_an_edited_model_file_is_not_silently_replayed(vimpact, tmp_path):
    model = tmp_path / "m.toml"
    shutil.copy(TWO_SIDED_TOML, model)
    out = str(tmp_path / "o")
    p = run(vimpact, ["period", "--model", str(model), *SHORT, "--no-plot", "--out", out])
    assert p.returncode == 0, p.stderr
    cfg = os.path.join(out, "config.toml")
    # A comment leaves the model as it was: it replays.
    model.write_text(model.read_text() + "\n# a note\n")
    assert run(vimpact, ["period", "--config", cfg, "--json"]).returncode == 0
    # A changed equation is another model: refused, saying so.
    text = model.read_text()
    assert 'v = "-2*zeta*v - x + a*cos(phi)"' in text
    model.write_text(text.replace('v = "-2*zeta*v - x + a*cos(phi)"', 'v = "-2*zeta*v - x + a*sin(phi)"'))
    p = run(vimpact, ["period", "--config", cfg])
    assert p.returncode == 2
    assert "has changed since" in p.stderr


def test_a_points_file_dimension_replays(vimpact, tmp_path):
    pts = tmp_path / "pts.csv"
    rows = ["a,b"] + [f"{(i * 0.37) % 1:.6f},{(i * 0.61) % 1:.6f}" for i in range(400)]
    pts.write_text("\n".join(rows) + "\n")
    first, again = str(tmp_path / "first"), str(tmp_path / "again")
    p = run(vimpact, ["dimension", "--points", "pts.csv", "--theiler", "1", "--no-plot", "--out", first],
            cwd=str(tmp_path))
    assert p.returncode == 0, p.stderr
    assert "model =" not in open(os.path.join(first, "config.toml")).read()
    p = run(vimpact, ["dimension", "--config", os.path.join(first, "config.toml"), "--out", again], cwd="/")
    assert p.returncode == 0, p.stderr
    # The points file is named by its absolute path in both records.
    same_files(first, again)


def test_a_run_config_cannot_be_combined_with_points(vimpact, tmp_path):
    pts = tmp_path / "pts.csv"
    pts.write_text("a,b\n" + "".join(f"{i},{i * i % 7}\n" for i in range(50)))
    cfg = tmp_path / "c.toml"
    cfg.write_text("rtol = 1e-9\n")
    p = run(vimpact, ["dimension", "--points", str(pts), "--config", str(cfg)])
    assert p.returncode == 2
    assert "cannot be combined with --points" in p.stderr


# ---------------------------------------------------------------- what a config file may do

def planted_library(tmp_path, name, marker):
    """A shared library whose constructor writes `marker`: what loading it would run."""
    src = tmp_path / "planted.c"
    src.write_text('#include <stdio.h>\n'
                   '__attribute__((constructor)) static void planted(void) {\n'
                   f'    FILE* f = fopen("{marker}", "w"); if (f) {{ fputs("ran", f); fclose(f); }}\n'
                   '}\n')
    lib = tmp_path / name
    subprocess.run(["cc", "-shared", "-fPIC", "-o", str(lib), str(src)], check=True)
    return lib


@pytest.mark.parametrize("name", ["planted.so", "planted"])
def test_a_config_never_loads_a_shared_library(vimpact, tmp_path, name):
    marker = tmp_path / "marker"
    lib = planted_library(tmp_path, name, marker)
    cfg = tmp_path / "config.toml"
    cfg.write_text(f'model = "{name}"\n')
    p = run(vimpact, ["period", "--config", str(cfg), "--json"], cwd="/")
    assert p.returncode == 2, p.stderr
    assert f"config {cfg}: key 'model' names a shared library ({lib})" in p.stderr, p.stderr
    assert "only when given on the command line" in p.stderr
    assert len(p.stderr.splitlines()) == 1
    assert not marker.exists(), "the library's code ran"
    # A model file beside the config still loads from it.
    shutil.copy(TWO_SIDED_TOML, tmp_path / "two.toml")
    cfg.write_text('model = "two.toml"\n')
    p = run(vimpact, ["period", "--config", str(cfg), *SHORT, "--json"], cwd="/")
    assert p.returncode == 0, p.stderr
    assert set(json.loads(p.stdout)["impacts_by_surface"]) == {"left", "right"}  # the two-stop model ran


@pytest.mark.parametrize("text, needle", [
    ("transient = true\n", "key 'transient' must be an integer (got true)"),
    ("record = 2.5\n", "key 'record' must be an integer (got 2.5)"),
    ("rtol = false\n", "key 'rtol' must be a number (got false)"),
    ("sigma = true\n", "key 'sigma' must be a number (got true)"),
    ("[parameters]\nUr = 'abc'\n", "key 'Ur' must be a number (got 'abc')"),
    ("transient = -5\n", "transient = -5 is outside its valid range [0, 1e+09]"),
    ("Ur = -1\n", "parameter Ur = -1 is outside its valid range"),
    ("model = 3\n", "key 'model' must be a string (got 3)"),
    ("[period]\ntol = [1, 2]\n", "[period] tol takes one value, not a list (got a list)"),
    ("[period]\ntol = 'abc'\n", "[period] tol must be a number (got 'abc')"),
    ("[period]\ntol = true\n", "[period] tol takes a value, not true or false"),
    ("[period]\nno-plot = 1\n", "[period] no-plot is a flag: true or false (got 1)"),
    ("[period]\nout = 'x'\n", "[period] out: it says where the results go: give it on the command line"),
    ("[period]\nrtol = 1e-9\n", "[period] rtol: it is a setting of the run: write it at the top level of the "
                                "file (rtol = ...)"),
    ("[sweep]\nthreads = true\n", "[sweep] threads takes a value, not true or false"),
    ("[sweep]\nthreads = 1.5\n", "[sweep] threads must be an integer (got 1.5)"),
])
def test_a_config_value_of_the_wrong_type_names_the_file_and_key(vimpact, tmp_path, text, needle):
    cfg = tmp_path / "c.toml"
    cfg.write_text(text)
    cmd = "sweep" if "[sweep]" in text else "period"
    extra = ["--param", "Ur", "--range", "14:15:2"] if cmd == "sweep" else []
    p = run(vimpact, [cmd, "--config", str(cfg), *extra, *SHORT, "--json"])
    assert p.returncode == 2, (text, p.stderr)
    assert p.stderr.startswith(f"vimpact: error: config {cfg}: "), (text, p.stderr)
    assert needle in p.stderr, (text, p.stderr)
    assert len(p.stderr.splitlines()) == 1


def test_threads_may_be_set_in_the_commands_table(vimpact, tmp_path):
    # How many threads a machine gives the run: the results do not depend on it.
    cfg = tmp_path / "c.toml"
    cfg.write_text("[map]\nthreads = 2\n")
    p = run(vimpact, ["map", "--config", str(cfg), "--x", "Ur:14:16:2", "--y", "sigma:-0.16:-0.14:2", *SHORT,
                      "--json"])
    assert p.returncode == 0, p.stderr
    j = json.loads(p.stdout)
    assert sum(j["label_counts"].values()) == 4
    # The value reaches --threads: its own check refuses a negative one.
    cfg.write_text("[map]\nthreads = -1\n")
    p = run(vimpact, ["map", "--config", str(cfg), "--x", "Ur:14:16:2", "--y", "sigma:-0.16:-0.14:2", "--json"])
    assert p.returncode == 2 and "--threads must be >= 0 (got -1)" in p.stderr, p.stderr
