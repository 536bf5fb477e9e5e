#!/usr/bin/env bash
# Issue 13 on real data: diagnose-vehs on the Silverbox likelihood model (the fit of
# scripts/silverbox.sh: data/silverbox/identify.json) with the estimation records [40650, 105712),
# then, for every effect diagnose refitted before recommending (the significant score and
# held-out suspects: confirmation.hpp), the identify refit with that effect added on all the
# estimation records and its free-run RMSE on the test records (data/silverbox/validate.json:
# arrow, multisine) beside the model's, marked "recommended" (confirmed by diagnose's held-out
# refit) or "not confirmed". The refit applies the recommendation as diagnose confirmed it: the
# model's own terms plus the effect, fitted like the model (identify + likelihood), no
# re-selection. For a recommended effect the script also shows the config's full library with
# BIC re-selection (what merging only {"effects": [...]} into the config would do). The issue's
# requirement: every recommended effect lowers the test RMSE; when none is recommended,
# diagnose names what is outside its catalogue (its conclusion).
# Timing: /usr/bin/time -v bench/diagnose_silverbox.sh (diagnose's own stages: diagnose.log).
#   bench/diagnose_silverbox.sh            outputs in build/silverbox_diagnose/
#   INPUT=zoh bench/diagnose_silverbox.sh  the likelihood fitted with a zero-order-hold input (the
#                                          interpolation diagnose's filter applies until it reads
#                                          the model's; default: the config's band_limited)
set -euo pipefail
# shellcheck source=../scripts/lib/tools.sh
source "$(dirname "$0")/../scripts/lib/tools.sh"
out="$build/silverbox_diagnose${INPUT:+_$INPUT}"
mkdir -p "$out"
need_tools identify-vehs simulate-vehs diagnose-vehs
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
rec = set(d.get("recommended", []))
names = [e["effect"] for e in d.get("confirmation", {}).get("effects", [])] or list(rec)
for n in names: print(n, "recommended" if n in rec else "not_confirmed")
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
c = d.get("confirmation", {})
if c.get("ran"):
    print("confirmation:", c.get("criterion"))
    print(f"  baseline held-out log L {c.get('baseline_loglik')}, free-run RMSE {c.get('baseline_rmse')}")
    for e in c.get("effects", []): print(f"  {e['effect']:28s} {e['reason']}")
    print("  residuals:", c.get("residuals", {}).get("summary"))
elif c.get("note"): print("confirmation:", c["note"])
print("recommended:", ", ".join(d.get("recommended", [])) or "none")
print("conclusion:", d.get("conclusion"))
PY
echo "free-run RMSE (mV after 50 samples): $(python3 -c 'import json; print(", ".join(s["name"] for s in json.load(open("data/silverbox/validate.json"))["validate"]["segments"]))')"
echo "  model as fitted: $(rmse "$out/validation.json")"
[ ${#effects[@]} -eq 0 ] && echo "  no effect refitted"
# the model's own support (what diagnose refitted) and its likelihood settings without selection
support=(--set "drift_library=$(python3 -c 'import json, sys; print(json.dumps(list(json.load(open(sys.argv[1]))["drift"])))' "$out/model.json")"
         --set "diffusion_library=$(python3 -c 'import json, sys; print(json.dumps(list(json.load(open(sys.argv[1]))["diffusion"])))' "$out/model.json")"
         --set "likelihood=$(python3 -c 'import json, sys; l = json.load(open(sys.argv[1]))["likelihood"]; l["select"] = False; print(json.dumps(l))' data/silverbox/identify.json)")
if [ -n "${INPUT:-}" ]; then support[5]="likelihood={\"input\": \"$INPUT\", \"covariance\": \"fisher\", \"select\": false}"; fi
refit() {  # effect label file-suffix identify-args...
  local e=$1 label=$2 f="$out/model_$1$3"; shift 3
  "$build/identify-vehs" data/silverbox/identify.json --set "output=\"$f.json\"" "$@" \
    --set "effects=[\"$e\"]" >"$f.txt" 2>"$f.log" || { echo "  + $e ($label): identify failed: $(tail -1 "$f.log")"; return; }
  if validate "$f.json" "$f.validation.json"; then
    echo "  + $e ($label): $(rmse "$f.validation.json")"
  else
    echo "  + $e ($label): validation failed: $(tail -1 "$f.validation.json.log")"
  fi
}
for line in "${effects[@]}"; do
  e=${line% *}; status=${line#* }
  refit "$e" "$status" "" "${support[@]}"
  if [ "$status" = recommended ]; then refit "$e" "$status; the config's library, BIC re-selection" "_reselected" "${lik[@]}"; fi
done
