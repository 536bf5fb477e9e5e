#!/usr/bin/env python3
"""Mean power of a driven rig with a standard error, against the truth, over seeds (issue 35).

The rig is bench/driven_harvester.py's (a bistable harvester on a shaker, integrated by numpy's
stochastic Heun scheme, not by vehs): 6 records of 4000 samples (dt 0.1) of x with the base
acceleration u, in "mm" and "s", with an electrical damping c_e = CE N s/m. Per seed:
identify-vehs with its defaults (only the data and units given), then simulate-vehs replays each
record's u through the fitted model (statistics with "parameters": true) and reports the mean
power in W with its standard error. The truth is the true rig's power, c_e E[Y^2] of a long
independent numpy simulation (many paths, stationary drive). Coverage: |P - truth| <= 1.96 SE.

Usage: driven_power_coverage.py [--seeds 20] [--first 1] [--keep DIR] [--truth-paths 4000]
Prints one row per seed and the coverage."""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from driven_harvester import BETA, DT, G, OMEGA_A, TWO_D, ZETA_A, records  # noqa: E402

CE = 0.05  # electrical damping [N s/m]
UNITS = {"length": "mm", "time": "s"}
WATTS_PER_EYY = CE * 1e-6  # (mm/s)^2 -> (m/s)^2


def true_eyy(paths, seconds, burn, h, seed=12345):
    """E[Y^2] of the rig in its stationary state (drive included) by the stochastic Heun scheme
    over `paths` independent paths, with its standard error from the spread of the path means."""
    rng = np.random.default_rng(seed)
    x, y, a, da = rng.choice([-1.0, 1.0], paths), np.zeros(paths), np.zeros(paths), np.zeros(paths)
    sy, sa = np.sqrt(TWO_D * h), 3.0 * OMEGA_A ** 1.5 * np.sqrt(h)

    def f(x, y, a, da):
        return y, -BETA * y + x - x ** 3 + G * a, da, -2 * ZETA_A * OMEGA_A * da - OMEGA_A ** 2 * a

    acc, count = np.zeros(paths), 0
    for k in range(int(round((burn + seconds) / h))):
        wy, wa = sy * rng.standard_normal(paths), sa * rng.standard_normal(paths)
        f0 = f(x, y, a, da)
        p = (x + h * f0[0], y + h * f0[1] + wy, a + h * f0[2], da + h * f0[3] + wa)
        f1 = f(*p)
        x, y = x + 0.5 * h * (f0[0] + f1[0]), y + 0.5 * h * (f0[1] + f1[1]) + wy
        a, da = a + 0.5 * h * (f0[2] + f1[2]), da + 0.5 * h * (f0[3] + f1[3]) + wa
        if k * h >= burn:
            acc += y * y
            count += 1
    means = acc / count
    return means.mean(), means.std(ddof=1) / np.sqrt(paths)


def truth(args, results):
    cache = os.path.join(results, "driven_power_truth.json")
    if os.path.exists(cache):
        return json.load(open(cache))
    eyy, se = true_eyy(args.truth_paths, 200.0, 50.0, 0.01)
    eyy_half, se_half = true_eyy(args.truth_paths // 4, 200.0, 50.0, 0.005, seed=54321)
    t = {"E[Y^2]": eyy, "stderr": se, "h": 0.01, "check_h_0.005": [eyy_half, se_half], "paths": args.truth_paths,
         "seconds": 200.0, "burn": 50.0, "watts": WATTS_PER_EYY * eyy}
    json.dump(t, open(cache, "w"), indent=1)
    return t


def one_seed(seed, work, build):
    rng = np.random.default_rng(seed)
    xs, us = records(rng, 6, 4000)
    files = []
    for r, (x, u) in enumerate(zip(xs, us)):
        f = os.path.join(work, f"seed{seed}_run{r}.csv")
        np.savetxt(f, np.column_stack([DT * np.arange(len(x)), x, u]), delimiter=",", header="t,x,u", comments="",
                   fmt="%.7g")
        files.append(f)
    model = os.path.join(work, f"model{seed}.json")
    cfg = os.path.join(work, f"identify{seed}.json")
    json.dump({"data": files, "units": UNITS, "output": model}, open(cfg, "w"))
    subprocess.run([os.path.join(build, "identify-vehs"), cfg, "-q"], check=True)
    drive = os.path.join(work, f"drive{seed}.csv")
    n = xs.shape[1]
    rows = [np.column_stack([np.full(n, r), DT * np.arange(n), us[r]]) for r in range(len(us))]
    np.savetxt(drive, np.vstack(rows), delimiter=",", header="traj,t,u", comments="", fmt="%.7g")
    stats = os.path.join(work, f"power{seed}.json")
    cfg = os.path.join(work, f"simulate{seed}.json")
    json.dump({"model": model, "drive": {"path": drive}, "trajectories": len(us), "duration": n * DT, "dt": DT,
               "substeps": 10, "x0": [float(x[0]) for x in xs], "y0": 0.0, "seed": seed,
               "harvester": {"electrical_damping": CE},
               "statistics": {"output": stats, "parameters": True}}, open(cfg, "w"))
    subprocess.run([os.path.join(build, "simulate-vehs"), cfg, "-q"], check=True)
    return json.load(open(stats))["mean_power"], json.load(open(model))["estimator"].get("input", "?")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--seeds", type=int, default=20)
    p.add_argument("--first", type=int, default=1)
    p.add_argument("--keep")
    p.add_argument("--truth-paths", type=int, default=4000)
    args = p.parse_args()
    here = os.path.dirname(os.path.abspath(__file__))
    build = os.environ.get("VEHS_BIN_DIR", os.path.join(here, "..", "build"))
    work = args.keep or tempfile.mkdtemp(prefix="vehs-power-")
    os.makedirs(work, exist_ok=True)
    t = truth(args, os.path.join(here, "results"))
    print(f"truth: E[Y^2] = {t['E[Y^2]']:.5g} ± {t['stderr']:.2g} (mm/s)^2 (h 0.01; h 0.005: "
          f"{t['check_h_0.005'][0]:.5g} ± {t['check_h_0.005'][1]:.2g}), P = {t['watts']:.5g} W")
    print("seed  P [W]        SE [W]     MC SE      param SE   z      covered")
    zs = []
    for seed in range(args.first, args.first + args.seeds):
        mp, _ = one_seed(seed, work, build)
        z = (mp["watts"] - t["watts"]) / mp["stderr"]
        zs.append(z)
        print(f"{seed:4d}  {mp['watts']:.4e}  {mp['stderr']:.3e}  {mp['monte_carlo_stderr']:.3e}  "
              f"{mp['parameter_stderr']:.3e}  {z:+.2f}  {'yes' if abs(z) <= 1.96 else 'NO'}", flush=True)
    zs = np.array(zs)
    print(f"covered (|z| <= 1.96) in {int(np.sum(np.abs(zs) <= 1.96))}/{len(zs)} seeds; mean z {zs.mean():+.2f}, "
          f"sd z {zs.std(ddof=1):.2f}; error method: {mp['error_method']}")


if __name__ == "__main__":
    sys.exit(main())
