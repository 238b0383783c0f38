"""Every figure script of examples/ runs in its --quick size and writes pictures that draw its
data."""
import glob
import json
import os
import subprocess
import sys

import pytest

from conftest import PLOTS, need

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = sorted(glob.glob(os.path.join(HERE, "..", "..", "examples", "fig*.sh")))


def test_there_is_a_script_per_figure_of_the_issue():
    names = {os.path.basename(p)[:-3] for p in EXAMPLES}
    wanted = {"fig2a", "fig2b", "fig2c", "fig3", "fig4", "fig5a", "fig5b", "fig5g", "fig7", "fig8", "fig9",
              "fig10a", "fig10b", "fig10c", "fig10d", "fig6", "fig14", "fig15", "fig16", "fig17"} | {f"fig11{c}" for c in "abcdef"}
    assert wanted <= names


@pytest.mark.parametrize("script", EXAMPLES, ids=[os.path.basename(p) for p in EXAMPLES])
def test_example_quick(vimpact, tmp_path, script):
    need("plots", PLOTS, "python3 -m vimpact.plot does not run here")
    env = dict(os.environ, VIMPACT=vimpact, OUT=str(tmp_path))
    p = subprocess.run(["bash", script, "--quick"], capture_output=True, text=True, env=env, timeout=600)
    assert p.returncode == 0, p.stdout + p.stderr
    assert "warning" not in p.stderr, p.stderr
    name = os.path.basename(script)[:-3]
    pngs = glob.glob(os.path.join(tmp_path, name, "**", "plot.png"), recursive=True)
    assert pngs, f"{script} wrote no picture"
    # What each picture of a run directory draws, redrawn from the directory: data in its first
    # axes (the diagram, map or chart itself), not only a file of some size. (A picture of
    # several runs drawn together, with no run.json beside it, is only checked for its size.)
    directories = sorted(os.path.dirname(f) for f in pngs if os.path.exists(os.path.join(os.path.dirname(f), "run.json")))
    assert all(os.path.getsize(f) > 10_000 for f in pngs)
    p = subprocess.run([sys.executable, os.path.join(HERE, "picture_census.py"), *directories], capture_output=True,
                       text=True, env=dict(os.environ, PYTHONPATH=os.path.join(HERE, "..", "..", "python")), timeout=600)
    assert p.returncode == 0, p.stderr
    for directory, axes in json.loads(p.stdout).items():
        where = os.path.relpath(directory, tmp_path)
        assert axes, f"{where}: the picture has no axes"
        assert axes[0]["values"] >= 2, f"{where}: the picture's first axes draws {axes[0]['values']} values: {axes}"
