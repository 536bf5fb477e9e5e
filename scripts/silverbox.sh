#!/usr/bin/env bash
# The Silverbox table of issue 12 in one command: identify-vehs on the estimation part
# [40650, 105712) (the moment fit refined by maximum likelihood, input band-limited;
# data/silverbox/identify.json), then simulate-vehs's free-run validation on the arrow, its first
# 32000 samples and the multisine test (data/silverbox/validate.json), RMSE in mV after 50
# samples. With the optional venv of bench/likelihood.sh (build/bench-venv with SysIdentPy) the
# best polynomial NARX of that benchmark's grid is refitted on the same split for a second column.
#   scripts/silverbox.sh            outputs in build/silverbox/ (model.json, validation.json,
#                                   validation_series.csv, validation.svg with gnuplot)
set -euo pipefail
# shellcheck source=lib/tools.sh
source "$(dirname "$0")/lib/tools.sh"
out="$build/silverbox"
mkdir -p "$out"
need_tools identify-vehs simulate-vehs
cd "$root"
"$build/identify-vehs" data/silverbox/identify.json --set "output=\"$out/model.json\"" >"$out/identify.txt" 2>"$out/identify.log" ||
  { tail -1 "$out/identify.log" >&2; exit 1; }
python3 -c 'import json, sys
c = json.load(open("data/silverbox/validate.json"))
c["model"] = sys.argv[1] + "/model.json"; c["validate"]["output"] = sys.argv[1] + "/validation.json"
json.dump(c, open(sys.argv[1] + "/validate.json", "w"), indent=1)' "$out"
"$build/simulate-vehs" "$out/validate.json" -q >/dev/null
narx=()
venv="$build/bench-venv"
if [ -x "$venv/bin/python" ] && "$venv/bin/python" -c "import sysidentpy" 2>/dev/null; then
  mapfile -t narx < <("$venv/bin/python" bench/silverbox_narx.py data/silverbox/SNLS80mV.csv --best |
                      awk '/ mV$/ {print $(NF-1)}')
fi
python3 - "$out/validation.json" "$out/model.json" "${narx[@]}" <<'PY'
import json, sys
v = json.load(open(sys.argv[1])); m = json.load(open(sys.argv[2])); narx = sys.argv[3:]
terms = [t for t, c in m["drift"].items() if c != 0]
print(f"Silverbox, free-run RMSE after {v['skip']} samples, mV (output rms on the arrow "
      f"{1e3 * v['segments'][0]['measured_rms']:.1f} mV)")
head = f"{'segment':26s} {'vehs':>8s}" + (f" {'NARX':>8s}" if narx else "")
print(head)
for i, s in enumerate(v["segments"]):
    print(f"{s['name']:26s} {1e3 * s['rmse']:8.3f}" + (f" {float(narx[i]):8.3f}" if i < len(narx) else ""))
lik = m.get("likelihood", {})
print(f"vehs: {len(terms)} drift terms ({', '.join(terms)}), a22 = {m['diffusion']}, input "
      f"{m['estimator'].get('input', 'zoh')}, log L {lik.get('log_likelihood', float('nan')):.1f}")
if narx:
    print("NARX: SysIdentPy FROLS, lags 4/4, degree 3, 10 terms (the grid winner of bench/likelihood.sh narx)")
PY
