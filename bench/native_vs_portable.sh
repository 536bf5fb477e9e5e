#!/usr/bin/env bash
# The README's speed table, portable and native columns measured back to back with the same
# commands: build/bench/bench_simulate and build/bench/bench_identify (portable: the default
# VEHS_NATIVE=OFF, the dispatched kernels at the CPU's widest level) against the same two in
# build-native (VEHS_NATIVE=ON: -march=native). Writes bench/results/simulate_{portable,native}.txt
# and identify_{portable,native}.txt, with the load average before and after each run (on a
# shared machine compare the 'per core' / 'CPU time' figures).
# Usage: bench/native_vs_portable.sh    (builds what is missing: bench targets only)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
portable="${VEHS_BUILD_DIR:-$root/build}"
native="${VEHS_NATIVE_BUILD_DIR:-$root/build-native}"
for b in bench_simulate bench_identify; do
  [ -x "$portable/bench/$b" ] || VEHS_BUILD_DIR="$portable" "$root/scripts/build.sh" "$b" >/dev/null
  [ -x "$native/bench/$b" ] ||
    VEHS_NATIVE=ON VEHS_BUILD_DIR="$native" VEHS_CMAKE_ARGS="${VEHS_CMAKE_ARGS:-} -DVEHS_BUILD_TESTS=OFF" \
      "$root/scripts/build.sh" "$b" >/dev/null
done
cpu="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2), flags: $(grep -o 'avx512f\|avx2\|fma' /proc/cpuinfo | sort -u | tr '\n' ' ')"
data="$portable/bench/bench_identify_data"
[ -f "$data/paper_1e7.npy" ] || "$portable/bench/bench_identify" generate "$data" >/dev/null
for kind in portable native; do
  dir=$portable
  [ "$kind" = native ] && dir=$native
  for b in simulate identify; do
    out="$root/bench/results/${b}_$kind.txt"
    {
      echo "# bench/native_vs_portable.sh: $dir/bench/bench_$b, ${kind^^} build, $(date -u +%FT%TZ),$cpu"
      uptime
      if [ "$b" = simulate ]; then
        "$dir/bench/bench_simulate" --benchmark_color=false 2>&1
      else
        for f in paper_1e7.npy paper_1e7.csv; do
          for t in 1 2; do "$dir/bench/bench_identify" run "$data/$f" "$t" 2>&1; done
        done
      fi
      uptime
    } >"$out.tmp"
    mv "$out.tmp" "$out"
    echo "== $out"
    grep -E 'load average|records|^ *[0-9]+ |per core|CPU time|peak RSS' "$out" | head -40
  done
done
