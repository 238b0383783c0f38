import os
import sys
import shutil
import subprocess
import tempfile

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from capabilities import need, required  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
TWO_SIDED_TOML = os.path.join(ROOT, "examples", "models", "two_sided_impact_oscillator.toml")

# Model files are compiled into a cache, never the user's: the one the test run shares
# (VIMPACT_TEST_CACHE_DIR, set by CTest for every test file of a build), else a fresh one for
# the session.
_SHARED = os.environ.get("VIMPACT_TEST_CACHE_DIR")
_CACHE = _SHARED or tempfile.mkdtemp(prefix="vimpact-cli-cache-")
os.environ["VIMPACT_CACHE_DIR"] = _CACHE


def pytest_addoption(parser):
    parser.addoption("--vimpact", action="store", default=None, help="path to the vimpact program")


def pytest_unconfigure(config):
    if not _SHARED:
        shutil.rmtree(_CACHE, ignore_errors=True)


@pytest.fixture(scope="session")
def vimpact(request):
    path = request.config.getoption("--vimpact") or os.environ.get("VIMPACT")
    if not path:
        path = os.path.join(ROOT, "build", "vimpact")
    assert os.path.exists(path), f"vimpact program not found at {path}"
    return os.path.abspath(path)


def _plots_work():
    """Whether `python3 -m vimpact.plot` can run (the Python package is being rewritten: the
    picture checks are skipped, not failed, while it cannot)."""
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "python"), MPLBACKEND="Agg")
    p = subprocess.run(["/usr/bin/python3", "-c", "import vimpact.plot"], env=env, capture_output=True)
    return p.returncode == 0


PLOTS = _plots_work()


def check_png(path):
    """The picture exists and is a PNG, when the plotting package works; else skipped."""
    if not PLOTS:
        if required("plots"):
            pytest.fail("the plotting package does not run here; VIMPACT_REQUIRE names plots", pytrace=False)
        return
    with open(path, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
