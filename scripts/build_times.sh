#!/usr/bin/env bash
# Where a build's compile time goes, from Ninja's own records. Measures nothing new unless asked to.
#   scripts/build_times.sh BUILD_DIR [N]
#       the N (default 15) longest jobs of BUILD_DIR's last build (.ninja_log: each output's latest entry, wall
#       seconds) and their sum over every job: the figures quoted for the test builds in tests/CMakeLists.txt and
#       scripts/test.sh (on two cores, a job's wall time is its CPU time when nothing else runs beside the build).
#   scripts/build_times.sh --inline BUILD_DIR OBJECT
#       compiles one object of BUILD_DIR twice with its own command (`ninja -t commands`), into a scratch file:
#       as built (the test programs define SPATIAL_NO_FORCED_INLINE) and with -USPATIAL_NO_FORCED_INLINE appended
#       (the forced inlining users compile), and prints the user CPU seconds of each. OBJECT as Ninja names it, e.g.
#       tests/CMakeFiles/spatial_simd_tests.dir/simd_crba.cpp.o.
set -euo pipefail

if [[ "${1:-}" == "--inline" ]]; then
  [[ $# -eq 3 ]] || { echo "usage: scripts/build_times.sh --inline BUILD_DIR OBJECT" >&2; exit 2; }
  dir=$2 obj=$3
  cmd=$(ninja -C "$dir" -t commands "$obj" | tail -n 1)
  [[ "$cmd" == *" -o $obj "* ]] || { echo "build_times.sh: no compile command for '$obj' in $dir" >&2; exit 2; }
  scratch=$(mktemp -d)
  trap 'rm -rf "$scratch"' EXIT
  cmd=${cmd/ -o $obj / -o $scratch/out.o }
  cmd=${cmd/ -MF $obj.d / -MF $scratch/out.d }
  for variant in "as built" "forced inlining"; do
    extra=""
    [[ "$variant" == "forced inlining" ]] && extra=" -USPATIAL_NO_FORCED_INLINE"
    /usr/bin/time -f "%U" -o "$scratch/time" bash -c "cd '$dir' && $cmd$extra"
    echo "$obj, $variant: $(cat "$scratch/time") CPU-s (user)"
  done
  exit 0
fi

[[ $# -ge 1 && $# -le 2 ]] || { echo "usage: scripts/build_times.sh BUILD_DIR [N] | --inline BUILD_DIR OBJECT" >&2; exit 2; }
log="$1/.ninja_log"
[[ -f "$log" ]] || { echo "build_times.sh: no $log (build with Ninja first)" >&2; exit 2; }
awk -v n="${2:-15}" -F'\t' '
  !/^#/ && NF >= 4 { t[$4] = ($2 - $1) / 1000 }
  END {
    for (k in t) { s += t[k]; print t[k] "\t" k | "sort -rn | head -n " n }
    close("sort -rn | head -n " n)
    printf "sum of every job: %.0f s\n", s
  }' "$log"
