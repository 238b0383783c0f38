#!/usr/bin/env bash
# Installs the dependencies, builds with warnings as errors, runs every test (GoogleTest and
# pytest under CTest), then builds the unit tests with AddressSanitizer + UBSan and runs them.
# Longer checks: VIMPACT_LONG_TESTS=1.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
jobs=$(nproc)

echo "== dev build (Release, -Werror)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DVIMPACT_WERROR=ON > /dev/null
cmake --build build -j"$jobs" 2>&1 | grep -E "error|warning|Linking" || true
test -x build/vimpact
(cd build && ctest --output-on-failure -j"$jobs")

echo "== sanitizer build (ASan + UBSan) of the unit tests"
# -O1 without debug info: at -O2 -g the instrumented stability tests take minutes per file to
# compile (8 min for the whole build against 3.5 at -O1 on 2 cores).
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1" -DVIMPACT_SANITIZE=ON \
      -DVIMPACT_WERROR=ON -DVIMPACT_BUILD_BENCH=OFF -DVIMPACT_BUILD_PYTHON=OFF > /dev/null
cmake --build build-asan -j"$jobs" --target vimpact_tests 2>&1 | grep -E "error|warning|Linking" || true
(cd build-asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --output-on-failure -j"$jobs" -L unit)
