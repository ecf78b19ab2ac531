#!/usr/bin/env bash
# The main job: the benchmark report, from a fresh clone on a fresh Debian bookworm machine.
#   1. Debian packages (scripts/deps.sh), then the optional peers and tools in build/venv (scripts/peers.sh:
#      Pinocchio from PyPI's `pin`, matplotlib; the run goes on without them if pip fails).
#   2. Release builds with g++ (preset "release", build/) and then with clang++ (preset "clang-release",
#      build-clang/): the first compiler builds every benchmark binary and the error study; the others only the
#      binaries of the cross-compiler comparisons ($COMPARED_BENCHES: every algorithm against Pinocchio and KDL,
#      the floating base, the error study), not the cost-growth, scene-option and walking benchmarks, whose
#      unrolled trees cost ~3 CPU minutes per compiler and which no target asks of a second compiler. Tests are
#      not built here (scripts/test.sh does that).
#   3. Runs the benchmark binaries of each build (Google Benchmark, repetitions with medians) and the error study,
#      writing JSON to build/report/raw/<compiler>/. The repetitions of a binary's benchmarks run in random order,
#      interleaved (--benchmark_enable_random_interleaving): on a shared host whose speed changes for seconds at a
#      time, a benchmark's five repetitions then fall in different periods instead of one (over four runs of
#      bench_batch, a median's largest ÷ smallest value was 1.16 on average and up to 1.66 in order, 1.05 and up to
#      1.10 interleaved: the commit that made it the default says how it was measured). Among them (first compiler
#      only, not in $COMPARED_BENCHES) bench_batch, the batched algorithms of issue 15 on 1 and all cores; Pinocchio's
#      batch API runs inside bench_pinocchio where the compiler has OpenMP (g++; clang without libomp-dev skips that
#      part).
#   4. The reference study's scenes: `spatial-dyn scene all` (first compiler's build) into build/report/scenes/,
#      plotted by tools/plot_scenes.py (skipped without matplotlib).
#   5. The iLQR example of the derivatives (`spatial-ilqr`, first compiler's build) into build/report/ilqr/, plotted
#      by tools/plot_ilqr.py (skipped without matplotlib).
#   6. The closed-loop walk of the HOAP-3 (`spatial-dyn walk`, first compiler's build), four variants: build/report/
#      walk (8 steps straight), walk_turn (--turn 0.15), walk_no_second_stage (--second-stage 0) and walk_pendulum
#      (--zmp-model double-pendulum); spatial-dyn plots each by tools/plot_walk.py with $SPATIAL_PYTHON (set here
#      to build/venv's python when it has matplotlib). A variant that fails is reported and does not stop the run.
#   7. The Python package (scripts/python.sh: built into build/venv), its example (tools/python_torque_map.py: the
#      stance leg's gravity-torque map against the motor limits) and its benchmark (bench/python_bench.py: overhead
#      of one call, batches on one and all cores, against Pinocchio's Python API), into build/report/python/.
#   8. tools/report.py: build/report/report.md, summary.json and the PNG charts; prints the headline table.
#
# Extra arguments are passed to every benchmark binary, e.g.  scripts/main.sh --benchmark_filter=stance21
# Environment: JOBS (build parallelism, default 2), REPETITIONS (default 5), MIN_TIME (seconds per repetition, default
# 0.05), INTERLEAVE (default 1; 0: each benchmark's repetitions one after another), COMPILERS (default "gcc clang"),
# COMPARED_BENCHES (what the compilers after the first build and run; default "bench_algorithms bench_floating
# bench_kdl bench_pinocchio error_study"; "all": every binary), SKIP_PEERS=1 (no Pinocchio, no charts; build/venv then
# holds only the Python package and its build tools).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

start=$(date +%s)
jobs=${JOBS:-2}
repetitions=${REPETITIONS:-5}
min_time=${MIN_TIME:-0.05}
interleave=true
[[ "${INTERLEAVE:-1}" == 0 ]] && interleave=false
compilers=${COMPILERS:-gcc clang}
compared_benches=${COMPARED_BENCHES:-bench_algorithms bench_floating bench_kdl bench_pinocchio error_study}
report_dir=build/report
raw_dir=$report_dir/raw

stage() { echo; echo "==== [$(( $(date +%s) - start )) s] $* ===="; }
# Whether $compiler builds and runs every benchmark binary (the first compiler does), or the binary $1: the
# compilers after the first, those of $compared_benches.
compares_all() { [[ "$compiler" == "$first_compiler" || "$compared_benches" == all ]]; }
compares() { compares_all || [[ " $compared_benches " == *" $1 "* ]]; }

stage "dependencies"
bash scripts/deps.sh
if [[ "${SKIP_PEERS:-0}" != 1 ]]; then
  bash scripts/peers.sh || echo "main.sh: peers.sh failed; going on without Pinocchio and charts" >&2
fi

rm -rf "$raw_dir"
mkdir -p "$raw_dir"

