#!/usr/bin/env bash
# The documentation generated from the sources.
#   scripts/docs.sh               build the documentation site into BUILD/docs/html: the pages of
#                                 docs/, README.md, CHANGELOG.md and the data/ and examples/
#                                 READMEs (Sphinx + MyST), the Python API from the docstrings
#                                 (autodoc, from the package installed in BUILD/python-venv) and
#                                 the C++ API from include/vehs/ (Doxygen HTML, linked in). Sphinx
#                                 runs with warnings as errors; relative links of every page are
#                                 checked offline first, files and #anchors alike (tests/docs/
#                                 check_docs.py links: a link to a missing heading fails).
#   scripts/docs.sh --reference   rewrite docs/reference/<tool>-keys.md from the built executables'
#                                 --help-markdown (the same key table as --help); the CTest test
#                                 "docs: key references in docs/reference match every tool's --help"
#                                 fails when a checked-in page differs from its tool's output.
# VEHS_BUILD_DIR as for scripts/build.sh (default ./build). Needs doxygen
# (scripts/install-deps.sh) and installs docs/requirements.txt into the build's Python venv.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
tools=(simulate-vehs identify-vehs fpk-stationary diagnose-vehs vehs-compare)

reference() {
  mkdir -p "$root/docs/reference"
  for t in "${tools[@]}"; do
    [ -x "$build/$t" ] || { echo "docs: $build/$t missing: run scripts/build.sh first" >&2; exit 2; }
    "$build/$t" --help-markdown > "$root/docs/reference/$t-keys.md.tmp"
    mv "$root/docs/reference/$t-keys.md.tmp" "$root/docs/reference/$t-keys.md"
  done
  "$build/identify-vehs" --catalogue-markdown > "$root/docs/reference/effects.md.tmp"
  mv "$root/docs/reference/effects.md.tmp" "$root/docs/reference/effects.md"
  echo "docs: wrote docs/reference/{$(IFS=,; echo "${tools[*]}")}-keys.md and effects.md" >&2
}

site() {
  local py out src
  py="$("$root/scripts/python-env.sh" "$build")"
  "$py" -c "import vehs" 2>/dev/null || { echo "docs: vehs is not installed in $build/python-venv (scripts/test.sh installs it)" >&2; exit 2; }
  "$py" -c "import sphinx, myst_parser" 2>/dev/null ||
    "$py" -m pip install -q --disable-pip-version-check -r "$root/docs/requirements.txt" >&2
  python3 "$root/tests/docs/check_docs.py" links "$root"
  out="$build/docs"
  src="$out/src"
  rm -rf "$src" "$out/html"
  mkdir -p "$src/docs" "$src/_doxygen"
  cp -r "$root/docs/site/." "$src/"
  cp "$root/README.md" "$root/CHANGELOG.md" "$src/"
  (cd "$root/docs" && find . -name '*.md' -not -path './site/*' -exec cp --parents {} "$src/docs/" \;)
  (cd "$root" && find data examples -name '*.md' -exec cp --parents {} "$src/" \;)
  (cd "$root" && sed "s|@OUT@|$src/_doxygen|" docs/site/Doxyfile | doxygen - >"$out/doxygen.log" 2>&1) ||
    { cat "$out/doxygen.log" >&2; exit 1; }
  mv "$src/_doxygen/html" "$src/_doxygen/cpp"
  VEHS_SOURCE_DIR="$root" "$py" -m sphinx -W --keep-going -q -b html "$src" "$out/html"
  echo "docs: $out/html/index.html" >&2
}

case "${1:-}" in
  --reference) reference ;;
  "") site ;;
  *) echo "usage: scripts/docs.sh [--reference]" >&2; exit 2 ;;
esac
