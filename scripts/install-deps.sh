#!/usr/bin/env bash
# Installs vimpact's build, test and plotting dependencies from Debian's archive.
# Idempotent: packages already present are skipped, and apt is not touched at all when
# nothing is missing.
set -euo pipefail

packages=(
  build-essential cmake git pkg-config
  # the test command reuses earlier builds' objects where it can (scripts/run-tests.sh)
  ccache
  libeigen3-dev libcli11-dev libtomlplusplus-dev nlohmann-json3-dev libfmt-dev
  # journal lines read fast by a distributed run's coordinator (src/io/json_line.hpp)
  libsimdjson-dev
  libgtest-dev libgmock-dev libbenchmark-dev libboost-dev libnanoflann-dev libginac-dev
  # SHA-256 of the compiled-model cache (libcrypto; src/model_file_compile.cpp)
  libssl-dev
  # SIMD lanes of the job commands (include/vimpact/core/lanes.hpp)
  libxsimd-dev
  # bench/ only: the SUNDIALS peer baseline (built when found)
  libsundials-dev
  python3 python3-numpy python3-scipy python3-matplotlib python3-pytest pybind11-dev python3-dev
  # pip install --no-build-isolation . (docs/python.md) builds with these, not PyPI's
  python3-venv python3-pip python3-setuptools python3-wheel
  # many-job runs across processes: mpirun -n N vimpact map ... (docs/distributed.md)
  libopenmpi-dev openmpi-bin
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
