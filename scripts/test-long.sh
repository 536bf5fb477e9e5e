#!/usr/bin/env bash
# The longest statistical checks of the test suite (Catch2 tag [long], CTest label "long": over
# 30 s each), left out of scripts/test.sh so that the suite stays under 10 minutes; .ci/run runs
# both. Builds what they need first (in the same build folder as scripts/test.sh).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
"$root/scripts/build.sh" vehs_test_targets
cd "$build"
export OMP_WAIT_POLICY=PASSIVE
ctest -j "$(nproc)" --output-on-failure --timeout 900 -L long
