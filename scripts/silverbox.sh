#!/usr/bin/env bash
# The Silverbox table of issue 12 in one command: identify-vehs on the estimation part
# [40650, 105712) (the moment fit refined by maximum likelihood, input band-limited;
# data/silverbox/identify.json), then simulate-vehs's free-run validation on the arrow, its first
# 32000 samples and the multisine test (data/silverbox/validate.json), RMSE in mV after 50
# samples; beside it the same with identify-vehs's defaults (data/silverbox/identify_defaults.json:
# only the data, columns, dt, samples and units; validated without detrending, as it was fitted). With the optional venv of bench/likelihood.sh (build/bench-venv with SysIdentPy) the
# best polynomial NARX of that benchmark's grid is refitted on the same split for a second column.
#   scripts/silverbox.sh            outputs in build/silverbox/ (model.json, validation.json,
#                                   validation_series.csv, validation.svg with gnuplot;
#                                   model_defaults.json, validation_defaults.json)
set -euo pipefail
# shellcheck source=lib/tools.sh
source "$(dirname "$0")/lib/tools.sh"
out="$build/silverbox"
mkdir -p "$out"
need_tools identify-vehs simulate-vehs
cd "$root"
# the tuned config, then the defaults (identify_defaults.json: data, columns, dt, samples, units)
for run in "model identify" "model_defaults identify_defaults"; do
  read -r model cfg <<<"$run"
  "$build/identify-vehs" "data/silverbox/$cfg.json" --set "output=\"$out/$model.json\"" >"$out/$cfg.txt" 2>"$out/$cfg.log" ||
    { tail -1 "$out/$cfg.log" >&2; exit 1; }
  # validated as the model was fitted: validate.json's detrend is the tuned fit's, the defaults keep the offsets
  python3 -c 'import json, sys
c = json.load(open("data/silverbox/validate.json")); m = json.load(open(sys.argv[1] + "/" + sys.argv[2] + ".json"))
c["model"] = sys.argv[1] + "/" + sys.argv[2] + ".json"
c["validate"]["detrend"] = m["data"]["detrend"]
if sys.argv[2] != "model":
    c["validate"]["figure"] = False
    c["validate"]["output"] = sys.argv[1] + "/validation_defaults.json"
else:
    c["validate"]["output"] = sys.argv[1] + "/validation.json"
json.dump(c, open(sys.argv[1] + "/validate_" + sys.argv[2] + ".json", "w"), indent=1)' "$out" "$model"
  "$build/simulate-vehs" "$out/validate_$model.json" -q >/dev/null
done
narx=()
venv="$build/bench-venv"
if [ -x "$venv/bin/python" ] && "$venv/bin/python" -c "import sysidentpy" 2>/dev/null; then
  mapfile -t narx < <("$venv/bin/python" bench/silverbox_narx.py data/silverbox/SNLS80mV.csv --best |
                      awk '/ mV$/ {print $(NF-1)}')
fi
python3 - "$out" "${narx[@]}" <<'PY'
import json, sys
out, narx = sys.argv[1], sys.argv[2:]
runs = [("tuned", "validation", "model"), ("defaults", "validation_defaults", "model_defaults")]
v = {k: json.load(open(f"{out}/{val}.json")) for k, val, _ in runs}
m = {k: json.load(open(f"{out}/{mod}.json")) for k, _, mod in runs}
t = v["tuned"]
print(f"Silverbox, free-run RMSE after {t['skip']} samples, mV (output rms on the arrow "
      f"{1e3 * t['segments'][0]['measured_rms']:.1f} mV)")
print(f"{'segment':26s} {'tuned':>8s} {'defaults':>8s}" + (f" {'NARX':>8s}" if narx else ""))
for i, s in enumerate(t["segments"]):
    print(f"{s['name']:26s} {1e3 * s['rmse']:8.3f} {1e3 * v['defaults']['segments'][i]['rmse']:8.3f}" +
          (f" {float(narx[i]):8.3f}" if i < len(narx) else ""))
for k, cfg in (("tuned", "identify.json"), ("defaults", "identify_defaults.json")):
    mk = m[k]
    terms = [n for n, c in mk["drift"].items() if c != 0]
    lik = mk.get("likelihood", {})
    print(f"{k} (data/silverbox/{cfg}): {len(terms)} drift terms ({', '.join(terms)}), a22 = {mk['diffusion']}, "
          f"input {mk['estimator'].get('input', 'zoh')}, log L {lik.get('log_likelihood', float('nan')):.1f}, "
          f"{mk['fit'].get('in_memory_seconds', float('nan')):.1f} s")
if narx:
    print("NARX: SysIdentPy FROLS, lags 4/4, degree 3, 10 terms (the grid winner of bench/likelihood.sh narx)")
PY
