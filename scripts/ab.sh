#!/usr/bin/env bash
# Old against new headers in ONE process: a Google Benchmark source is compiled twice, once against the headers of
# an older revision and once against the working tree's, and the two objects are linked into one binary whose
# benchmarks run interleaved in random order (--benchmark_enable_random_interleaving). On a shared host whose speed
# changes for seconds at a time, two binaries run one after the other disagree by more than the change being
# measured; here every old repetition has new ones just before and after it.
#
#   bash scripts/ab.sh [--cxx CXX] [--reps N] OLD_REV SOURCE [extra benchmark arguments]
#   e.g.  bash scripts/ab.sh HEAD bench/crba_ab.cpp          # uncommitted changes against the last commit
#         bash scripts/ab.sh --cxx clang++ --reps 60 HEAD~3 bench/crba_ab.cpp
#
# How the two builds coexist: the old object is compiled with -Dspatial=spatial_old (every use of the namespace is
# renamed; #include <spatial/...> lines are not macro-expanded, so the old headers are still found) and
# -DAB_TAG='"old/"', the new one with -DAB_TAG='"new/"'. SOURCE includes bench/ab.hpp, names its benchmarks
# AB_TAG "name", keeps its own functions in an anonymous namespace and defines no main (bench/crba_ab.cpp,
# minv_ab.cpp, derivatives_ab.cpp and jacobian_ab.cpp are such sources). The old revision's include/ and
# src/models/ (the committed copies of the generated models) come from `git archive`; the new build takes the
# working tree's include/ and the build's generated models (build/src/models/include, else src/models).
# Flags: -std=c++17 -O3 -march=native -DNDEBUG, as the benchmarks, and -g (line tables for perf: `perf record -e
# cpu-clock build/ab/<source>-<compiler> --benchmark_filter=...`, then `perf report --sort srcline`). Work files in
# build/ab/.
#
# Prints, per benchmark: old and new CPU time per iteration over N repetitions (default 40), minimum and median, and
# new ÷ old of each. The minimum is the least disturbed repetition; quote both.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

cxx=g++
reps=40
while [[ $# -gt 0 ]]; do
  case "$1" in
    --cxx) cxx=$2; shift 2 ;;
    --reps) reps=$2; shift 2 ;;
    -h|--help) awk 'NR > 1 && /^#/ { print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    *) break ;;
  esac
done
[[ $# -ge 2 ]] || { echo "usage: scripts/ab.sh [--cxx CXX] [--reps N] OLD_REV SOURCE [benchmark args]" >&2; exit 2; }
rev=$1
src=$2
shift 2
[[ -f "$src" ]] || { echo "ab.sh: no file '$src'" >&2; exit 2; }
git rev-parse --verify --quiet "$rev^{commit}" >/dev/null || { echo "ab.sh: '$rev' is not a revision" >&2; exit 2; }

out=build/ab
old=$out/old-$(git rev-parse --short "$rev")
mkdir -p "$out"
if [[ ! -d "$old" ]]; then
  rm -rf "$old.tmp"
  mkdir -p "$old.tmp"
  git archive "$rev" include src/models | tar -x -C "$old.tmp"
  mv "$old.tmp" "$old"
fi
mkdir -p "$old/models/spatial"
ln -sfn "$(pwd)/$old/src/models" "$old/models/spatial/models"
if [[ -d build/src/models/include/spatial/models ]]; then
  new_models=build/src/models/include
else
  mkdir -p "$out/new-models/spatial"
  ln -sfn "$(pwd)/src/models" "$out/new-models/spatial/models"
  new_models=$out/new-models
fi
eigen=$(pkg-config --cflags-only-I eigen3 2>/dev/null || echo -I/usr/include/eigen3)
eigen=${eigen//-I/-isystem }
flags=(-std=c++17 -O3 -march=native -DNDEBUG -g -Wall -Wextra -Wpedantic)
name=$(basename "$src" .cpp)-$(basename "$cxx")
echo "ab.sh: building $out/$name (old: $rev = $(git rev-parse --short "$rev"), new: working tree; $cxx)" >&2
# shellcheck disable=SC2086
"$cxx" "${flags[@]}" -Dspatial=spatial_old '-DAB_TAG="old/"' -I"$old/include" -I"$old/models" -Ibench -Itests \
  $eigen -c "$src" -o "$out/$name-old.o" &
old_pid=$!
# shellcheck disable=SC2086
"$cxx" "${flags[@]}" '-DAB_TAG="new/"' -Iinclude -I"$new_models" -Ibench -Itests $eigen -c "$src" -o "$out/$name-new.o" &
new_pid=$!
wait "$old_pid" && wait "$new_pid"
"$cxx" "$out/$name-old.o" "$out/$name-new.o" -o "$out/$name" -lbenchmark_main -lbenchmark -pthread

"$out/$name" --benchmark_min_time=0.05 --benchmark_repetitions="$reps" --benchmark_enable_random_interleaving=true \
  --benchmark_out="$out/$name.json" --benchmark_out_format=json "$@" >/dev/null
python3 - "$out/$name.json" "$rev" "$cxx" <<'EOF'
import collections, json, statistics, sys
path, rev, cxx = sys.argv[1:4]
runs = collections.defaultdict(list)
for b in json.load(open(path))["benchmarks"]:
    if b.get("run_type") == "iteration":
        runs[b["run_name"]].append(b["cpu_time"])
names = sorted({k.split("/", 1)[1] for k in runs if "/" in k})
print(f"CPU time per iteration ({cxx}; old: {rev}, new: working tree; {len(next(iter(runs.values())))} interleaved repetitions)\n")
print("| benchmark | old min | new min | new ÷ old (min) | old median | new median | new ÷ old (median) |")
print("|---|---:|---:|---:|---:|---:|---:|")
for n in names:
    o, w = runs.get("old/" + n), runs.get("new/" + n)
    if not o or not w:
        continue
    mo, mw, do, dw = min(o), min(w), statistics.median(o), statistics.median(w)
    print(f"| {n} | {mo:.1f} | {mw:.1f} | {mw / mo:.3f} | {do:.1f} | {dw:.1f} | {dw / do:.3f} |")
EOF
