#!/usr/bin/env bash
# Issue 13's power study, one hidden case at a time (bench/results/diagnose_calibration_log.md, "The study over
# seeds"): nice 10, one thread, the log in out/score_study/CASE.seedsK-N.log, the CPU seconds
# and the load average at the end.
#   bench/diagnose_score_study.sh CASE [SEEDS [SEED0]]     e.g. bench/diagnose_score_study.sh impact_stop 10
# VEHS_SCORE_LOOP=0: power only (no refit with the named effect); VEHS_SCORE_RECORDS=n: n records; VEHS_SCORE_SAMPLES=n: n samples a record;
# VEHS_SCORE_ORACLE=0: no oracle refit (the loop alone); VEHS_SCORE_LOOP_LIKELIHOOD=1 / 0: the loop's refit always / never refined by the
# likelihood (default: as identify-vehs's estimator "auto" decides); VEHS_SCORE_COARSE=1: Δt 0.35 with 2 % sensor noise, likelihood-fitted baseline (power only).
# VEHS_SCORE_NULL=1: the case's data without its hidden effect (the oracle's null, the suspects' false claims).
# VEHS_SCORE_PR_START=suspect: the per-record forcing's likelihood refit starts from the score suspect's amplitude and ω
# (default: from every record's own moment fit, as identify-vehs's per_record_phase does).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
case="${1:?usage: diagnose_score_study.sh CASE [SEEDS [SEED0]]}"
seeds="${2:-10}"
seed0="${3:-0}"
mkdir -p "$root/out/score_study"
tag="${VEHS_SCORE_RECORDS:+.records$VEHS_SCORE_RECORDS}${VEHS_SCORE_SAMPLES:+.samples$VEHS_SCORE_SAMPLES}"
[ "${VEHS_SCORE_LOOP:-1}" = 0 ] && tag="$tag.noloop"
[ "${VEHS_SCORE_COARSE:-0}" = 1 ] && tag="$tag.coarse"
[ "${VEHS_SCORE_ORACLE:-1}" = 0 ] && tag="$tag.nooracle"
[ "${VEHS_SCORE_LOOP_LIKELIHOOD:-}" = 1 ] && tag="$tag.looplik"
[ "${VEHS_SCORE_LOOP_LIKELIHOOD:-}" = 0 ] && tag="$tag.loopmoments"
[ -n "${VEHS_SCORE_PR_START:-}" ] && tag="$tag.start-$VEHS_SCORE_PR_START"
[ "${VEHS_SCORE_NULL:-0}" = 1 ] && tag="$tag.null"
log="$root/out/score_study/$case.seeds$seed0-$((seed0 + seeds - 1))$tag.log"
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)" >"$log"
VEHS_SCORE_CASE="$case" VEHS_SCORE_SEEDS="$seeds" VEHS_SCORE_SEED0="$seed0" OMP_NUM_THREADS=1 \
  /usr/bin/time -a -o "$log" -f "$case seeds $seed0..$((seed0 + seeds - 1)): %e s wall, %U s user + %S s sys CPU" \
  nice -n 10 "$build/tests/test_diagnose" "[.score_study]" >>"$log" 2>&1 || true
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)" >>"$log"
grep -E "SUMMARY|CPU|load average" "$log"