# One compiler's build after the other, each with $jobs jobs. Run together (four compilers on two cores, each
# instantiating unrolled trees in several GB), they slowed each other down by more than the share of a core:
# tools/spatial_dyn.cpp took 323 s there against 100 s in a build of its own with two jobs. Each build
# starts with the longest sources (bench_pinocchio's three parts; bench/CMakeLists.txt orders the targets so), so that
# no long one ends a build alone on one core. The first compiler's build also makes spatial-dyn and spatial-ilqr,
# which the scenes, the iLQR example and the walks need. Logs: build/report/raw/build-<compiler>.log.
first_compiler=${compilers%% *}
for compiler in $compilers; do
  case "$compiler" in
    gcc) preset=release; build_dir=build ;;
    clang) preset=clang-release; build_dir=build-clang ;;
    *) echo "main.sh: unknown compiler '$compiler' (gcc or clang)" >&2; exit 2 ;;
  esac
  stage "$compiler: configure ($preset, $build_dir)"
  cmake --preset "$preset" >"$raw_dir/configure-$compiler.log" 2>&1 || { cat "$raw_dir/configure-$compiler.log"; exit 1; }
  grep -E "spatial:" "$raw_dir/configure-$compiler.log" || true
  if compares_all; then
    targets=(spatial_benchmarks)
  else
    # bench_pinocchio is a target only when Pinocchio was found
    targets=()
    for b in $compared_benches; do
      [[ $b == bench_pinocchio ]] && ! grep -q "bench_pinocchio enabled" "$raw_dir/configure-$compiler.log" && continue
      targets+=("$b")
    done
  fi
  [[ "$compiler" == "$first_compiler" ]] && targets+=(spatial-dyn spatial-ilqr)
  stage "$compiler: build (log in $raw_dir/build-$compiler.log)"
  if ! cmake --build --preset "$preset" --target "${targets[@]}" --parallel "$jobs" >"$raw_dir/build-$compiler.log" 2>&1; then
    tail -n 60 "$raw_dir/build-$compiler.log"
    echo "main.sh: the $compiler build failed (whole log: $raw_dir/build-$compiler.log)" >&2
    exit 1
  fi
done

for compiler in $compilers; do
  case "$compiler" in
    gcc) build_dir=build ;;
    clang) build_dir=build-clang ;;
  esac
  out="$raw_dir/$compiler"
  mkdir -p "$out"
  shopt -s nullglob
  benches=("$build_dir"/bin/bench_*)
  shopt -u nullglob
  # only what this run built (an earlier run may have left other binaries in $build_dir/bin)
  kept=()
  for bench in "${benches[@]}"; do
    compares "$(basename "$bench")" && kept+=("$bench")
  done
  benches=("${kept[@]}")
  if [[ ${#benches[@]} -eq 0 ]]; then
    echo "main.sh: no benchmark executables in $build_dir/bin" >&2
    exit 1
  fi
  for bench in "${benches[@]}"; do
    [[ -f "$bench" && -x "$bench" ]] || continue
    name=$(basename "$bench")
    stage "$compiler: $name"
    "$bench" --benchmark_min_time="$min_time" --benchmark_repetitions="$repetitions" \
      --benchmark_enable_random_interleaving="$interleave" \
      --benchmark_report_aggregates_only=true \
      --benchmark_out="$out/$name.json" --benchmark_out_format=json "$@" >"$out/$name.txt" 2>&1 ||
      { cat "$out/$name.txt"; echo "main.sh: $name failed" >&2; exit 1; }
    grep -E "peer check" "$out/$name.txt" | sed 's/^/  /' || true
    echo "  $(grep -c '_median' "$out/$name.txt" || true) benchmarks -> $out/$name.json"
  done
  if compares error_study; then
    stage "$compiler: error study"
    "$build_dir/bin/error_study" "$out/error_study.json"
  fi
done

python=python3
if [[ -x build/venv/bin/python ]] && build/venv/bin/python -c "import matplotlib" >/dev/null 2>&1; then
  python=build/venv/bin/python
fi

scene_build=build
[[ "$first_compiler" == clang ]] && scene_build=build-clang
stage "scenes (spatial-dyn scene all, $scene_build)"
cmake --build "$scene_build" --target spatial-dyn --parallel "$jobs"
rm -rf "$report_dir/scenes"
"$scene_build/bin/spatial-dyn" scene all --out "$report_dir/scenes"
"$python" tools/plot_scenes.py "$report_dir/scenes"

stage "iLQR example (spatial-ilqr, $scene_build)"
rm -rf "$report_dir/ilqr"
"$scene_build/bin/spatial-ilqr" --out "$report_dir/ilqr"
"$python" tools/plot_ilqr.py "$report_dir/ilqr"

stage "walking (spatial-dyn walk, $scene_build)"
# spatial-dyn runs tools/plot_walk.py with $SPATIAL_PYTHON (default python3): the venv's, when it has matplotlib.
if [[ "$python" != python3 ]]; then
  export SPATIAL_PYTHON="$PWD/$python"
fi
run_walk() {
  local name=$1
  shift
  rm -rf "${report_dir:?}/$name"
  "$scene_build/bin/spatial-dyn" walk --out "$report_dir/$name" "$@" ||
    echo "main.sh: spatial-dyn walk --out $report_dir/$name $* failed; going on" >&2
}
run_walk walk
run_walk walk_turn --turn 0.15
run_walk walk_no_second_stage --second-stage 0
run_walk walk_pendulum --zmp-model double-pendulum
run_walk walk_public --length 0.087 --period 1.28 --double-support 0.05 --com-height 0.275

stage "Python package (scripts/python.sh), its example and benchmark"
bash scripts/python.sh
rm -rf "$report_dir/python"
if build/venv/bin/python -c "import matplotlib" >/dev/null 2>&1; then
  build/venv/bin/python tools/python_torque_map.py --out "$report_dir/python"
else
  echo "main.sh: no matplotlib in build/venv (SKIP_PEERS?): the torque map is skipped"
fi
build/venv/bin/python bench/python_bench.py --out "$report_dir/python"

stage "report"
"$python" tools/report.py --input "$raw_dir" --output "$report_dir"

echo
echo "main.sh: done in $(( $(date +%s) - start )) s; report in $report_dir/report.md"
