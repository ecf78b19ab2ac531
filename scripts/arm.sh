#!/usr/bin/env bash
# Cross-builds the portable unit tests for aarch64 (Debian's g++-aarch64-linux-gnu) and runs them under qemu-user, so
# that the library is tested as it runs on a robot's ARM computer: 64-bit ARM code, Eigen (and xsimd) on NEON.
#   build-arm/: CMake project tests/arm (toolchain cmake/aarch64-linux-gnu.cmake): spatial::spatial, the committed
#   HOAP-3 models, GoogleTest built from Debian's sources (/usr/src/googletest); ctest runs the test binary under
#   `qemu-aarch64 -L /usr/aarch64-linux-gnu` (CMAKE_CROSSCOMPILING_EMULATOR), in GoogleTest shards. A failing case
#   fails the script.
#
# What it covers (tests/arm/CMakeLists.txt, SPATIAL_ARM_TESTS): tests/arm/test_arm_target.cpp (the binary is aarch64
# with Eigen and xsimd on NEON) and tests/test_<name>.cpp for sincos, algebra, analytic, static_trees, derivatives,
# floating and batch: the algebra's identities, the analytic mechanisms, RNEA / CRBA / ABA / LTDL over random
# run-time trees of every joint type and over compile-time trees (static_trees), the floating base with the HOAP-3
# model, the analytical derivatives against finite differences, the sine/cosine kernel, and the batched algorithms
# on NEON lanes (batch.hpp: random run-time trees of every joint type, double and float; its compile-time HOAP-3
# cases are left to the x86 builds, tests/arm/CMakeLists.txt).
# What it leaves out:
#   - what needs urdfdom, KDL or the command-line tools, none of which exists for aarch64 here: the URDF loader's
#     tests, the CLI tests, the KDL cross-checks, test_models / test_names / test_io / test_reduce /
#     test_floating_urdf / test_scenes;
#   - the AVX2 kernel tests (simd_*.cpp: x86 only);
#   - for the time budget (the compiler, not qemu, is the cost: see below), the portable files whose code paths the
#     ones above already take on ARM — test_properties and test_contact (in the list at first: 41 and 56 CPU s,
#     both passed on aarch64), IK, walking, ZMP, centroidal, Jacobians, frame derivatives, H⁻¹, options,
#     sizes, iLQR, the compile-time HOAP-3 derivatives and chains (test_derivatives_hoap3*, test_static_chain66),
#     autodiff, and the no-allocation, debug-assertion and stress suites. Their aarch64 compile times (g++ 12, -O1,
#     CPU s): walking_closed_loop, derivatives_hoap3(_floating) and walking_whole_body ~250-310 each (x86: 50-85),
#     static_chain66 ~110, autodiff ~100, walking_simulation 32, walking 34, options 51, minv 31, ik 27, centroidal
#     24, ilqr 24, jacobians 19, sizes 16, zmp 10, frame_derivatives 10. All of them passed on aarch64 (2026-12-02, one
#     15-minute build). Add some with `cmake -S tests/arm -B build-arm -DSPATIAL_ARM_TESTS_EXTRA='zmp;ik'` (any
#     tests/test_<name>.cpp that does not load URDF).
# The sanitizer stage is not repeated for ARM: ASan and UBSan check the library's memory accesses and arithmetic,
# which are the same C++ on both architectures; what differs on ARM (code generation, NEON, floating-point
# contraction) is what this stage checks, by the tests' numbers.
#
# Measured (2026-12-02, 2 cores, JOBS=2, from an empty build-arm/, test_batch.cpp not there yet): 317 s user + 15 s
# sys, of which ~300 CPU s compiling (algebra 43, contact 56, static_trees 41, floating 41, properties 41,
# derivatives 21, analytic 10, sincos 2, GoogleTest 12) and ~28 CPU s in qemu (the four shards: 14 s wall). That is
# ~2.8 min of wall time on an idle 2-core machine; the measurement itself ran beside other builds (load 5) and took
# 7.5 min. Compile time is what counts: -O2 instead of -O1 compiles algebra, static_trees and analytic in 1.3-1.5×
# the CPU time and could save at most a part of the 28 s in qemu; -O1 is the lower total.
#
# Usage: scripts/arm.sh. JOBS (default 2) sets the parallelism of the build and of the tests. Needs the packages
# g++-aarch64-linux-gnu, qemu-user and libgtest-dev (scripts/deps.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

jobs=${JOBS:-2}
out=build-arm

for tool in aarch64-linux-gnu-g++ qemu-aarch64; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "arm.sh: $tool not found (scripts/deps.sh installs g++-aarch64-linux-gnu and qemu-user)" >&2
    exit 1
  fi
done

cmake -S tests/arm -B "$out" -G Ninja -DCMAKE_TOOLCHAIN_FILE="$PWD/cmake/aarch64-linux-gnu.cmake"
cmake --build "$out" --parallel "$jobs"
echo "arm.sh: aarch64 build done at ${SECONDS} s"
ctest --test-dir "$out" --output-on-failure --no-tests=error -j "$jobs"
echo "arm.sh: aarch64 tests passed under qemu (${SECONDS} s)"
