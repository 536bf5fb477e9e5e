#!/usr/bin/env bash
# The longest checks of the test suite (Catch2 tag [long], CTest label "long", and the Python tests
# marked long: over 30 s each), left out of scripts/test.sh so that the suite stays under 10
# minutes; .ci/run runs both. Builds what they need first (in the same build folder as
# scripts/test.sh).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
python="$("$root/scripts/python-env.sh" "$build")"
VEHS_CMAKE_ARGS="${VEHS_CMAKE_ARGS:-} -DVEHS_PYTHON=ON -DPython_EXECUTABLE=$python" \
  "$root/scripts/build.sh" vehs_test_targets _vehs
cd "$build"
export OMP_WAIT_POLICY=PASSIVE
ctest -j "$(nproc)" --output-on-failure --timeout 900 -L long
python="$("$root/scripts/python-install.sh" "$build")"
cd "$root"
VEHS_BIN_DIR="$build" VEHS_REQUIRE_CLI=1 "$python" -m pytest -q -p no:cacheprovider -m long "$root/python/tests"
