#!/usr/bin/env bash
# Installs missing dependencies (Debian packages) and builds vehs in ./build (Release, Ninja).
#   scripts/build.sh               everything (library, executables, tests, benchmarks)
#   scripts/build.sh TARGET ...    only these targets (e.g. simulate-vehs identify-vehs)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install-deps.sh"
cmake -S "$root" -B "$root/build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build "$root/build" -j "$(nproc)" "${targets[@]}"
