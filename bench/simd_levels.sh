#!/usr/bin/env bash
# Speed at every SIMD level of the dispatched kernels that this CPU runs (vehs/sim/simd.hpp: the
# same bitwise results at each level), one thread, forced with VEHS_SIMD:
#   simulate  the simulator's kernels: the paper's Eq. 30 (rk4_euler, 100 records × 10⁵ samples),
#             rates per CPU second ('per core') -> bench/results/simulate_levels.txt
#   identify  identify's Gram kernel: the paper-sized data (10⁷ samples, .npy) read and
#             identified, with CPU seconds -> bench/results/identify_levels.txt
# CPU-time figures stay meaningful when other jobs share the machine.
# Usage: bench/simd_levels.sh [simulate|identify]...   (default both; Release builds of
#        bench_simulate / bench_identify in $VEHS_BUILD_DIR or ./build, built if missing)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
run_level() {  # what, level
  if [ "$1" = simulate ]; then
    VEHS_SIMD=$2 "$build/bench/bench_simulate" --benchmark_color=false \
      --benchmark_filter='BM_PaperSimulate/threads:1/records:100/scheme:1' 2>&1 | sed -n '/^All benchmarks/,$p'
  else
    VEHS_SIMD=$2 "$build/bench/bench_identify" run "$build/bench/bench_identify_data/paper_1e7.npy" 1 2>&1 |
      grep -v '^ *estimator'
  fi
}
for what in "${@:-simulate identify}"; do
  for w in $what; do
    [ -x "$build/bench/bench_$w" ] || VEHS_BUILD_DIR="$build" "$root/scripts/build.sh" "bench_$w" >/dev/null
    if [ "$w" = identify ] && [ ! -f "$build/bench/bench_identify_data/paper_1e7.npy" ]; then
      "$build/bench/bench_identify" generate "$build/bench/bench_identify_data" >/dev/null
    fi
    out="$root/bench/results/${w}_levels.txt"
    {
      echo "# bench/simd_levels.sh $w, $(date -u +%FT%TZ),$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2), build $build"
      echo "# CPU flags: $(grep -o 'avx512f\|avx2\|fma' /proc/cpuinfo | sort -u | tr '\n' ' ')"
      uptime
      for level in scalar sse2 avx2 avx512; do
        echo "== VEHS_SIMD=$level"
        run_level "$w" "$level" || echo "(this CPU cannot run it)"
      done
      uptime
    } >"$out.tmp"
    mv "$out.tmp" "$out"
    cat "$out"
  done
done
