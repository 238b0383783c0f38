#!/usr/bin/env bash
# Installs what vimpact needs from Debian's archive, by purpose, so that a first run installs
# only what the main job uses:
#   main    build the library, the program and the Python module, run them, draw the pictures
#   tests   main and what the test command adds (GoogleTest, pytest, MPI, ccache, pip's tools)
#   bench   main and the benchmarks' peers (Google Benchmark, Boost.Odeint, SUNDIALS, SciPy)
#
#   bash scripts/install-deps.sh [PURPOSE...]     (default: main)
#   bash scripts/install-deps.sh --list PURPOSE   prints PURPOSE's packages, one per line
#
# Idempotent: packages already present are skipped, and apt is not touched at all when nothing
# is missing.
set -euo pipefail

main=(
  # Ninja compiles the program's sources alongside the library's (Make waits for the library)
  build-essential cmake ninja-build git pkg-config
  libeigen3-dev libcli11-dev libtomlplusplus-dev nlohmann-json3-dev
  # journal lines read fast by a distributed run's coordinator (src/io/json_line.hpp)
  libsimdjson-dev
  # model files (symbolic derivatives) and the correlation dimension's k-d tree
  libginac-dev libnanoflann-dev
  # SHA-256 of the compiled-model cache (libcrypto; src/model_file_compile.cpp)
  libssl-dev
  # SIMD lanes of the job commands (include/vimpact/core/lanes.hpp)
  libxsimd-dev
  # the Python module and the pictures
  python3 python3-dev pybind11-dev python3-numpy python3-matplotlib
  # plotly.js for the page of `vimpact explore`, served from the machine
  python3-plotly
)
tests=(
  # the test command reuses earlier builds' objects where it can (scripts/run-tests.sh)
  ccache
  libgtest-dev libgmock-dev python3-pytest
  # the notebooks of examples/notebooks, executed by the tests
  python3-nbclient python3-nbformat python3-ipykernel
  # the explorer's page driven in a real, headless browser (tests/python/test_explore.py)
  chromium chromium-driver python3-selenium
  # Python results as data frames and labelled grids (to_pandas, to_xarray)
  python3-pandas python3-xarray
  # many-job runs across processes: mpirun -n N vimpact map ... (docs/distributed.md)
  libopenmpi-dev openmpi-bin
  # pip install --no-build-isolation . (docs/python.md) builds with these, not PyPI's
  python3-venv python3-pip python3-setuptools python3-wheel
)
bench=(
  libbenchmark-dev
  # the peers the benchmarks compare with: Boost.Odeint, SUNDIALS (CVODE), SciPy
  libboost-dev libsundials-dev python3-scipy
)

purpose_packages() {  # purpose_packages PURPOSE: its packages, main's included
  case "$1" in
    main) printf '%s\n' "${main[@]}" ;;
    tests) printf '%s\n' "${main[@]}" "${tests[@]}" ;;
    bench) printf '%s\n' "${main[@]}" "${bench[@]}" ;;
    *) echo "install-deps: unknown purpose '$1' (purposes: main, tests, bench)" >&2; exit 2 ;;
  esac
}

if [ "${1:-}" = "--list" ]; then
  [ $# -eq 2 ] || { echo "install-deps: --list takes one purpose (main, tests, bench)" >&2; exit 2; }
  purpose_packages "$2"
  exit 0
fi

purposes=("$@")
[ ${#purposes[@]} -gt 0 ] || purposes=(main)
packages=()
for purpose in "${purposes[@]}"; do
  list=$(purpose_packages "$purpose")  # exits 2 on an unknown purpose
  mapfile -t -O "${#packages[@]}" packages <<< "$list"
done

missing=()
for p in $(printf '%s\n' "${packages[@]}" | sort -u); do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all packages for ${purposes[*]} present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
