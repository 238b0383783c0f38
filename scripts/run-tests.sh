#!/usr/bin/env bash
# Installs the dependencies, builds with warnings as errors and runs every test (GoogleTest and
# pytest under CTest: unit, command line, Python, examples, documents). A failed build or a
# missing test fails the run. About 13 minutes on 2 cores from a clean clone.
# Longer checks, VIMPACT_LONG_TESTS=1: the long unit tests, the pip package, and then a second
# build of the unit tests with AddressSanitizer + UBSan, run again (about 20 minutes more).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh tests
jobs=$(nproc)
# A capability the installer provided that a test finds missing fails the test instead of
# skipping it (tests/capabilities.py).
export VIMPACT_REQUIRE=plots,mpi,cli,notebooks,frames,browser
# Objects of an earlier build of the same sources come from ccache (installed above), in any
# clone: paths are hashed relative to the clone.
launcher=()
if command -v ccache > /dev/null; then
    export CCACHE_BASEDIR=$PWD CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi

build() {  # build DIR TARGET...: the log on failure only
    local dir=$1
    shift
    if ! cmake --build "$dir" -j"$jobs" "$@" > "$dir/build.log" 2>&1; then
        grep -E "error|Error" "$dir/build.log" | head -40
        tail -20 "$dir/build.log"
        exit 1
    fi
}

# Ninja (installed by install-deps.sh) for a new build directory (an existing one keeps the
# generator it was made with): Make compiles a target's objects only after the targets it links are
# linked, so the program, the module and the tests waited for the library's last object with a
# core idle; Ninja compiles them alongside it.
new_dir_generator() {  # new_dir_generator DIR
    if [ ! -f "$1/CMakeCache.txt" ] && command -v ninja > /dev/null; then echo -GNinja; fi
}

echo "== dev build (Release, -Werror)"
# The benchmarks are not built here: bench/run_*.sh build and run them.
# A unity build, as scripts/run-main.sh's (about half the CPU for the library, the program
# and the Python module; the test files stay units of their own: tests/CMakeLists.txt).
cmake -S . -B build $(new_dir_generator build) -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON -DVIMPACT_WERROR=ON \
      -DVIMPACT_BUILD_TESTS=ON -DVIMPACT_BUILD_BENCH=OFF "${launcher[@]}" > /dev/null
build build
# A new build directory has no record of how long each test takes, and CTest would start the
# tests in the order they were declared: the recorded costs make it start the longest first.
costs=build/Testing/Temporary/CTestCostData.txt
if [ ! -f "$costs" ]; then mkdir -p "$(dirname "$costs")"; grep -v '^#' tests/ctest-costs.txt > "$costs"; fi
(cd build && ctest --output-on-failure --no-tests=error -j"$jobs")

if [ "${VIMPACT_LONG_TESTS:-}" != 1 ]; then
    echo "== done (VIMPACT_LONG_TESTS=1 adds the long tests and the sanitizer build)"
    exit 0
fi

echo "== sanitizer build (ASan + UBSan) of the unit tests"
# -O1 without debug info: at -O2 -g the instrumented stability tests take minutes per file to
# compile. Model files of dimensions 3 and 4 only: the unit tests use no others, and every
# further dimension is one more instrumented copy of every analysis.
# With AVX2 the SIMD lanes (4 doubles a register, core/lanes.hpp) are built and tested under the
# sanitizers too; without it the lanes tests skip. AVX2 rather than the machine's own set: GCC
# 12's AVX-512 headers raise false uninitialised-value warnings (CMakeLists.txt).
simd=""
if grep -qw avx2 /proc/cpuinfo && grep -qw fma /proc/cpuinfo; then simd="-mavx2 -mfma"; fi
cmake -S . -B build-asan $(new_dir_generator build-asan) -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1" -DCMAKE_CXX_FLAGS="$simd" -DVIMPACT_SANITIZE=ON \
      -DVIMPACT_WERROR=ON -DVIMPACT_BUILD_BENCH=OFF -DVIMPACT_BUILD_PYTHON=OFF -DVIMPACT_BUILD_CLI=OFF \
      -DVIMPACT_MODEL_DIMS="3;4" "${launcher[@]}" > /dev/null
build build-asan --target vimpact_tests
# (The test binary suppresses CLN's load-time allocation itself: tests/model_file_test.cpp.)
(cd build-asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --output-on-failure --no-tests=error -j"$jobs" -L unit)
