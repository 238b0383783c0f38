import json
import os
import shutil
import subprocess
import sys
import tempfile

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from capabilities import need  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
TWO_SIDED_TOML = os.path.join(ROOT, "examples", "models", "two_sided_impact_oscillator.toml")


def pytest_addoption(parser):
    parser.addoption("--vimpact", action="store", default=None, help="path to the vimpact program")


def pytest_configure(config):
    # Model files compile into a cache of the test run's own (VIMPACT_CACHE_DIR), inherited by
    # the subprocesses the tests start, so no test reads or fills the user's cache: the one
    # the test files of a build share (VIMPACT_TEST_CACHE_DIR, set by CTest), else a fresh one.
    shared = os.environ.get("VIMPACT_TEST_CACHE_DIR")
    cache = shared or tempfile.mkdtemp(prefix="vimpact-pytest-cache-")
    os.environ["VIMPACT_CACHE_DIR"] = cache
    config._vimpact_cache = "" if shared else cache
    # The package under test is the build tree's (PYTHONPATH=build/python), never an
    # installed one; say which in the report header.
    import vimpact
    sys.stderr.write(f"vimpact from {os.path.dirname(vimpact.__file__)}\n")


def pytest_unconfigure(config):
    if getattr(config, "_vimpact_cache", ""):
        shutil.rmtree(config._vimpact_cache, ignore_errors=True)


@pytest.fixture(scope="session")
def vimpact_cli(request):
    """The command-line program; the comparisons with it are skipped where it is not built."""
    path = request.config.getoption("--vimpact") or os.environ.get("VIMPACT")
    if not path:
        path = os.path.join(ROOT, "build", "vimpact")
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        need("cli", False, f"the vimpact program is not built at {path} (configure with -DVIMPACT_BUILD_CLI=ON, or "
                           f"pass --vimpact=PATH): the comparisons with the command line need it")
    # A program built before the command line took any model (no --model) writes other files.
    help_text = subprocess.run([path, "simulate", "--help"], capture_output=True, text=True, timeout=60).stdout
    if "--model" not in help_text:
        pytest.skip(f"the vimpact program at {path} predates the model-generic command line (no --model option): "
                    f"rebuild it to compare with it")
    return os.path.abspath(path)


@pytest.fixture(scope="session")
def cli(vimpact_cli):
    """cli(*args) -> CompletedProcess of the command line program."""
    def run(*args, cwd=None):
        return subprocess.run([vimpact_cli, *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=300)
    return run


@pytest.fixture(scope="session")
def cli_json(cli):
    def run(*args):
        p = cli(*args, "--json")
        assert p.returncode == 0, p.stderr
        return json.loads(p.stdout)
    return run


@pytest.fixture(scope="session")
def two_sided_file():
    """The two-stop oscillator as a model file, compiled once into the run's cache."""
    import vimpact
    return vimpact.Model.from_file(TWO_SIDED_TOML)
