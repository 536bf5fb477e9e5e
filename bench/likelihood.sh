#!/usr/bin/env bash
# The likelihood benchmarks of issue 12, written to bench/results/likelihood_<part>.txt:
#   bench/likelihood.sh [silverbox] [narx] [synthetic] [paper] [driven] [effects] [speed] [gaussian]
# (no argument: all). `narx` installs SysIdentPy (PyPI; an optional dependency of this
# benchmark only) into build/bench-venv and fits polynomial NARX models on the same Silverbox
# split. Long: run under nice; the synthetic part takes about an hour on 2 cores.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
out="$root/bench/results"
mkdir -p "$out"
parts=("$@")
[ ${#parts[@]} -eq 0 ] && parts=(silverbox narx synthetic paper driven effects speed gaussian)
bench="$build/bench/bench_likelihood"
# build it unless present (a rebuild with other settings would rebuild the whole tree)
[ -x "$bench" ] || "$root/scripts/build.sh" bench_likelihood >/dev/null
cd "$root"
run() {  # run PART COMMAND...: output to a temporary file, moved into place when complete
  local part="$1"; shift
  local tmp="$out/.likelihood_$part.txt.tmp"
  { echo "# $(date -u +%F) $(uname -m), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"; "$@"; } >"$tmp"
  mv "$tmp" "$out/likelihood_$part.txt"
  cat "$out/likelihood_$part.txt"
}
for p in "${parts[@]}"; do
  case "$p" in
    silverbox) run silverbox "$bench" silverbox data/silverbox/SNLS80mV.csv ;;
    narx)
      venv="$build/bench-venv"
      [ -x "$venv/bin/python" ] || python3 -m venv "$venv"
      "$venv/bin/python" -c "import sysidentpy" 2>/dev/null || "$venv/bin/pip" install -q sysidentpy
      run narx "$venv/bin/python" bench/silverbox_narx.py data/silverbox/SNLS80mV.csv ;;
    synthetic)
      run synthetic bash -c "
        '$bench' synthetic bistable 0.35 0    20 2000 8
        '$bench' synthetic bistable 0.35 0.02 20 2000 8
        '$bench' synthetic bistable 0.7  0    20 2000 8
        '$bench' synthetic bistable 0.7  0.02 20 2000 8" ;;
    paper)
      run paper bash -c "
        '$bench' synthetic paper 0.118 0    ${PAPER_SEEDS:-20} 1000 8
        '$bench' synthetic paper 0.118 0.02 ${PAPER_SEEDS:-20} 1000 8
        '$bench' synthetic paper 0.236 0    ${PAPER_SEEDS:-20} 1000 8
        '$bench' synthetic paper 0.236 0.02 ${PAPER_SEEDS:-20} 1000 8" ;;
    driven) run driven "$bench" driven "${SEEDS:-20}" ;;
    effects) run effects "$bench" effects "${SEEDS:-20}" ;;
    speed) run speed "$bench" speed ;;
    gaussian) run gaussian "$bench" gaussian ;;
    *) echo "likelihood.sh: unknown part '$p'" >&2; exit 2 ;;
  esac
done
