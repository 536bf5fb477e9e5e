#!/usr/bin/env bash
# Issue 13 on real data: diagnose-vehs on the Silverbox likelihood model (scripts/silverbox.sh)
# with the estimation records [40650, 105712), then, for every effect diagnose recommends (a
# significant score suspect or a held-out significant suspect), the identify refit with that
# effect added and its free-run RMSE on the test records (arrow, multisine) beside the model's.
#   bench/diagnose_silverbox.sh      outputs in build/silverbox/ (diagnosis.json, diagnosis_report/,
#                                    model_<effect>.json, validation_<effect>.json)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"
out="$build/silverbox"
for exe in identify-vehs simulate-vehs diagnose-vehs; do
  [ -x "$build/$exe" ] || "$root/scripts/build.sh" "$exe" >/dev/null
done
cd "$root"
[ -s "$out/model.json" ] || scripts/silverbox.sh >/dev/null
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
  "$build/identify-vehs" data/silverbox/identify.json --set "output=\"$out/model_$e.json\"" \
    --set "effects=[\"$e\"]" >"$out/identify_$e.txt" 2>"$out/identify_$e.log" || { echo "  + $e: identify failed: $(tail -1 "$out/identify_$e.log")"; continue; }
  python3 -c 'import json, sys
c = json.load(open("data/silverbox/validate.json"))
c["model"] = sys.argv[1]; c["validate"]["output"] = sys.argv[2]; c["validate"]["figure"] = False
json.dump(c, open(sys.argv[3], "w"), indent=1)' "$out/model_$e.json" "$out/validation_$e.json" "$out/validate_$e.json"
  if "$build/simulate-vehs" "$out/validate_$e.json" -q >/dev/null 2>"$out/validate_$e.log"; then
    echo "  + $e: $(rmse "$out/validation_$e.json")"
  else
    echo "  + $e: validation failed: $(tail -1 "$out/validate_$e.log")"
  fi
done
