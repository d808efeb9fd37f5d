#!/usr/bin/env bash
# Installs what Canopy needs on Debian (only the missing apt packages), then
# configures and builds it, and a sanitizer build next to it ([build-dir]-asan).
# Usage: scripts/setup.sh [build-dir]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$here/build}"

packages=(
  cmake g++ gfortran make pkg-config
  paraview-dev python3-paraview libopenmpi-dev openmpi-bin
  xvfb xauth x11-utils libgl1-mesa-dri libgtest-dev libbenchmark-dev
  libfreetype-dev libglew-dev libx11-dev libxt-dev libxml2-dev libnetcdf-dev
  libhdf5-openmpi-dev libboost-dev liblz4-dev libdouble-conversion-dev libutfcpp-dev
  libexpat1-dev liblzma-dev libpng-dev libjpeg-dev libtiff-dev zlib1g-dev libgl-dev
  libp4est-dev python3-h5py python3-matplotlib python3-pandas valgrind
  clang-14 libclang-rt-14-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "canopy setup: installing ${#missing[@]} missing packages: ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" -j "$(nproc)"

# The same sources with AddressSanitizer + UBSan, next to the main build: its
# sanitizers.* tests run this build's unit, in-situ and mini-app tests
# (docs/testing.md). CANOPY_SKIP_SANITIZER_BUILD=1 skips it (those tests then fail
# saying so).
if [ "${CANOPY_SKIP_SANITIZER_BUILD:-0}" != 1 ]; then
  cmake -S "$here" -B "$build-asan" -DCMAKE_BUILD_TYPE=Release \
    "-DCANOPY_SANITIZE=address;undefined" -DCANOPY_BUILD_BENCHMARKS=OFF
  cmake --build "$build-asan" --target canopy_sanitizer_tests -j "$(nproc)"
fi
