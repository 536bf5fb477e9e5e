#!/usr/bin/env bash
# Installs missing dependencies, builds, and runs the whole test suite (ctest over Catch2).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh" vehs_test_targets  # the library, the executables and the tests (not bench/)
cd "$root/build"
# ctest -j2 runs two 2-thread tests on 2 cores: OpenMP threads that spin while waiting steal the
# cores from the working ones (measured, fresh ctest order: suite 4m09 with spinning waits, 3m10 with
# passive ones)
export OMP_WAIT_POLICY=PASSIVE
ctest -j "$(nproc)" --output-on-failure --timeout 900
