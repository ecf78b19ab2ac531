#!/usr/bin/env bash
# Installs the Debian packages that building, testing and benchmarking spatial need, and only those missing.
# Runs apt-get update only when something is missing. Uses sudo only when not already root.
# g++-aarch64-linux-gnu, libc6-dev-arm64-cross (the target's C library) and qemu-user are for scripts/arm.sh (the unit
# tests cross-built for aarch64 and run under qemu-aarch64; no binfmt registration needed).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

packages=(
  build-essential
  cmake
  ninja-build
  clang
  libclang-rt-14-dev
  python3
  python3-venv
  python3-dev
  libeigen3-dev
  liburdfdom-dev
  liborocos-kdl-dev
  libgtest-dev
  libbenchmark-dev
  libxsimd-dev
  g++-aarch64-linux-gnu
  libc6-dev-arm64-cross
  qemu-user
)

missing=()
for package in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$package" 2>/dev/null || true)
  if [[ "$status" != *" ok installed" ]]; then
    missing+=("$package")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "deps.sh: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "deps.sh: installing ${missing[*]}"
as_root=()
if [[ $(id -u) -ne 0 ]]; then
  if ! command -v sudo >/dev/null 2>&1; then
    echo "deps.sh: not root and sudo is not available; install these packages first: ${missing[*]}" >&2
    exit 1
  fi
  as_root=(sudo)
fi

export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update -q
"${as_root[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
