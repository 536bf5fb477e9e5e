#!/usr/bin/env bash
# Worked example of finding missing physics (README, "Finding the missing physics"):
#   1. measurements of a bistable harvester whose guide has dry friction (the hidden effect;
#      data/missing_physics/truth.json is read only by the simulator)
#   2. baseline fit with the paper's dictionaries          (identify_v1.json   -> model_v1.json)
#   3. diagnosis: verdict, score, ranked suspects          (diagnose_v1.json   -> report/)
#   4. the one-line config change suggested by the top suspect: "effects": ["coulomb_friction"]
#   5. refit                                                (identify_v2.json -> model_v2.json)
#   6. diagnosis again: the score falls, the history plot shows it (report/index.html)
# Builds first (installing what is missing). Outputs go to out/missing_physics/.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh" simulate-vehs identify-vehs diagnose-vehs vehs-compare >/dev/null
cd "$root"
bin="$root/build"
d=data/missing_physics
o=out/missing_physics
rm -rf "$o" && mkdir -p "$o"
step() { printf '\n== %s\n' "$*" >&2; }
step "measurements: 100 records x 500 time units, dt = 0.01, a continuous process (20 substeps)"
"$bin/simulate-vehs" -q $d/simulate.json
step "baseline fit with the paper's dictionaries ($d/identify_v1.json)"
"$bin/identify-vehs" -q $d/identify_v1.json
step "diagnosis of the baseline ($d/diagnose_v1.json)"
"$bin/diagnose-vehs" $d/diagnose_v1.json
step "the top suspect's 'add' fragment, merged into the identify config:"
python3 - <<'PY' 2>/dev/null || true
import json
d = json.load(open("out/missing_physics/diagnosis_v1.json"))
print("   ", json.dumps(d["suspects"][0]["add"]) if d.get("suspects") else "(no suspect)")
PY
diff $d/identify_v1.json $d/identify_v2.json || true
step "refit with the effect ($d/identify_v2.json)"
"$bin/identify-vehs" -q $d/identify_v2.json
step "diagnosis of the refit ($d/diagnose_v2.json)"
"$bin/diagnose-vehs" $d/diagnose_v2.json
step "learned vs true (the truth is the simulator's; the fits never saw it)"
"$bin/vehs-compare" $d/compare_v1.json
"$bin/vehs-compare" $d/compare_v2.json
step "report with the score over model versions: $o/report/index.html"
