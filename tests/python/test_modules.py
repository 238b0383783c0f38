"""GiNaC (model files) and MPI (runs launched as several ranks) live in modules the library
loads when a run needs them (src/core/load_module.hpp): a run of a built-in model in one
process loads neither library, from the command line or from Python; a model file loads GiNaC."""
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


def test_a_built_in_run_loads_neither_ginac_nor_mpi(vimpact_cli):
    objects = loaded_by([vimpact_cli, "period", "--set", "Ur=19", "--transient", "20", "--record", "10"])
    assert any("libvimpact" in o for o in objects)  # the loader's report was read
    assert heavy(objects) == []


def test_a_model_file_loads_ginac_and_not_mpi(vimpact_cli, tmp_path):
    objects = loaded_by([vimpact_cli, "period", "--model", MODEL, "--section", "strobe", "--transient", "20",
                         "--record", "10"], env={"VIMPACT_CACHE_DIR": str(tmp_path)})
    assert any(os.path.basename(o).startswith("libginac") for o in objects)
    assert not any(os.path.basename(o).startswith("libmpi") for o in objects)


PYTHON_RUN = """
import vimpact
HEAVY = HEAVY_NAMES
MODEL = MODEL_FILE
def heavy():
    with open("/proc/self/maps") as f:
        return sorted(set(l.split()[-1].rsplit("/", 1)[-1] for l in f if any(h in l for h in HEAVY)))
vimpact.period(vimpact.WakeImpact(Ur=19), transient=20, record=10)
print("built-in:", heavy())
vimpact.period(vimpact.Model.from_file(MODEL), section="strobe", transient=20, record=10)
print("model file:", heavy())
"""


def test_python_loads_ginac_with_the_first_model_file(tmp_path):
    code = PYTHON_RUN.replace("HEAVY_NAMES", repr(HEAVY)).replace("MODEL_FILE", repr(MODEL))
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300,
                       env=dict(os.environ, PYTHONPATH=os.pathsep.join(q for q in sys.path if q),
                                VIMPACT_CACHE_DIR=str(tmp_path)))
    assert p.returncode == 0, p.stderr[-2000:]
    built_in, model_file = p.stdout.splitlines()
    assert built_in == "built-in: []"
    assert "libginac" in model_file and "libmpi" not in model_file
