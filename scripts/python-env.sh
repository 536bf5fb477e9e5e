#!/usr/bin/env bash
# The Python package's virtual environment, kept in the build folder so that a second run is fast:
#   scripts/python-env.sh BUILD_DIR   creates BUILD_DIR/python-venv when missing and installs the
#                                     PyPI packages the build and tests need (only when missing);
#                                     prints the venv's python.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
mkdir -p "$1"
venv="$(cd "$1" && pwd)/python-venv"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv" >&2
fi
if ! "$venv/bin/python" -c "import nanobind, scikit_build_core, numpy, matplotlib, dask, distributed, pytest, tqdm, nbformat, nbclient, ipykernel" 2>/dev/null; then
  echo "python-env: installing $(tr '\n' ' ' < "$root/python/requirements-dev.txt")into $venv" >&2
  "$venv/bin/pip" install -q --disable-pip-version-check -r "$root/python/requirements-dev.txt" >&2
fi
echo "$venv/bin/python"
