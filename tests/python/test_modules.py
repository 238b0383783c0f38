"""GiNaC (model files), MPI (runs launched as several ranks) and each engine model's analyses
live in modules the library loads when a run needs them (src/core/load_module.hpp): a run of a
built-in model in one process loads neither library and only its model's engine module, from
the command line or from Python; a model file loads GiNaC and the engine module of its
dimension."""
import json
import os
import subprocess
import sys

MODEL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "models",
                     "impacting_pendulum.toml")
HEAVY = ("libginac", "libcln", "libmpi", "libopen-pal")


def loaded_by(args, env=None):
    """The shared objects the dynamic loader opened for a run of the program (LD_DEBUG)."""
    p = subprocess.run(args, capture_output=True, text=True, env=dict(os.environ, LD_DEBUG="files", **(env or {})),
                       timeout=300)
    assert p.returncode == 0, p.stderr[-2000:]
    return {line.split("file=")[1].split()[0] for line in p.stderr.splitlines() if "file=" in line}


def heavy(objects):
    return sorted(o for o in objects if any(os.path.basename(o).startswith(h) for h in HEAVY))


def engines(objects):
    return sorted(os.path.basename(o) for o in objects if os.path.basename(o).startswith("libvimpact_engine_"))


def test_a_built_in_run_loads_neither_ginac_nor_mpi(vimpact_cli):
    objects = loaded_by([vimpact_cli, "period", "--set", "Ur=19", "--transient", "20", "--record", "10"])
    assert any("libvimpact" in o for o in objects)  # the loader's report was read
    assert heavy(objects) == []
    assert engines(objects) == ["libvimpact_engine_wake_impact.so"]


def test_each_model_kind_loads_its_own_engine_module(vimpact_cli):
    objects = loaded_by([vimpact_cli, "period", "--model", "two_sided_impact_oscillator", "--transient", "20",
                         "--record", "10"])
    assert engines(objects) == ["libvimpact_engine_two_sided_impact_oscillator.so"]
    described = subprocess.run([vimpact_cli, "models", MODEL, "--json"], capture_output=True, text=True,
                               check=True).stdout
    dim = len(json.loads(described)["models"][0]["initial_state"])
    objects = loaded_by([vimpact_cli, "period", "--model", MODEL, "--section", "strobe", "--transient", "20",
                         "--record", "10"])
    # Its dimension's fixed-size module, or the runtime-sized one where the build lists no such
    # dimension (VIMPACT_MODEL_DIMS); never a built-in model's.
    assert len(engines(objects)) == 1
    assert engines(objects)[0] in (f"libvimpact_engine_table_{dim}.so", "libvimpact_engine_table_dynamic.so")


def test_a_model_file_loads_ginac_and_not_mpi(vimpact_cli, tmp_path):
    objects = loaded_by([vimpact_cli, "period", "--model", MODEL, "--section", "strobe", "--transient", "20",
                         "--record", "10"], env={"VIMPACT_CACHE_DIR": str(tmp_path)})
    assert any(os.path.basename(o).startswith("libginac") for o in objects)
    assert not any(os.path.basename(o).startswith("libmpi") for o in objects)


PYTHON_RUN = """
import vimpact
HEAVY = HEAVY_NAMES
MODEL = MODEL_FILE
def heavy(names=HEAVY):
    with open("/proc/self/maps") as f:
        return sorted(set(l.split()[-1].rsplit("/", 1)[-1] for l in f if any(h in l for h in names)))
vimpact.period(vimpact.WakeImpact(Ur=19), transient=20, record=10)
print("built-in:", heavy())
print("engines:", heavy(("libvimpact_engine_",)))
vimpact.period(vimpact.Model.from_file(MODEL), section="strobe", transient=20, record=10)
print("model file:", heavy())
"""


def test_python_loads_ginac_with_the_first_model_file(tmp_path):
    code = PYTHON_RUN.replace("HEAVY_NAMES", repr(HEAVY)).replace("MODEL_FILE", repr(MODEL))
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300,
                       env=dict(os.environ, PYTHONPATH=os.pathsep.join(q for q in sys.path if q),
                                VIMPACT_CACHE_DIR=str(tmp_path)))
    assert p.returncode == 0, p.stderr[-2000:]
    built_in, engines_loaded, model_file = p.stdout.splitlines()
    assert built_in == "built-in: []"
    assert engines_loaded == "engines: ['libvimpact_engine_wake_impact.so']"
    assert "libginac" in model_file and "libmpi" not in model_file
