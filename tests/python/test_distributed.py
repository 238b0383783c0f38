"""Python under MPI (docs/distributed.md): a script starts the command line on several ranks
with mpirun and reads the directory back with the package's readers; the result equals the
Python call computed in this process, field by field. Skipped without mpirun or without a
vimpact program built with MPI."""
import shutil
import subprocess

import numpy as np
import pytest

import vimpact
from conftest import need


@pytest.fixture(scope="module")
def mpirun(vimpact_cli):
    need("mpi", shutil.which("mpirun") is not None, "mpirun is not installed")
    cmd = ["mpirun", "--oversubscribe", "--allow-run-as-root"]
    p = subprocess.run(cmd + ["-n", "2", vimpact_cli, "sweep", "--param", "Ur", "--range", "16:17:2", "--transient",
                              "20", "--record", "10"], capture_output=True, text=True, timeout=300)
    need("mpi", "built without MPI" not in p.stderr, "the vimpact program was built without MPI")
    assert p.returncode == 0, p.stderr
    return cmd


def test_a_map_on_two_ranks_read_back_in_python(vimpact_cli, mpirun, tmp_path):
    out = tmp_path / "map"
    # As in docs/distributed.md: the ranks run the command line, Python reads the directory.
    subprocess.run(mpirun + ["-n", "2", vimpact_cli, "map", "--x", "Ur:16:25:5", "--y", "sigma:-0.16:-0.02:4",
                             "--transient", "80", "--record", "40", "--tol", "1e-5", "--threads", "1", "--no-plot",
                             "--out", str(out)], check=True, capture_output=True, timeout=300)
    loaded = vimpact.Map.load(out)
    here = vimpact.map(vimpact.WakeImpact(), x=("Ur", vimpact.grid(16, 25, 5)), y=("sigma", vimpact.grid(-0.16, -0.02, 4)),
                       tol=1e-5, transient=80, record=40)
    for name in ("x_values", "y_values", "label", "period", "impacts", "outcome"):
        a, b = np.asarray(getattr(here, name)), np.asarray(getattr(loaded, name))
        assert a.shape == b.shape and (a == b).all(), name
