#!/usr/bin/env bash
# Issue 13 on real data: diagnose-vehs on the Silverbox likelihood model (the fit of
# scripts/silverbox.sh: data/silverbox/identify.json) with the estimation records [40650, 105712),
# then, for every effect diagnose recommends (a significant score suspect or a held-out
# significant suspect), the identify refit with that effect added and its free-run RMSE on the
# test records (data/silverbox/validate.json: arrow, multisine) beside the model's.
#   bench/diagnose_silverbox.sh            outputs in build/silverbox_diagnose/
#   INPUT=zoh bench/diagnose_silverbox.sh  the likelihood fitted with a zero-order-hold input (the
#                                          interpolation diagnose's filter applies until it reads
#                                          the model's; default: the config's band_limited)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
out="$build/silverbox_diagnose${INPUT:+_$INPUT}"
mkdir -p "$out"
for exe in identify-vehs simulate-vehs diagnose-vehs; do
  [ -x "$build/$exe" ] || "$root/scripts/build.sh" "$exe" >/dev/null
done
cd "$root"
lik=()
[ -n "${INPUT:-}" ] && lik=(--set "likelihood={\"input\": \"$INPUT\", \"covariance\": \"fisher\", \"select\": true, \"criterion\": \"bic\"}")
validate() {  # model.json validation.json
  python3 -c 'import json, sys
c = json.load(open("data/silverbox/validate.json"))
c["model"] = sys.argv[1]; c["validate"]["output"] = sys.argv[2]; c["validate"]["figure"] = False
json.dump(c, open(sys.argv[2] + ".config", "w"), indent=1)' "$1" "$2"
  "$build/simulate-vehs" "$2.config" -q >/dev/null 2>"$2.log"
}
"$build/identify-vehs" data/silverbox/identify.json --set "output=\"$out/model.json\"" "${lik[@]}" >"$out/identify.txt" 2>"$out/identify.log" ||
  { tail -1 "$out/identify.log" >&2; exit 1; }
validate "$out/model.json" "$out/validation.json"
python3 - "$out" <<'PY'
import csv, json, sys
out = sys.argv[1]
ident = json.load(open("data/silverbox/identify.json"))
first, last = ident["samples"]
with open(ident["data"]) as f, open(out + "/estimation.csv", "w", newline="") as g:
    r = csv.reader(f); w = csv.writer(g)
    w.writerow(next(r))
    for i, row in enumerate(r):
        if first <= i < last: w.writerow(row)
json.dump({"model": out + "/model.json", "data": out + "/estimation.csv", "columns": ident["columns"],
           "dt": ident["dt"], "detrend": ident["detrend"], "output": out + "/diagnosis.json", "fpk": False},
          open(out + "/diagnose.json", "w"), indent=1)
PY
"$build/diagnose-vehs" "$out/diagnose.json" -q >"$out/diagnose.log" 2>&1 || { tail -3 "$out/diagnose.log" >&2; exit 1; }
mapfile -t effects < <(python3 - "$out/diagnosis.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
names = []
for s in d.get("score_suspects", []):
    if s.get("significant"): names.append(s["effect"].replace("_per_record", ""))
for s in d.get("suspects", []):
    if s.get("significant"): names.append(s["effect"])
seen = set()
for n in names:
    if n not in seen: seen.add(n); print(n)
PY
)
rmse() {  # validation.json -> "arrow msine" in mV
  python3 -c 'import json, sys; v = json.load(open(sys.argv[1])); print(" ".join("%.3f" % (1e3 * s["rmse"]) for s in v["segments"]))' "$1"
}
python3 - "$out/diagnosis.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print("verdict:", d.get("verdict"), "score", d.get("score"))
for name, t in d.get("tests", {}).items():
    if t.get("available"): print(f"  {name:22s} p = {t.get('p_value'):.3g}")
for key in ("score_suspects", "suspects"):
    for s in d.get(key, [])[:4]:
        print(f"  {key}: {s['effect']:28s} z = {s.get('z', 0):.2f} significant {s.get('significant')}")
PY
echo "free-run RMSE (mV after 50 samples): $(python3 -c 'import json; print(", ".join(s["name"] for s in json.load(open("data/silverbox/validate.json"))["validate"]["segments"]))')"
echo "  model as fitted: $(rmse "$out/validation.json")"
[ ${#effects[@]} -eq 0 ] && echo "  no effect recommended"
for e in "${effects[@]}"; do
  "$build/identify-vehs" data/silverbox/identify.json --set "output=\"$out/model_$e.json\"" "${lik[@]}" \
    --set "effects=[\"$e\"]" >"$out/identify_$e.txt" 2>"$out/identify_$e.log" || { echo "  + $e: identify failed: $(tail -1 "$out/identify_$e.log")"; continue; }
  if validate "$out/model_$e.json" "$out/validation_$e.json"; then
    echo "  + $e: $(rmse "$out/validation_$e.json")"
  else
    echo "  + $e: validation failed: $(tail -1 "$out/validation_$e.json.log")"
  fi
done
