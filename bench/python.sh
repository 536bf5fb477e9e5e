#!/usr/bin/env bash
# Python and Dask overhead against the CLI (bench/python_overhead.py; results in
# bench/results/python.txt). Builds the tools and the package (scripts/test.sh's venv) first.
#   bench/python.sh [sweep] [identify]     (REPEATS=3: best of; BLOCKS=default,2: Dask tasks per sweep)
# e.g. the Fig. 5a sweep, CLI vs vehs.dask.sweep's default tasks, once:
#   REPEATS=1 BLOCKS=default bench/python.sh sweep
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
python="$("$root/scripts/python-env.sh" "$build")"
VEHS_CMAKE_ARGS="${VEHS_CMAKE_ARGS:-} -DVEHS_PYTHON=ON -DPython_EXECUTABLE=$python" \
  "$root/scripts/build.sh" fpk-stationary identify-vehs simulate-vehs _vehs >/dev/null
"$python" -m pip install -q --disable-pip-version-check --no-build-isolation --no-deps --force-reinstall \
  --config-settings=build-dir="$build" --config-settings=cmake.define.VEHS_BUILD_TESTS=ON --config-settings=cmake.define.VEHS_BUILD_BENCH=ON \
  --config-settings=cmake.define.Python_EXECUTABLE="$python" "$root/python"
export OMP_WAIT_POLICY=PASSIVE
VEHS_BIN_DIR="$build" "$python" "$root/bench/python_overhead.py" "$@"
