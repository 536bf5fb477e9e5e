#!/usr/bin/env bash
# Installs missing dependencies, builds, and runs the whole test suite (ctest over Catch2).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh"
cd "$root/build"
ctest -j "$(nproc)" --output-on-failure --timeout 900
