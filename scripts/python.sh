#!/usr/bin/env bash
# Builds the Python package (pyproject.toml, python/) and installs it into the virtual environment build/venv, the
# one scripts/peers.sh sets up for the report (Pinocchio's `pin`, matplotlib); with --test, then runs its pytest
# suite (python/tests; the checks against Pinocchio's Python API run when pin is in the venv, the checks against
# spatial-dyn when $SPATIAL_DYN or build/bin/spatial-dyn exists).
#   - The build tools (scikit-build-core, nanobind, numpy) and pytest come from PyPI into the venv; the package is
#     built without pip's build isolation, in build-python/ (kept, so that a second run rebuilds only what changed),
#     with $JOBS parallel jobs (default 2).
#   - Debian packages it needs (python3-dev for the headers, python3-venv, Eigen, urdfdom) come from scripts/deps.sh.
# Usage: scripts/python.sh [--test] [pytest arguments after --]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

run_tests=0
pytest_args=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --test) run_tests=1 ;;
    --) shift; pytest_args=("$@"); break ;;
    -h|--help) echo "usage: scripts/python.sh [--test] [-- pytest arguments]"; exit 0 ;;
    *) echo "python.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
  esac
  shift
done

venv=build/venv
if [[ ! -x "$venv/bin/python" ]]; then
  echo "python.sh: creating $venv"
  mkdir -p build
  python3 -m venv "$venv"
fi
py="$venv/bin/python"

need=()
"$py" -c "import scikit_build_core" >/dev/null 2>&1 || need+=("scikit-build-core>=0.10")
"$py" -c "import nanobind" >/dev/null 2>&1 || need+=("nanobind>=2.4")
"$py" -c "import numpy" >/dev/null 2>&1 || need+=("numpy>=2.0")
"$py" -c "import pytest" >/dev/null 2>&1 || need+=("pytest")
if [[ ${#need[@]} -gt 0 ]]; then
  echo "python.sh: pip install ${need[*]}"
  "$py" -m pip install --disable-pip-version-check --no-input --progress-bar off -q "${need[@]}"
fi

echo "python.sh: building and installing the package (pip install ., build-python/)"
start=$SECONDS
CMAKE_BUILD_PARALLEL_LEVEL=${JOBS:-2} "$py" -m pip install --disable-pip-version-check --no-input --progress-bar off \
  -q --no-build-isolation .
echo "python.sh: package installed in $((SECONDS - start)) s"

if [[ $run_tests -eq 1 ]]; then
  if [[ -z "${SPATIAL_DYN:-}" && -x build/bin/spatial-dyn ]]; then
    export SPATIAL_DYN="$PWD/build/bin/spatial-dyn"
  fi
  # From the tests' directory, so that `import spatial` is the installed package, not the source tree's python/.
  (cd python/tests && "$PWD/../../$py" -m pytest -q "${pytest_args[@]}" .)
fi
