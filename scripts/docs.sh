#!/usr/bin/env bash
# The documentation generated from the sources.
#   scripts/docs.sh --reference   rewrite docs/reference/<tool>-keys.md from the built executables'
#                                 --help-markdown (the same key table as --help); the CTest test
#                                 "docs: key references in docs/reference match every tool's --help"
#                                 fails when a checked-in page differs from its tool's output.
# VEHS_BUILD_DIR as for scripts/build.sh (default ./build).
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
  echo "docs: wrote docs/reference/{$(IFS=,; echo "${tools[*]}")}-keys.md" >&2
}

case "${1:-}" in
  --reference) reference ;;
  *) echo "usage: scripts/docs.sh --reference" >&2; exit 2 ;;
esac
