#!/usr/bin/env bash
# identify-vehs end to end on 10^6 samples where the likelihood refines the moment fit (README,
# "Real rigs", Round 12): a Duffing (b2 = -x - x^3 - 0.1 y, a22 = 0.2) sampled at dt 0.3
# (omega*dt ~ 0.43, continuous-time records by Ito-Taylor 1.5 on 30 substeps), 10 records of
# 10^5 samples; the moment fit, the likelihood with forward and backward selection. Prints the
# wall and CPU time with the load average.
#   bench/identify_million.sh        (outputs in build/identify_million/)
set -euo pipefail
# shellcheck source=../scripts/lib/tools.sh
source "$(dirname "$0")/../scripts/lib/tools.sh"
out="$build/identify_million"
mkdir -p "$out"
need_tools simulate-vehs identify-vehs
cd "$out"
echo '{"drift": {"x": -1.0, "x^3": -1.0, "y": -0.1}, "diffusion": {"1": 0.2}}' >model.json
echo '{"model": "model.json", "trajectories": 10, "duration": 30000, "dt": 0.3, "substeps": 30, "scheme": "taylor15",
 "x0": {"uniform": [-1, 1]}, "burn_in": 50, "output": "records.csv"}' >simulate.json
echo '{"data": ["records.csv"], "output": "identified.json"}' >identify.json
[ -s records.csv ] || "$build/simulate-vehs" simulate.json -q
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
/usr/bin/time -f "identify-vehs on 10^6 samples: %e s wall, %U s user + %S s sys CPU, %M kB peak" \
  "$build/identify-vehs" identify.json -q
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
python3 -c 'import json; m = json.load(open("identified.json")); print("drift", m["drift"], "diffusion", m["diffusion"]); print("likelihood used:", m["estimator"]["sampling_adequacy"]["likelihood"])'
