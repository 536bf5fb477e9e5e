#!/usr/bin/env bash
# Installs every build, test and figure dependency of vehs from Debian packages.
# Safe to run any number of times: only missing packages are installed.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libsuitesparse-dev nlohmann-json3-dev catch2
  libcli11-dev libfast-float-dev libbenchmark-dev
  # Ceres Solver: maximum likelihood with automatic derivatives (likelihood area)
  libceres-dev
  # muParser: the expressions of user-defined terms (src/core/user_function.cpp)
  libmuparser-dev
  # MATLAB .mat measurement files (src/io/mat_reader.cpp)
  libmatio-dev
  gnuplot-nox chromium
  # scripts/simd_compare.py (the SIMD-width check of .ci/run; standard library only)
  python3
  # the Python package (python/): its virtual environment and the extension's headers
  python3-venv python3-dev
  # an optimised BLAS for UMFPACK's dense kernels (Debian's BLAS alternative: libsuitesparse
  # links libblas.so.3, which this package provides with priority over the reference BLAS;
  # the serial variant, because vehs parallelises over sweep points itself)
  libopenblas0-serial
  # the C++ API pages of the documentation site (scripts/docs.sh)
  doxygen
)
# bench/fuzz/run.sh: clang with libFuzzer and its OpenMP runtime (only when fuzzing)
if [ -n "${VEHS_WITH_FUZZ:-}" ]; then packages+=(clang libclang-rt-14-dev libomp-14-dev); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present" >&2
  exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done" >&2
