# Sourced by the scripts that run the tools (scripts/silverbox.sh, bench/*.sh): sets `root` (the
# repository) and `build` (VEHS_BUILD_DIR, default build/), and need_tools EXE... builds the
# executables that are missing (scripts/build.sh).
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
need_tools() {
  local exe
  for exe in "$@"; do
    [ -x "$build/$exe" ] || "$root/scripts/build.sh" "$exe" >/dev/null
  done
}
