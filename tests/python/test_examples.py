"""examples/python/*.py run (with --quick, their CI size) and write their pictures."""
import glob
import os
import subprocess
import sys

import pytest

EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "python")
SCRIPTS = sorted(p for p in glob.glob(os.path.join(EXAMPLES, "*.py")) if not os.path.basename(p).startswith("_"))


def test_every_analysis_has_an_example():
    names = {os.path.splitext(os.path.basename(p))[0] for p in SCRIPTS}
    assert {"period", "sweep", "map", "basins", "response", "stability", "model_file"} <= names


@pytest.mark.parametrize("script", SCRIPTS, ids=os.path.basename)
def test_example_runs(tmp_path, script):
    env = dict(os.environ, OUT=str(tmp_path), MPLBACKEND="Agg",
               PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    p = subprocess.run([sys.executable, script, "--quick"], capture_output=True, text=True, env=env, timeout=300,
                       cwd=tmp_path)
    assert p.returncode == 0, p.stdout + p.stderr
    name = os.path.splitext(os.path.basename(script))[0]
    assert os.path.getsize(tmp_path / "python" / f"{name}.png") > 1000
    assert "picture:" in p.stdout
