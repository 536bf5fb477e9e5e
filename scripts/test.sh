#!/usr/bin/env bash
# Installs missing dependencies, builds, and runs the whole test suite: ctest over Catch2, then the
# Python package's pytest suite (python/tests) in a virtual environment kept in the build folder.
# The longest checks (CTest label "long", pytest marker "long") run with scripts/test-long.sh instead.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
"$root/scripts/install-deps.sh"
mkdir -p "$build"
python="$("$root/scripts/python-env.sh" "$build")"
# the library, the executables, the tests (not bench/) and the Python extension, in one build
VEHS_CMAKE_ARGS="${VEHS_CMAKE_ARGS:-} -DVEHS_PYTHON=ON -DPython_EXECUTABLE=$python" \
  "$root/scripts/build.sh" vehs_test_targets _vehs
cd "$build"
# ctest -j2 runs two 2-thread tests on 2 cores: OpenMP threads that spin while waiting steal the
# cores from the working ones (measured, fresh ctest order: suite 4m09 with spinning waits, 3m10 with
# passive ones)
export OMP_WAIT_POLICY=PASSIVE
ctest -j "$(nproc)" --output-on-failure --timeout 900 -LE long
python="$("$root/scripts/python-install.sh" "$build")"
cd "$root"
# the Python tests marked long (the paper pipeline example) run with scripts/test-long.sh
VEHS_BIN_DIR="$build" VEHS_REQUIRE_CLI=1 "$python" -m pytest -q -p no:cacheprovider -m "not long" "$root/python/tests"
