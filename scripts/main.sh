#!/usr/bin/env bash
# Builds the release preset and runs every benchmark, writing one JSON report per benchmark binary to
# build/report/<name>.json. Extra arguments are passed to every benchmark binary, e.g.
#   scripts/main.sh --benchmark_filter=RNEA
# JOBS (default 2) sets the build parallelism.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

jobs=${JOBS:-2}
report_dir=build/report

bash scripts/deps.sh

cmake --preset release
cmake --build --preset release --parallel "$jobs"

mkdir -p "$report_dir"

shopt -s nullglob
benches=()
for candidate in build/bin/bench_*; do
  if [[ -f "$candidate" && -x "$candidate" ]]; then
    benches+=("$candidate")
  fi
done
if [[ ${#benches[@]} -eq 0 ]]; then
  echo "main.sh: no benchmark executables in build/bin" >&2
  exit 1
fi

for bench in "${benches[@]}"; do
  name=$(basename "$bench")
  echo "==== $name ===="
  "$bench" --benchmark_min_time=0.2 \
    --benchmark_out="$report_dir/$name.json" --benchmark_out_format=json "$@"
done

echo "main.sh: reports written to $report_dir/"
