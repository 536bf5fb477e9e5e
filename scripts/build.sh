#!/usr/bin/env bash
# Installs missing dependencies (Debian packages) and builds vehs in ./build (Release, Ninja).
#   scripts/build.sh               everything (library, executables, tests, benchmarks)
#   scripts/build.sh TARGET ...    only these targets (e.g. simulate-vehs identify-vehs)
# The defaults are portable (any x86-64 CPU) and never turn warnings into errors. Environment:
#   VEHS_BUILD_DIR   build folder (default ./build)
#   VEHS_NATIVE=ON   optimise for this machine (-march=native; local use, no library install)
#   VEHS_WERROR=ON   warnings in project code are errors (CI: .ci/run)
#   VEHS_CMAKE_ARGS  further arguments for the CMake configure step
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
"$root/scripts/install-deps.sh"
# shellcheck disable=SC2086
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DVEHS_NATIVE="${VEHS_NATIVE:-OFF}" -DVEHS_WERROR="${VEHS_WERROR:-OFF}" ${VEHS_CMAKE_ARGS:-} >/dev/null
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build "$build" -j "$(nproc)" "${targets[@]}"
