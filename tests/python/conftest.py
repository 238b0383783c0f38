import json
import os
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))


def pytest_addoption(parser):
    parser.addoption("--vimpact", action="store", default=None, help="path to the vimpact program")


@pytest.fixture(scope="session")
def vimpact_cli(request):
    path = request.config.getoption("--vimpact") or os.environ.get("VIMPACT")
    if not path:
        path = os.path.join(HERE, "..", "..", "build", "vimpact")
    assert os.path.exists(path), f"vimpact program not found at {path}"
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


def pytest_configure(config):
    # The package under test is the build tree's (PYTHONPATH=build/python), never an
    # installed one; say which in the report header.
    import vimpact
    sys.stderr.write(f"vimpact from {os.path.dirname(vimpact.__file__)}\n")
