#!/usr/bin/env bash
# Issue 13's speed target in one line: the paper-sized diagnosis (10^7 samples, score suspects
# and calibration included) timed with its CPU seconds and the load average beside it.
#   bench/diagnose_paper_time.sh     (builds the three tools and the paper's data if missing)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
cd "$root"
for exe in simulate-vehs identify-vehs diagnose-vehs; do
  [ -x "$build/$exe" ] || scripts/build.sh "$exe" >/dev/null
done
[ -s out/paper/measurements.npy ] || "$build/simulate-vehs" data/paper/simulate.json -q >/dev/null
[ -s out/paper/learned.json ] || "$build/identify-vehs" data/paper/identify.json >/dev/null
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
/usr/bin/time -f "diagnose-vehs data/diagnose/paper.json: %e s wall, %U s user + %S s sys CPU, %M kB peak" \
  "$build/diagnose-vehs" data/diagnose/paper.json -q >/dev/null
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
