#!/usr/bin/env bash
# identify's speed at every SIMD level of its Gram kernel that this CPU runs (vehs/identify/gram.hpp,
# the same bitwise results at each), written to bench/results/identify_levels.txt: the paper-sized
# data (10⁷ samples, .npy) read and identified on one thread, CPU seconds beside the wall times
# ('CPU time' lines: meaningful when other jobs share the machine).
# Usage: bench/identify_levels.sh      (a Release build of bench_identify in $VEHS_BUILD_DIR or ./build)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
bench="$build/bench/bench_identify"
[ -x "$bench" ] || "$root/scripts/build.sh" bench_identify >/dev/null
data="$build/bench/bench_identify_data"
[ -f "$data/paper_1e7.npy" ] || "$bench" generate "$data" >/dev/null
out="$root/bench/results/identify_levels.txt"
{
  echo "# bench/identify_levels.sh, $(date -u +%FT%TZ),$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2), build $build"
  echo "# CPU flags: $(grep -o 'avx512f\|avx2\|fma' /proc/cpuinfo | sort -u | tr '\n' ' ')"
  uptime
  for level in scalar sse2 avx2 avx512; do
    echo "== VEHS_SIMD=$level"
    VEHS_SIMD=$level "$bench" run "$data/paper_1e7.npy" 1 2>&1 | grep -v '^ *estimator' || echo "(this CPU cannot run it)"
  done
  uptime
} >"$out.tmp"
mv "$out.tmp" "$out"
cat "$out"
