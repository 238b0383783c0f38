"""The Python package vimpact, built by the project's CMake build.

``pip install --no-build-isolation .`` (pyproject.toml) runs this: CMake builds the library,
the compiled module and the program (Release, no tests or benchmarks) and installs them in the
layout of a Python package (-DVIMPACT_PYTHON_PACKAGE=ON): site-packages/vimpact holds the pure-
Python files, _vimpact, libvimpact.so and the headers model files are compiled with; the
program goes to the environment's bin. Extra CMake options: CMAKE_ARGS; parallel jobs:
CMAKE_BUILD_PARALLEL_LEVEL, else one per CPU.
"""
import os
import re
import shlex
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def project_version():
    # CMakeLists.txt's project() is the one place the version is written.
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(vimpact\s+VERSION\s+([0-9.]+)", text).group(1)


def site_packages_from_bin():
    """Relative paths from the scripts directory to platlib, for the install schemes pip may
    use with this interpreter: its default (a virtual environment's, or the system's) and the
    user's (--user)."""
    schemes = [sysconfig.get_default_scheme(), f"{os.name}_user"]
    paths = []
    for scheme in schemes:
        if scheme not in sysconfig.get_scheme_names():
            continue
        p = sysconfig.get_paths(scheme)
        rel = os.path.relpath(p["platlib"], p["scripts"])
        if rel not in paths:
            paths.append(rel)
    return paths


class CMakeBuild(build_ext):
    """The usual CMake-extension build: one CMake build stands for the placeholder extension."""

    def run(self):
        if self.inplace:
            raise RuntimeError("vimpact has no editable install: build with CMake and use "
                               "PYTHONPATH=build/python (docs/python.md)")
        build = Path(self.build_temp).resolve() / "cmake"
        package_root = Path(self.build_lib).resolve()
        stage = Path(self.build_temp).resolve() / "program"
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(self.parallel or os.cpu_count() or 1)
        configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                     "-DVIMPACT_BUILD_TESTS=OFF", "-DVIMPACT_BUILD_BENCH=OFF", "-DVIMPACT_PYTHON_PACKAGE=ON",
                     # The interpreter installing the package: the module is built for it, and
                     # the program draws its pictures with it, from the environment that has
                     # the package.
                     f"-DPython3_EXECUTABLE={sys.executable}",
                     "-DVIMPACT_SITE_PACKAGES_FROM_BIN=" + ";".join(site_packages_from_bin())]
        configure += shlex.split(os.environ.get("CMAKE_ARGS", ""))
        subprocess.run(configure, check=True)
        subprocess.run(["cmake", "--build", str(build), "--target", "_vimpact", "vimpact_cli", "-j", jobs],
                       check=True)
        subprocess.run(["cmake", "--install", str(build), "--component", "python_package",
                        "--prefix", str(package_root)], check=True)
        subprocess.run(["cmake", "--install", str(build), "--component", "python_package_program",
                        "--prefix", str(stage)], check=True)
        # The program is data for bin rather than a setuptools script: build_scripts reads
        # scripts as Python source. Every install scheme's data directory holds its bin.
        self.distribution.data_files = [("bin", [str(stage / "bin" / "vimpact")])]


setup(
    version=project_version(),
    packages=["vimpact"],
    package_data={"vimpact": ["*.html"]},  # the explorer's page
    package_dir={"": "python"},
    ext_modules=[Extension("vimpact._vimpact", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    # Not in build/: that is the documented CMake build directory.
    options={"build": {"build_base": "build-python-package"}},
)
