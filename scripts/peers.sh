#!/usr/bin/env bash
# Sets up the optional peers and tools of the benchmark report in a Python virtual environment, build/venv:
#   - pin (Pinocchio from PyPI, pinned to the version the report was developed with): its C++ headers and CMake
#     package come with it, under build/venv/lib/python3.*/site-packages/cmeel.prefix, with cmeel-boost's headers;
#   - cmeel-eigen, the Eigen that pin is built against (a build-time dependency of pin, so pip does not install it
#     with pin): bench_pinocchio compiles against it and never against Debian's Eigen;
#   - matplotlib, for the charts of tools/report.py.
# Idempotent: packages already importable in the venv are not installed again. Never fatal: when the venv or a
# package cannot be installed it says so and exits 0, and the report goes on without Pinocchio or without charts.
# Usage: scripts/peers.sh [--no-pinocchio]
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

venv=build/venv
want_pin=1
for arg in "$@"; do
  case "$arg" in
    --no-pinocchio) want_pin=0 ;;
    -h|--help) echo "usage: scripts/peers.sh [--no-pinocchio]"; exit 0 ;;
    *) echo "peers.sh: unknown argument '$arg' (try --help)" >&2; exit 2 ;;
  esac
done

# python3 -m venv needs Debian's python3-venv (ensurepip); install it the way scripts/deps.sh installs packages.
if ! python3 -c 'import ensurepip, venv' >/dev/null 2>&1; then
  status=$(dpkg-query -W -f='${Status}' python3-venv 2>/dev/null || true)
  if [[ "$status" != *" ok installed" ]]; then
    echo "peers.sh: installing python3-venv"
    as_root=()
    if [[ $(id -u) -ne 0 ]]; then as_root=(sudo); fi
    export DEBIAN_FRONTEND=noninteractive
    "${as_root[@]}" apt-get update -q && "${as_root[@]}" apt-get install -y -q --no-install-recommends python3-venv ||
      echo "peers.sh: could not install python3-venv" >&2
  fi
fi

if [[ ! -x "$venv/bin/python" ]]; then
  echo "peers.sh: creating $venv"
  mkdir -p build
  if ! python3 -m venv "$venv"; then
    echo "peers.sh: could not create $venv; going on without Pinocchio and matplotlib" >&2
    rm -rf "$venv"
    exit 0
  fi
fi
py="$venv/bin/python"

pip_install() {  # pip_install <import name> <pip requirement>
  if "$py" -c "import $1" >/dev/null 2>&1; then
    echo "peers.sh: $2 already installed"
    return 0
  fi
  echo "peers.sh: pip install $2"
  if ! "$py" -m pip install --disable-pip-version-check --no-input --progress-bar off -q "$2"; then
    echo "peers.sh: pip install $2 failed; going on without it" >&2
    return 1
  fi
}

pip_install matplotlib matplotlib || true
prefix=
if [[ $want_pin -eq 1 ]]; then
  pip_install pinocchio "pin==4.1.0" || true
  prefix=$(ls -d "$venv"/lib/python3*/site-packages/cmeel.prefix 2>/dev/null | head -n1 || true)
  if [[ -n "$prefix" && ! -f "$prefix/include/eigen3/Eigen/Core" ]]; then
    echo "peers.sh: pip install cmeel-eigen==3.4.1"
    "$py" -m pip install --disable-pip-version-check --no-input --progress-bar off -q "cmeel-eigen==3.4.1" ||
      echo "peers.sh: pip install cmeel-eigen failed; the Pinocchio benchmark will be skipped" >&2
  fi
fi

if [[ -n "$prefix" && -f "$prefix/include/pinocchio/config.hpp" && -f "$prefix/include/eigen3/Eigen/Core" ]]; then
  echo "peers.sh: Pinocchio's headers (and its Eigen) are in $prefix/include"
else
  echo "peers.sh: Pinocchio is absent; the report will say so"
fi
exit 0
