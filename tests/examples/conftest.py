import pytest


def pytest_addoption(parser):
    parser.addoption("--example", help="the run_impact_damper program")
    parser.addoption("--plugin", help="the impact_damper plugin (shared library)")
    parser.addoption("--vimpact", default="", help="the vimpact program ('' if not built)")
    parser.addoption("--source", help="the repository")
    parser.addoption("--build", help="the build directory")


@pytest.fixture(scope="session")
def opts(request):
    return {k: request.config.getoption(k) for k in ("example", "plugin", "vimpact", "source", "build")}


@pytest.fixture(autouse=True)
def cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("VIMPACT_CACHE_DIR", str(tmp_path_factory.getbasetemp() / "cache"))
