#!/usr/bin/env bash
# Issue 33 ("cost cliffs"): identify-vehs and diagnose-vehs timed (wall and CPU) on data generated
# by their own route (bench/diagnose_cost_data.py: Euler–Maruyama on 40 steps per interval, not
# vehs's simulator), written to bench/results/diagnose_cost.txt:
#   bench/diagnose_cost.sh [poly] [penta] [driven]     (no argument: all three)
# poly:   20 bistable records, 1.5e5 samples at Δt = 0.2; drift library up to x^8 with x^4…x^8 kept
#         (keep_terms, likelihood select false), so the model holds a degree-8 polynomial;
# penta:  20 penta-stable records (−U' up to x^9), 1.5e5 samples at Δt = 0.05, library up to x^8
#         (the fit keeps x^6, x^7: a model the data reject, so diagnose runs its confirmation refits);
# driven: one bistable record of 4e5 samples, Δt = 0.2, recorded base acceleration u, identify's
#         defaults (u in the library).
# Every stage runs alone (the machine has 2 cores); the load average is printed beside it.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
cd "$root"
for exe in identify-vehs diagnose-vehs; do
  [ -x "$build/$exe" ] || scripts/build.sh "$exe" >/dev/null
done
parts=("$@")
[ ${#parts[@]} -eq 0 ] && parts=(poly penta driven)
work=out/cost
mkdir -p "$work" bench/results
timed() {  # timed LABEL COMMAND...
  local label="$1"; shift
  /usr/bin/time -f "$label: %e s wall, %U s user + %S s sys CPU, %M kB peak" "$@" >"$work/$label.log" 2>"$work/$label.err" ||
    { tail -5 "$work/$label.err"; return 1; }
  tail -1 "$work/$label.err"
  echo "  load average: $(cut -d' ' -f1-3 /proc/loadavg)"
}
for p in "${parts[@]}"; do
  case "$p" in
    poly)
      gen=bistable
      lib='"drift_library": {"K1": 9, "K2": 3}, "keep_terms": {"drift": ["x^4", "x^5", "x^6", "x^7", "x^8"]}, "likelihood": {"select": false}' ;;
    penta) gen=penta; lib='"drift_library": {"K1": 9, "K2": 3}' ;;
    driven) gen=driven; lib='' ;;
    *) echo "unknown part $p" >&2; exit 2 ;;
  esac
  [ -s "$work/$p.npy" ] || python3 bench/diagnose_cost_data.py "$gen" "$work/$p.npy"
  echo "{\"data\": [\"$work/$p.npy\"], \"output\": \"$work/${p}_model.json\"${lib:+, $lib}}" >"$work/identify_$p.json"
  echo "{\"model\": \"$work/${p}_model.json\", \"data\": [\"$work/$p.npy\"], \"output\": \"$work/${p}_diagnosis.json\", \"report\": \"$work/${p}_report\"}" \
    >"$work/diagnose_$p.json"
  timed "identify_$p" "$build/identify-vehs" "$work/identify_$p.json"
  timed "diagnose_$p" "$build/diagnose-vehs" "$work/diagnose_$p.json" -q
  grep -m1 "^conclusion" "$work/diagnose_$p.log" || true
done | tee bench/results/diagnose_cost.txt
