#!/usr/bin/env bash
# The Python package into the build folder's virtual environment, with pip (scikit-build-core),
# reusing that build folder: only the extension module is (re)linked; the tools and test settings
# of the build are kept.
#   scripts/python-install.sh BUILD_DIR   prints the venv's python
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$(mkdir -p "$1" && cd "$1" && pwd)"
python="$("$root/scripts/python-env.sh" "$build")"
"$python" -m pip install -q --disable-pip-version-check --no-build-isolation --no-deps --force-reinstall \
  --config-settings=build-dir="$build" --config-settings=cmake.define.VEHS_BUILD_TESTS=ON \
  --config-settings=cmake.define.VEHS_BUILD_BENCH=ON \
  --config-settings=cmake.define.Python_EXECUTABLE="$python" "$root/python" >&2
echo "$python"
