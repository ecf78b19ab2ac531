#!/usr/bin/env bash
# Instruction counts per call of every scene option (bench/callgrind_scenes.cpp) against the full computation, on
# the 21-DoF HOAP-3 stance model, under valgrind's callgrind. Valgrind does not decode AVX-512, so the driver is
# built with -O3 -march=x86-64-v3 (AVX2, FMA) instead of -march=native.
#
#   bash scripts/callgrind.sh [REPS] [CXX]       # default 2000 calls per option, g++
#
# Prints a Markdown table: option, tree, instructions per call, full computation's, ratio. Work files go to
# build/callgrind/.
set -euo pipefail
cd "$(dirname "$0")/.."
REPS=${1:-2000}
CXX=${2:-g++}
OUT=build/callgrind
mkdir -p "$OUT/include/spatial"
command -v valgrind >/dev/null || { echo "callgrind.sh: valgrind is not installed (apt-get install valgrind)" >&2; exit 1; }
# The generated models: the build's copy when there is one, else the committed copy.
if [ -d build/src/models/include/spatial/models ]; then
  MODELS=$(pwd)/build/src/models/include/spatial/models
else
  MODELS=$(pwd)/src/models
fi
ln -sfn "$MODELS" "$OUT/include/spatial/models"
# Eigen as a system header: its AVX code has warnings of its own under -march=x86-64-v3.
EIGEN_INC=$(pkg-config --cflags-only-I eigen3 2>/dev/null || echo -I/usr/include/eigen3)
EIGEN_INC=${EIGEN_INC//-I/-isystem }
FLAGS="-std=c++17 -O3 -march=x86-64-v3 -DNDEBUG -g"
echo "building $OUT/callgrind_scenes with $CXX $FLAGS" >&2
# shellcheck disable=SC2086
"$CXX" $FLAGS -Wall -Wextra -Wpedantic -Iinclude -I"$OUT/include" -Ibench -Itests $EIGEN_INC bench/callgrind_scenes.cpp \
  -o "$OUT/callgrind_scenes"
rm -f "$OUT"/callgrind.out.*
valgrind --tool=callgrind --callgrind-out-file="$OUT/callgrind.out.scenes" "$OUT/callgrind_scenes" "$REPS" \
  >/dev/null 2>"$OUT/valgrind.log"
callgrind_annotate --inclusive=yes --threshold=100 "$OUT/callgrind.out.scenes" >"$OUT/annotate.txt"
python3 - "$OUT/annotate.txt" "$REPS" "$CXX $FLAGS" <<'EOF'
import re, sys
path, reps, flags = sys.argv[1], int(sys.argv[2]), sys.argv[3]
counts = {}
for line in open(path):
    m = re.match(r"\s*([\d,]+)\s.*\bscene_(\w+?)_(static|runtime)\b", line)
    if m:
        counts[(m.group(2), m.group(3))] = int(m.group(1).replace(",", "")) / reps
print(f"Instructions per call (callgrind, {reps} calls per option, {flags}); ratio = option / full computation.\n")
print("| option | tree | instructions/call | full computation | ratio |")
print("|---|---|---:|---:|---:|")
ALGOS = ["RNEA", "ABA", "FD_CRBA", "CRBA"]
def split(name):
    algo = "FD_CRBA" if name.startswith("FD_CRBA_") else name.split("_", 1)[0]
    return algo, name[len(algo) + 1:]
def order(item):
    (name, tree), n = item
    algo, variant = split(name)
    return (tree != "static", ALGOS.index(algo) if algo in ALGOS else 9, variant != "Full", -n)
for (name, tree), n in sorted(counts.items(), key=order):
    algo, variant = split(name)
    full = counts.get((f"{algo}_Full", tree))
    full_s = f"{full:,.0f}" if full else "-"
    ratio = f"{n / full:.3f}" if full else "-"
    print(f"| {algo}.{variant} | {tree} | {n:,.0f} | {full_s} | {ratio} |")
EOF
