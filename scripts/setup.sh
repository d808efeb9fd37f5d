#!/usr/bin/env bash
# Installs what Canopy needs on Debian (only the missing apt packages), then
# configures and builds it.
#
#   scripts/setup.sh [build-dir]          what the main job runs: the library, the
#                                         ParaView plugin and the mini-app (README's
#                                         first command)
#   scripts/setup.sh --tests [build-dir]  also what the tests need: every test and
#                                         benchmark, and a sanitizer build next to it
#                                         ([build-dir]-asan) whose tests the sanitizers.*
#                                         tests run (README's second command)
#
# Both use the same build folder: after the first, the second builds only the rest.
# With --tests the build treats a compiler warning in Canopy's code as an error.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
tests=0
if [ "${1:-}" = "--tests" ]; then
  tests=1
  shift
fi
build="${1:-$here/build}"

# The main job: ParaView 5.11 and what its CMake config needs, MPI, a virtual display.
packages=(
  cmake g++ make pkg-config
  paraview-dev python3-paraview libopenmpi-dev openmpi-bin
  xvfb xauth x11-utils libgl1-mesa-dri
  libfreetype-dev libglew-dev libx11-dev libxt-dev libxml2-dev libnetcdf-dev
  libhdf5-openmpi-dev libboost-dev liblz4-dev libdouble-conversion-dev libutfcpp-dev
  libexpat1-dev liblzma-dev libpng-dev libjpeg-dev libtiff-dev zlib1g-dev libgl-dev
)
if ((tests)); then
  # The tests: GoogleTest, Google Benchmark, Fortran (the Fortran binding's test),
  # p4est (Canopy::p4est and its example), deal.II (Canopy::dealii, its example and
  # benchmark; ~240 packages, ~1.5 GB with PETSc and Trilinos, about 50 s here, so
  # not for the main job), h5py and friends (the checkers), valgrind, clang-14 (the
  # fuzzers).
  packages+=(
    gfortran libgtest-dev libbenchmark-dev libp4est-dev libdeal.ii-dev
    python3-h5py python3-matplotlib python3-pandas valgrind
    clang-14 libclang-rt-14-dev
  )
fi
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

if ((!tests)); then
  # Tests off only where the folder has none configured yet: a folder set up for
  # the tests stays so.
  cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release \
    "-DCANOPY_BUILD_TESTS=$( [ -f "$build/CTestTestfile.cmake" ] && echo ON || echo OFF)" \
    "-DCANOPY_BUILD_BENCHMARKS=$( [ -f "$build/CTestTestfile.cmake" ] && echo ON || echo OFF)"
  cmake --build "$build" -j "$(nproc)" --target canopy_miniamr CanopyPlugin
  exit 0
fi

cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release -DCANOPY_BUILD_TESTS=ON \
  -DCANOPY_BUILD_BENCHMARKS=ON -DCANOPY_WERROR=ON
cmake --build "$build" -j "$(nproc)"

# The same sources with AddressSanitizer + UBSan, next to the main build: its
# sanitizers.* tests run this build's unit, in-situ and mini-app tests
# (docs/testing.md). CANOPY_SKIP_SANITIZER_BUILD=1 skips it (those tests then fail
# saying so).
if [ "${CANOPY_SKIP_SANITIZER_BUILD:-0}" != 1 ]; then
  cmake -S "$here" -B "$build-asan" -DCMAKE_BUILD_TYPE=Release \
    "-DCANOPY_SANITIZE=address;undefined" -DCANOPY_BUILD_BENCHMARKS=OFF -DCANOPY_WERROR=ON
  cmake --build "$build-asan" --target canopy_sanitizer_tests -j "$(nproc)"
fi
