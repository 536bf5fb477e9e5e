#!/usr/bin/env bash
# The simulator's speed at every SIMD level of its kernels that this CPU runs (vehs/sim/simd.hpp:
# the same bitwise results at each), written to bench/results/simulate_levels.txt: the paper's
# Eq. 30 (rk4_euler, 100 records × 10⁵ samples, one thread), as rates per
# CPU second ('per core': meaningful when other jobs share the machine).
# Usage: bench/simulate_levels.sh      (a Release build of bench_simulate in $VEHS_BUILD_DIR or ./build)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
bench="$build/bench/bench_simulate"
[ -x "$bench" ] || "$root/scripts/build.sh" bench_simulate >/dev/null
out="$root/bench/results/simulate_levels.txt"
{
  echo "# bench/simulate_levels.sh, $(date -u +%FT%TZ),$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
  echo "# CPU flags: $(grep -o 'avx512f\|avx2\|fma' /proc/cpuinfo | sort -u | tr '\n' ' ')"
  uptime
  for level in scalar sse2 avx2 avx512; do
    echo "== VEHS_SIMD=$level"
    VEHS_SIMD=$level "$bench" --benchmark_filter='BM_PaperSimulate/threads:1/records:100/scheme:1' \
      --benchmark_color=false 2>&1 | sed -n '/^All benchmarks/,$p' || echo "(this CPU cannot run it)"
  done
  uptime
} >"$out.tmp"
mv "$out.tmp" "$out"
cat "$out"
