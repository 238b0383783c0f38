"""examples/notebooks/*.ipynb: stored without outputs, and each runs from top to bottom in a
Jupyter kernel (nbclient, small grids with VIMPACT_QUICK=1), drawing its pictures; the period
label the paper's notebook prints is the command line's for the same run."""
import glob
import json
import os
import subprocess
import sys

import importlib.util

import pytest

from capabilities import need

HAVE = all(importlib.util.find_spec(m) for m in ("nbformat", "nbclient", "ipykernel"))
if HAVE:
    import nbclient
    import nbformat


@pytest.fixture(autouse=True, scope="module")
def notebooks_capability():
    need("notebooks", HAVE, "no Jupyter kernel: python3-nbclient, python3-nbformat, python3-ipykernel "
         "(scripts/install-deps.sh tests)")

NOTEBOOKS = sorted(glob.glob(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples",
                                          "notebooks", "*.ipynb")))


def test_the_three_notebooks_are_there():
    names = {os.path.basename(p) for p in NOTEBOOKS}
    assert {"paper_figures.ipynb", "own_model.ipynb", "continuation.ipynb"} <= names


@pytest.mark.parametrize("path", NOTEBOOKS, ids=os.path.basename)
def test_stored_without_outputs(path):
    nb = nbformat.read(path, as_version=4)
    nbformat.validate(nb)
    for cell in nb.cells:
        if cell.cell_type == "code":
            assert cell.outputs == [] and cell.execution_count is None, cell.source[:60]


@pytest.fixture(scope="module")
def executed(tmp_path_factory):
    """Each notebook run once: its cells with their outputs, by file name."""
    # The kernel inherits this environment: the build's module and a quick protocol.
    saved = dict(os.environ)
    os.environ.update(PYTHONPATH=os.pathsep.join(p for p in sys.path if p), VIMPACT_QUICK="1",
                      MPLBACKEND="module://matplotlib_inline.backend_inline")
    runs = {}
    try:
        for path in NOTEBOOKS:
            nb = nbformat.read(path, as_version=4)
            where = tmp_path_factory.mktemp(os.path.basename(path).removesuffix(".ipynb"))
            try:
                nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                                        resources={"metadata": {"path": str(where)}}).execute()
                runs[os.path.basename(path)] = nb
            except Exception as e:  # the test of that notebook reports it
                runs[os.path.basename(path)] = e
    finally:
        os.environ.clear()
        os.environ.update(saved)
    return runs


def ran(executed, name):
    nb = executed[name]
    if isinstance(nb, Exception):
        pytest.fail(f"{name}: {nb}")
    return nb


def texts(nb):
    out = []
    for cell in nb.cells:
        for o in cell.get("outputs", []):
            out.append(o.get("text", "") + "".join(o.get("data", {}).get("text/plain", "")))
    return "\n".join(out)


def pictures(nb):
    return [o["data"]["image/png"] for cell in nb.cells for o in cell.get("outputs", [])
            if "image/png" in o.get("data", {})]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=os.path.basename)
def test_runs_and_draws(path, executed):
    nb = ran(executed, os.path.basename(path))
    assert pictures(nb), "no picture drawn"
    # A picture with something drawn on it is far larger than an empty frame's PNG.
    assert max(len(p) for p in pictures(nb)) > 20000


def test_the_paper_notebooks_label_is_the_command_lines(cli, executed, tmp_path):
    nb = ran(executed, "paper_figures.ipynb")
    line = [t for t in texts(nb).splitlines() if t.startswith("Ur = 19:")][0]
    p = cli("period", "--set", "Ur=19", "--set", "sigma=-0.150298", "--transient", "100", "--record", "40", "--json",
            cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert line == f"Ur = 19: {json.loads(p.stdout)['label']}"
