#!/usr/bin/env python3
"""identify's moment fit on pentastable records with a y^2 diffusion (issue 13, the
velocity_dependent_noise loop; bench/results/diagnose_calibration_log.md): rare velocity bursts carry x into the x^9
wall, where the ULI lens's expansion in h does not hold (omega*h up to ~10). Over seeds, the true
library's estimates of beta, 2D, q_y2 and the x^7, x^9 coefficients as z against the truth
(mean, sd, worst seed), the rows the fit left out, and diagnose's verdict on the fitted model
(an error, e.g. twins that diverge, counts as inadequate). Records as
bench/sampling_rule_state_dependent.py draws them.
  build/python-venv/bin/python bench/identify_wall_rows.py [SEEDS [SEED0 [DIAGNOSED]]]
(the vehs package built by scripts/test.sh; diagnose on the first DIAGNOSED seeds only, all by
default: 15–60 CPU s a diagnosed seed, 0.2 s otherwise).
  build/python-venv/bin/python bench/identify_wall_rows.py time
(identify's CPU seconds a fit on seed 202's records, one thread: 0.038 on main, 0.058 with the
rows beyond the lens left out, 24 Nov 2026 at load 10)."""
import sys
import time

import numpy as np
import vehs
from sampling_rule_state_dependent import DIFF, PENTA, records

# (name, section, term, sign): beta = -drift[y]
PARAMS = [("beta", "drift", "y", -1.0), ("2D", "diffusion", "1", 1.0), ("q_y2", "diffusion", "y^2", 1.0),
          ("x^7", "drift", "x^7", 1.0), ("x^9", "drift", "x^9", 1.0)]
TRUTH = {"drift": PENTA, "diffusion": DIFF}


def one(seed, diagnosed):
    r = records(seed)
    model, report = vehs.identify(r, sparsity="none", drift_library=list(PENTA), diffusion_library=list(DIFF))
    d = model.to_dict()
    z = {n: (d[s][t] - TRUTH[s][t]) / d["stderr"][s][t] for n, s, t, _ in PARAMS}
    est = {n: sign * d[s][t] for n, s, t, sign in PARAMS}
    left_out = d["fit"].get("rows_left_out", 0)
    if not diagnosed:
        return z, est, left_out, "-"
    try:
        verdict = vehs.diagnose(model, r).verdict
    except vehs.Error as e:
        verdict = "error: " + str(e)[:60]
    return z, est, left_out, verdict


def timing():
    vehs.set_threads(1)
    r = records(202)
    t = time.process_time()
    for _ in range(10):
        vehs.identify(r, sparsity="none", drift_library=list(PENTA), diffusion_library=list(DIFF))
    print(f"identify, 32 x 4000, true library: {(time.process_time() - t) / 10:.3f} CPU s a fit")


def main():
    if sys.argv[1:2] == ["time"]:
        return timing()
    seeds = int(sys.argv[1]) if len(sys.argv) > 1 else 60
    seed0 = int(sys.argv[2]) if len(sys.argv) > 2 else 200
    diagnosed = int(sys.argv[3]) if len(sys.argv) > 3 else seeds
    zs, adequate = [], 0
    for seed in range(seed0, seed0 + seeds):
        z, est, left_out, verdict = one(seed, seed < seed0 + diagnosed)
        zs.append([z[n] for n, *_ in PARAMS])
        adequate += verdict == "adequate"
        print(f"seed {seed}: " + " ".join(f"{n} {est[n]:.4g} (z {z[n]:+.2f})" for n, *_ in PARAMS) +
              f"  left out {left_out}  {verdict}", flush=True)
    zs = np.array(zs)
    for i, (n, *_) in enumerate(PARAMS):
        worst = int(np.argmax(np.abs(zs[:, i])))
        print(f"{n}: z mean {zs[:, i].mean():+.3f} sd {zs[:, i].std():.3f}, worst {zs[worst, i]:+.2f} (seed {seed0 + worst}), "
              f"|z| > 5 in {int((np.abs(zs[:, i]) > 5).sum())}")
    print(f"diagnose: adequate {adequate} of {min(diagnosed, seeds)}")


if __name__ == "__main__":
    main()
