#!/usr/bin/env bash
# Fuzzes every reader with libFuzzer (clang from Debian) under AddressSanitizer and
# UndefinedBehaviorSanitizer: the CSV and .npy measurement readers, JSON configs (parse, key
# checks, every typed getter, --set) and model files. Each target runs VEHS_FUZZ_RUNS executions
# (default 10^7) from the seed corpus in bench/fuzz/corpus/<target>/, with a 10 s limit per input
# (a slower input is reported as a hang) and 2 GB of memory; it stops at the first crash,
# sanitizer report, hang or memory blow-up and leaves the reproducer in build-fuzz/findings/.
#   bench/fuzz/run.sh                 all four targets
#   bench/fuzz/run.sh csv_reader      one target (csv_reader, npy_reader, json_config, model_file)
# Environment: VEHS_FUZZ_RUNS (executions per target), VEHS_FUZZ_SECONDS (a time limit per target
# instead: the line then says how many executions it reached, the rate, and the hours 10^7 needs),
# VEHS_FUZZ_BUILD_DIR (default ./build-fuzz). Run it under `nice -n 10` on a shared machine.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="${VEHS_FUZZ_BUILD_DIR:-$root/build-fuzz}"
runs="${VEHS_FUZZ_RUNS:-10000000}"
seconds="${VEHS_FUZZ_SECONDS:-0}"
VEHS_WITH_FUZZ=1 "$root/scripts/install-deps.sh"
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(csv_reader npy_reader json_config model_file)
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DVEHS_FUZZ=ON -DVEHS_BUILD_TESTS=OFF \
  -DVEHS_BUILD_BENCH=OFF ${VEHS_CMAKE_ARGS:-} >/dev/null
build_targets=()
for t in "${targets[@]}"; do build_targets+=(--target "fuzz_$t"); done
cmake --build "$build" -j "$(nproc)" "${build_targets[@]}"
mkdir -p "$build/findings"
status=0
for t in "${targets[@]}"; do
  work="$build/corpus/$t"  # the grown corpus (the repository's seeds stay as they are)
  mkdir -p "$work"
  log="$build/fuzz_$t.log"
  start=$(date +%s)
  if /usr/bin/time -f "%U %S" -o "$log.cpu" "$build/bench/fuzz/fuzz_$t" -runs="$runs" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
       -print_final_stats=1 -artifact_prefix="$build/findings/$t-" "$work" "$root/bench/fuzz/corpus/$t" >"$log" 2>&1; then
    n=$(grep -a -m1 'stat::number_of_executed_units' "$log" | awk '{print $2}')
    rate=$(grep -a -m1 'stat::average_exec_per_sec' "$log" | awk '{print $2}')
    cpu=$(awk '{ printf "%.0f", $1 + $2 }' "$log.cpu")
    echo "fuzz_$t: $n executions, no crash, sanitizer report or hang ($(( $(date +%s) - start )) s wall," \
         "$cpu CPU s, load average $(cut -d' ' -f1-3 /proc/loadavg)): $rate exec/s," \
         "$(awk -v n="$n" -v c="$cpu" 'BEGIN { printf "%.0f", (c > 0 ? n / c : 0) }') per CPU second;" \
         "10^7 take $(awk -v r="$rate" 'BEGIN { printf "%.1f", (r > 0 ? 1e7 / r / 3600 : 0) }') h at this rate," \
         "$(awk -v n="$n" -v c="$cpu" 'BEGIN { printf "%.1f", (n > 0 ? 1e7 * c / n / 3600 : 0) }') h of an idle core (log $log)"
  else
    status=1
    echo "fuzz_$t: FINDING after $(( $(date +%s) - start )) s: $(grep -a -m1 -E 'ERROR|SUMMARY|timeout|deadly' "$log")"
    echo "  reproducer: $(ls "$build/findings/$t-"* 2>/dev/null | head -1); log $log"
  fi
done
exit $status
