"""scripts/install-deps.sh installs by purpose: the main job (scripts/run-main.sh) gets only
what it builds and runs, the test command and the benchmarks add their own packages."""
import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "install-deps.sh"
PURPOSES = ("main", "tests", "bench")


def listed(purpose):
    p = subprocess.run(["bash", str(SCRIPT), "--list", purpose], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return p.stdout.split()


def test_every_purpose_holds_the_main_jobs_packages_once():
    main = set(listed("main"))
    for purpose in PURPOSES:
        packages = listed(purpose)
        assert len(packages) == len(set(packages)), purpose
        assert main <= set(packages), purpose


def test_the_main_job_installs_no_test_or_benchmark_package():
    main = set(listed("main"))
    others = (set(listed("tests")) | set(listed("bench"))) - main
    # What the tests and the benchmarks build with, and the SUNDIALS package that pulled
    # PETSc and Trilinos into every first install.
    for package in ("libgtest-dev", "python3-pytest", "libopenmpi-dev", "libbenchmark-dev", "libsundials-dev"):
        assert package in others, package


@pytest.mark.parametrize("args", [["--list", "docs"], ["docs"], ["--list"]])
def test_an_unknown_or_missing_purpose_exits_2_and_installs_nothing(args):
    p = subprocess.run(["bash", str(SCRIPT), *args], capture_output=True, text=True)
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert "purpose" in p.stderr and "main, tests, bench" in p.stderr
    assert "installing" not in p.stdout


@pytest.mark.skipif(shutil.which("apt-cache") is None, reason="not a Debian machine")
def test_every_package_is_in_the_archive():
    packages = sorted(set(listed("tests")) | set(listed("bench")))
    p = subprocess.run(["apt-cache", "show", "--no-all-versions", *packages], capture_output=True, text=True)
    found = set(re.findall(r"^Package: (\S+)$", p.stdout, flags=re.M))
    assert found == set(packages), set(packages) - found


def test_the_main_job_configures_without_the_tests_and_benchmarks_packages(tmp_path):
    # run-main.sh's own configure line, with the packages only the tests and the benchmarks
    # install made invisible to CMake: it must not need them.
    text = (ROOT / "scripts" / "run-main.sh").read_text()
    line = re.search(r'^cmake -S \. -B build "\$\{options\[@\]\}" >', text, flags=re.M)
    options = re.search(r"^options=\((.*?)\)$", text, flags=re.M)
    assert line and options, "run-main.sh has no configure line"
    hidden = [f"-DCMAKE_DISABLE_FIND_PACKAGE_{name}=ON" for name in ("GTest", "benchmark", "Boost", "MPI")]
    p = subprocess.run(["cmake", "-S", str(ROOT), "-B", str(tmp_path / "build"), *options.group(1).split(), *hidden],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
