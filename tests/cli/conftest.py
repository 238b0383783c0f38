import os

import pytest


def pytest_addoption(parser):
    parser.addoption("--vimpact", action="store", default=None, help="path to the vimpact program")


@pytest.fixture(scope="session")
def vimpact(request):
    path = request.config.getoption("--vimpact") or os.environ.get("VIMPACT")
    if not path:
        here = os.path.dirname(os.path.abspath(__file__))
        path = os.path.join(here, "..", "..", "build", "vimpact")
    assert os.path.exists(path), f"vimpact program not found at {path}"
    return os.path.abspath(path)
