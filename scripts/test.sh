#!/usr/bin/env bash
# Builds and runs every test.
#   1. Release build with g++ (preset "release", build/): all tests, including the packaging test. Both builds make only the
#      target spatial_test_programs (the test executables and the tools they run), not the benchmarks and the iLQR
#      example: scripts/main.sh builds and runs those.
#   2. The Python package (scripts/python.sh --test): built into build/venv (with Pinocchio's `pin` from
#      scripts/peers.sh, whose Python API the package is checked against) and its pytest suite (python/tests).
#      Then the spherical joints' peer check: bench_general (bench/bench_general.cpp, built against that Pinocchio
#      once build/venv holds it) checks RNEA, CRBA and ABA of a tree with spherical joints against Pinocchio's
#      JointModelSpherical and aborts on a mismatch; it times nothing here (scripts/main.sh does). Without Pinocchio
#      (pip failed) it is skipped with a warning, as the Python package's Pinocchio tests are.
#   3. ARM (scripts/arm.sh, build-arm/): the portable unit tests cross-built for aarch64 (g++-aarch64-linux-gnu) and
#      run under qemu-user, Eigen and xsimd on NEON; no URDF, KDL or CLI tests (no urdfdom or KDL for aarch64 here).
#   4. Debug build with clang++, ASan and UBSan (preset "asan", build-asan/; -g1: line tables only, enough for the
#      sanitizers' stack traces): the unit, AVX2-kernel and stress tests (tests/CMakeLists.txt). clang++, not g++:
#      the instrumented unoptimised tests compile in 712 CPU-s instead of 1605 (2026-12-02), and the suite is read by
#      a second compiler (it refused a lambda capturing a structured binding, which C++17 forbids and g++ allows).
#      Both builds compile the tests with SPATIAL_NO_FORCED_INLINE (tests/CMakeLists.txt says why): the sanitizer
#      build's jobs took 747 s in all instead of 1366 with forced inlining (`scripts/build_times.sh build-asan`,
#      2026-12-03 against 2026-12-02), and this script's release stage ended at 1000 s instead of 1500.
#   5. The URDF loader's fuzz target (scripts/fuzz.sh, clang + libFuzzer + ASan/UBSan, build-fuzz/) for 30 s on $JOBS
#      processes (60 CPU-s with the default two: the minute of fuzzing it always had, in half the time).
# Usage: scripts/test.sh [--quick]    --quick skips steps 3, 4 and 5.
# JOBS (default 2) sets the parallelism of builds and tests.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

quick=0
for arg in "$@"; do
  case "$arg" in
    --quick) quick=1 ;;
    -h|--help) echo "usage: scripts/test.sh [--quick]   (--quick skips the ARM and sanitizer builds and the fuzzer)"; exit 0 ;;
    *) echo "test.sh: unknown argument '$arg' (try --help)" >&2; exit 2 ;;
  esac
done
jobs=${JOBS:-2}

bash scripts/deps.sh

echo "==== release build and tests ===="
cmake --preset release
cmake --build --preset release --parallel "$jobs" --target spatial_test_programs
ctest --test-dir build --output-on-failure --no-tests=error -j "$jobs"
echo "test.sh: release stage done at ${SECONDS} s"

echo "==== Python package: build and pytest ===="
bash scripts/peers.sh
bash scripts/python.sh --test
# build/venv now holds Pinocchio (peers.sh never fails: without pip, no Pinocchio), so configuring again makes the
# bench_general target.
cmake --preset release >build/configure-after-peers.log
if grep -q "bench_pinocchio enabled" build/configure-after-peers.log; then
  cmake --build --preset release --parallel "$jobs" --target bench_general
  build/bin/bench_general --benchmark_filter='^$'
else
  echo "test.sh: WARNING: no Pinocchio in build/venv (scripts/peers.sh could not install it): the spherical joints'" \
    "peer check (bench_general) and the Python package's Pinocchio tests were skipped" >&2
fi
echo "test.sh: Python stage done at ${SECONDS} s"

if [[ $quick -eq 1 ]]; then
  echo "test.sh: --quick given, ARM build, sanitizer build and fuzzer skipped"
  exit 0
fi

echo "==== ARM (aarch64) cross build, tests under qemu ===="
JOBS="$jobs" bash scripts/arm.sh
echo "test.sh: ARM stage done at ${SECONDS} s"

echo "==== sanitizer (ASan + UBSan) build and tests ===="
cmake --preset asan
cmake --build --preset asan --parallel "$jobs" --target spatial_test_programs
UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1} \
  ctest --test-dir build-asan --output-on-failure --no-tests=error -j "$jobs" -LE package
echo "test.sh: sanitizer stage done at ${SECONDS} s"

echo "==== fuzzing the URDF loader (30 s, ${jobs} processes) ===="
JOBS="$jobs" bash scripts/fuzz.sh 30

echo "test.sh: all tests passed (${SECONDS} s)"
