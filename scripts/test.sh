#!/usr/bin/env bash
# Installs missing dependencies, builds, and runs the whole test suite (ctest over Catch2).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh" vehs_test_targets  # the library, the executables and the tests (not bench/)
cd "$root/build"
ctest -j "$(nproc)" --output-on-failure --timeout 900
