"""`pip install --no-build-isolation .` into a fresh virtual environment, as docs/python.md says.

The source tree's files are copied (what git tracks, plus new files not ignored), pip builds
and installs them with the system's setuptools and no package index, and the copy is deleted:
the installed package then has to work on its own, from another directory, with no
PYTHONPATH. The build inside pip is a full Release build (5 minutes on an idle 2-core machine,
over 13 beside another build), so this runs only with VIMPACT_LONG_TESTS=1.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import textwrap
import time

import pytest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
TWO_SIDED_TOML = os.path.join(ROOT, "examples", "models", "two_sided_impact_oscillator.toml")

pytestmark = pytest.mark.skipif(not os.environ.get("VIMPACT_LONG_TESTS"),
                                reason="the pip build takes 5 minutes or more: set VIMPACT_LONG_TESTS=1")


def project_version():
    text = open(os.path.join(ROOT, "CMakeLists.txt")).read()
    return re.search(r"project\(vimpact\s+VERSION\s+([0-9.]+)", text).group(1)


@pytest.fixture(scope="module")
def venv(tmp_path_factory):
    """The virtual environment with vimpact installed, its source copy already gone."""
    base = tmp_path_factory.mktemp("pip")
    src = base / "src"
    files = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"], cwd=ROOT,
                           check=True, capture_output=True).stdout.decode().split("\0")
    for f in filter(None, files):
        if os.path.isfile(os.path.join(ROOT, f)):  # a tracked file deleted in the work tree is left out
            os.makedirs(src / os.path.dirname(f), exist_ok=True)
            shutil.copy2(os.path.join(ROOT, f), src / f)
    env_dir = base / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(env_dir)], check=True)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    start = time.monotonic()
    # --no-index: anything pip would have to download fails here instead of reaching for a network.
    p = subprocess.run([str(env_dir / "bin" / "pip"), "install", "--no-build-isolation", "--no-index", str(src)],
                       capture_output=True, text=True, env=env, cwd=base)
    sys.stderr.write(f"\npip install took {time.monotonic() - start:.0f} s\n")
    assert p.returncode == 0, p.stdout[-5000:] + p.stderr[-5000:]
    shutil.rmtree(src)
    return env_dir


@pytest.fixture
def run(venv, tmp_path):
    """run(*argv) in an empty directory with the environment's bin first on PATH and no PYTHONPATH; a
    compiler wrapper logs each model-file compile's arguments to tmp_path/cxx.log."""
    wrapper = tmp_path / "cxx"
    wrapper.write_text(f'#!/bin/sh\necho "$@" >> {tmp_path / "cxx.log"}\nexec c++ "$@"\n')
    wrapper.chmod(0o755)
    work = tmp_path / "work"
    work.mkdir()
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env.update(PATH=f"{venv / 'bin'}:{env.get('PATH', '')}", VIMPACT_CACHE_DIR=str(tmp_path / "cache"),
               CXX=str(wrapper), MPLBACKEND="Agg")

    def go(*argv):
        p = subprocess.run(list(map(str, argv)), capture_output=True, text=True, env=env, cwd=work, timeout=600)
        assert p.returncode == 0, p.stdout + p.stderr
        return p.stdout
    return go


def is_png(path):
    with open(path, "rb") as f:
        return f.read(8) == b"\x89PNG\r\n\x1a\n"


def test_module_version_analysis_and_picture(venv, run, tmp_path):
    code = textwrap.dedent(f"""
        import json, vimpact
        m = vimpact.Model("wake_impact", Ur=19)
        s = vimpact.simulate(m, record=20, sample_dt=0.1)
        vimpact.plot.phase(s, {str(tmp_path / "phase.png")!r})
        print(json.dumps({{"version": vimpact.__version__, "file": vimpact.__file__,
                           "period": vimpact.period(m).label}}))
    """)
    out = json.loads(run(venv / "bin" / "python", "-c", code))
    assert out["version"] == project_version()
    assert out["file"].startswith(str(venv)), out["file"]
    assert out["period"] == "P3"
    assert is_png(tmp_path / "phase.png")


def test_model_file_compiled_with_the_installed_headers(venv, run, tmp_path):
    code = f"import vimpact; print(vimpact.period(vimpact.Model({TWO_SIDED_TOML!r})).label)"
    assert run(venv / "bin" / "python", "-c", code).strip() == "P1"
    # The library's own Runge-Kutta steps, from the package's copy of the headers (the
    # source tree is gone; without them the model would compile without fused steps).
    code = "import os, vimpact; print(os.path.realpath(os.path.dirname(vimpact.__file__)))"
    site = run(venv / "bin" / "python", "-c", code).strip()
    assert f"-I{site}/include" in (tmp_path / "cxx.log").read_text()


def test_program(venv, run, tmp_path):
    assert "simulate" in run(venv / "bin" / "vimpact", "--help")
    assert json.loads(run(venv / "bin" / "vimpact", "period", "--set", "Ur=19", "--json"))["label"] == "P3"
    assert json.loads(run(venv / "bin" / "vimpact", "period", "--model", TWO_SIDED_TOML, "--json"))["label"] == "P1"
    out = tmp_path / "out"
    run(venv / "bin" / "vimpact", "simulate", "--set", "Ur=19", "--record", "20", "--out", out)
    assert is_png(out / "plot.png"), "the program drew no picture with the environment's interpreter"
