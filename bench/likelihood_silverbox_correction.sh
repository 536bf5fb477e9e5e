#!/usr/bin/env bash
# Silverbox with and without the likelihood's bias correction (issue 12): identify-vehs on the
# split of scripts/silverbox.sh with likelihood.bias_correction 0 and "auto" (B = 8: the fit
# estimates sensor noise), one thread each, then simulate-vehs's free-run validation. Prints per
# setting the CPU seconds, wall seconds and load of identify, the RMSEs (mV) and the correction's
# record in the model file. Run through `bench/likelihood.sh silverbox_correction`.
set -euo pipefail
# shellcheck source=../scripts/lib/tools.sh
source "$(dirname "$0")/../scripts/lib/tools.sh"
cd "$root"
need_tools identify-vehs simulate-vehs
for setting in 0 '"auto"'; do
  out="$build/silverbox_correction/$(echo "$setting" | tr -d '"')"
  mkdir -p "$out"
  lik="{\"input\": \"band_limited\", \"covariance\": \"fisher\", \"select\": true, \"criterion\": \"bic\", \"bias_correction\": $setting}"
  load="$(cut -d' ' -f1-3 /proc/loadavg)"
  OMP_NUM_THREADS=1 /usr/bin/time -f "%U %S %e" -o "$out/time.txt" "$build/identify-vehs" data/silverbox/identify.json \
    --set "output=\"$out/model.json\"" --set "likelihood=$lik" >"$out/identify.txt" 2>"$out/identify.log"
  python3 -c 'import json, sys
c = json.load(open("data/silverbox/validate.json"))
c["model"] = sys.argv[1] + "/model.json"; c["validate"]["output"] = sys.argv[1] + "/validation.json"; c["validate"]["figure"] = False
json.dump(c, open(sys.argv[1] + "/validate.json", "w"), indent=1)' "$out"
  "$build/simulate-vehs" "$out/validate.json" -q >/dev/null
  python3 - "$out" "$setting" "$load" <<'PY'
import json, sys
o, setting, load = sys.argv[1:4]
user, sys_, wall = (float(v) for v in open(o + "/time.txt").read().split()[-3:])
v = json.load(open(o + "/validation.json")); l = json.load(open(o + "/model.json"))["likelihood"]
rmse = " / ".join(f"{1e3 * s['rmse']:.3f}" for s in v["segments"])
print(f"bias_correction {setting:7s} identify {user + sys_:6.2f} CPU s {wall:7.1f} s wall (load {load}); "
      f"RMSE arrow / first 32000 / multisine test {rmse} mV; bias_correction {json.dumps(l.get('bias_correction'))}")
PY
done
