#!/usr/bin/env bash
# Reruns Catch2 tests on N independent seeds and reports the spread of their statistics — the
# evidence behind the false-failure probabilities stated in the tests (tests/stat_bounds.hpp).
#   scripts/seed-study.sh N BINARY [TEST-SPEC ...]
#   e.g. scripts/seed-study.sh 50 build/tests/test_identify "[identify][effects]"
# Run s (1..N) sets VEHS_TEST_SEED_SHIFT=s, which moves every seed of the tests that take theirs
# from vehs_test::seed(); the statistics they tally() are collected. Printed per test and
# quantity: runs, mean z ± its standard error, sd of z (≈ 1 for calibrated error bars), max |z|,
# mean relative error ± its standard error; and per test the runs that failed any check.
# Environment: SHIFT0 (first shift, default 1), JOBS (runs at a time, default nproc, each with OMP_NUM_THREADS=1; tests that
# write files under the build folder — the [app] ones — need JOBS=1), OUT (folder for the raw
# tallies and JUnit reports; default a new folder under /tmp, printed).
set -euo pipefail
if [ $# -lt 2 ]; then
  sed -n '2,13p' "$0" >&2
  exit 2
fi
n=$1
bin=$(realpath "$2")
shift 2
jobs=${JOBS:-$(nproc)}
out=${OUT:-$(mktemp -d /tmp/seed-study.XXXXXX)}
mkdir -p "$out"
echo "seed-study: $n runs of $(basename "$bin") $*, raw results in $out" >&2

run_one() {
  VEHS_TEST_SEED_SHIFT=$1 VEHS_TEST_TALLY="$out/tally.$1" OMP_NUM_THREADS=1 \
    "$bin" "${@:2}" -r junit -o "$out/junit.$1.xml" >/dev/null 2>&1 || true
}
first=${SHIFT0:-1}  # SHIFT0=k: shifts k … k + N − 1 (default 1 … N)
for s in $(seq "$first" $((first + n - 1))); do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n; done
  run_one "$s" "$@" &
done
wait

cat "$out"/tally.* 2>/dev/null | awk -F'\t' '
  { k = $1 "\t" $2; n[k]++; z = $3 + 0; s[k] += z; s2[k] += z * z
    if (!(k in mx) || (z < 0 ? -z : z) > mx[k]) mx[k] = (z < 0 ? -z : z)
    if ($4 != "nan" && $4 != "-nan") { nr[k]++; r[k] += $4; r2[k] += $4 * $4 } }
  END {
    printf "%-64s %-24s %5s %22s %9s %9s %22s\n", "test", "quantity", "n", "mean z +- se", "sd z", "max|z|", "mean rel.err +- se"
    for (k in n) {
      split(k, p, "\t"); m = s[k] / n[k]; v = n[k] > 1 ? (s2[k] - n[k] * m * m) / (n[k] - 1) : 0
      sd = v > 0 ? sqrt(v) : 0; rel = ""
      if (nr[k] > 0) { rm = r[k] / nr[k]; rv = nr[k] > 1 ? (r2[k] - nr[k] * rm * rm) / (nr[k] - 1) : 0
        rel = sprintf("%+9.3f%% +- %.3f%%", 100 * rm, 100 * sqrt(rv > 0 ? rv : 0) / sqrt(nr[k])) }
      printf "%-64.64s %-24.24s %5d %+10.4g +- %-8.3g %9.4g %9.4g %22s\n", p[1], p[2], n[k], m, sd / sqrt(n[k]), sd, mx[k], rel
    }
  }' | { read -r header; echo "$header"; sort; }

echo
echo "runs that failed, per test case:"
for f in "$out"/junit.*.xml; do
  [ -e "$f" ] || continue
  awk '/<testcase /{ match($0, / name="[^"]*"/); name = substr($0, RSTART + 7, RLENGTH - 8) }
       /<failure/ { if (!(name in seen)) { seen[name] = 1; print name } }' "$f"
done | sort | uniq -c | sort -rn
echo "(of $n runs)"
