#!/usr/bin/env bash
# Builds the URDF loader's fuzz target (tests/fuzz/fuzz_urdf.cpp) with clang, libFuzzer, ASan and UBSan in its own
# build directory, and runs it for a bounded time on the seed corpus (tests/fuzz/corpus, urdf/test, urdf/*.urdf).
# Leak detection is on; an input running longer than 10 s counts as a hang. A crash, sanitizer report, leak or hang
# fails the script; libFuzzer writes the input to build-fuzz/artifacts/. It fuzzes with $JOBS processes (default 2;
# libFuzzer's fork mode, which shares one corpus; timeouts and out-of-memory inputs fail the run there too).
# Usage: scripts/fuzz.sh [SECONDS]   (default 60, of wall time). Needs clang and Debian's libclang-rt-14-dev
# (scripts/deps.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

seconds=${1:-60}
if ! [[ "$seconds" =~ ^[0-9]+$ ]]; then
  echo "usage: scripts/fuzz.sh [SECONDS]" >&2
  exit 2
fi
out=build-fuzz
mkdir -p "$out/corpus" "$out/artifacts"

cxx=${FUZZ_CXX:-clang++}
flags=(-std=c++17 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
       -Wall -Wextra -Wpedantic -Iinclude -I/usr/include/eigen3)
libs=(-lurdfdom_model -lconsole_bridge -ltinyxml)
if [[ ! -x "$out/fuzz_urdf" || tests/fuzz/fuzz_urdf.cpp -nt "$out/fuzz_urdf" ||
      -n "$(find include -newer "$out/fuzz_urdf" -name '*.hpp' -print -quit)" ]]; then
  echo "fuzz.sh: building $out/fuzz_urdf"
  "$cxx" "${flags[@]}" tests/fuzz/fuzz_urdf.cpp -o "$out/fuzz_urdf" "${libs[@]}"
fi

# The seeds: valid and broken URDFs. The working corpus (first directory) collects what the fuzzer finds.
cp -f urdf/*.urdf "$out/corpus/"
jobs=${JOBS:-2}
if ! [[ "$jobs" =~ ^[1-9][0-9]*$ ]]; then
  echo "fuzz.sh: JOBS must be a positive integer (got '$jobs')" >&2
  exit 2
fi
fork=()
if [[ $jobs -gt 1 ]]; then
  fork=(-fork="$jobs" -ignore_timeouts=0 -ignore_ooms=0 -ignore_crashes=0)
fi
echo "fuzz.sh: running for ${seconds} s with ${jobs} process(es)"
ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1} \
UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1} \
  "$out/fuzz_urdf" "${fork[@]}" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=32768 \
    -dict=tests/fuzz/urdf.dict -artifact_prefix="$out/artifacts/" -print_final_stats=1 \
    "$out/corpus" tests/fuzz/corpus urdf/test
echo "fuzz.sh: no crash, leak or hang in ${seconds} s (${jobs} process(es))"
