# Toolchain file: cross-compile for 64-bit ARM Linux (aarch64) with Debian's cross compiler, and run what is built
# under qemu-user. Debian bookworm packages: g++-aarch64-linux-gnu (which brings libc6-dev-arm64-cross, the target's
# C library in /usr/aarch64-linux-gnu) and qemu-user (qemu-aarch64); scripts/deps.sh installs both.
#
#   cmake -S tests/arm -B build-arm -G Ninja -DCMAKE_TOOLCHAIN_FILE=$PWD/cmake/aarch64-linux-gnu.cmake  (scripts/arm.sh)
#
# Header-only dependencies (Eigen, xsimd) come from the host's /usr/include, which Debian's cross compiler searches
# after its own /usr/aarch64-linux-gnu/include: they contain no compiled code, so nothing of the host's architecture
# is linked. Compiled libraries must be aarch64 ones: CMAKE_LIBRARY_ARCHITECTURE makes find_package and find_library
# look in /usr/lib/aarch64-linux-gnu (Debian multiarch), never in the host's /usr/lib/x86_64-linux-gnu, so e.g. the
# host's libgtest.a and its GTestConfig.cmake are not picked up by mistake; arch-independent package configs
# (/usr/share/eigen3/cmake) are still found.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)

# Programs (ninja, python, ...) are the host's; libraries and headers found by find_library/find_path come from the
# target's root first, then from the host's /usr (see above for why that is safe for header-only packages).
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)

# ctest, gtest_discover_tests and try_run run aarch64 executables through qemu-user, with the target's dynamic
# loader and libraries (libstdc++, libm, libc) from /usr/aarch64-linux-gnu.
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /usr/aarch64-linux-gnu)
