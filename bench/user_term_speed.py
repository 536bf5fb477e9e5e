#!/usr/bin/env python3
"""The price of writing a force as a user's expression instead of the catalogue's term: Coulomb
friction as the built-in "sign(y)" and as the expression "(y>0)-(y<0)" (the same function), fitted
by identify-vehs's likelihood on the same records, and simulate-vehs's speed with each.

The rig (stochastic Heun at 50 substeps per sample, not vehs's simulator): x'' = -k x - c x' -
mu sign(x') + sqrt(2D) xi, k 987 1/s^2, c 3 1/s, mu 0.25 m/s^2, 2D 6e-3 m^2/s^3; 40 samples per
period, 1 % sensor noise; 4000 samples in metres and seconds.

Usage: user_term_speed.py [--samples 4000] [--seed 1]
Prints, for each form, the fitted friction and its SE, the fit's seconds, and the ratio."""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

K, C, MU, TWO_D, DT, SUB, NOISE = 987.0, 3.0, 0.25, 6e-3, 5e-3, 50, 1e-5


def record(rng, n):
    h = DT / SUB
    x, y = 1e-3, 0.0

    def acc(x, y):
        return -K * x - C * y - MU * np.sign(y)

    xs = np.empty(n)
    for k in range(-2000, n):
        if k >= 0:
            xs[k] = x
        for _ in range(SUB):
            dw = np.sqrt(TWO_D * h) * rng.standard_normal()
            a0 = acc(x, y)
            xp, yp = x + h * y, y + h * a0 + dw
            x, y = x + 0.5 * h * (y + yp), y + 0.5 * h * (a0 + acc(xp, yp)) + dw
    return xs + NOISE * rng.standard_normal(n)


def fit(build, work, csv, friction):
    out = os.path.join(work, f"model_{len(friction)}.json")
    cfg = os.path.join(work, f"identify_{len(friction)}.json")
    json.dump({"data": csv, "units": {"length": "m", "time": "s"}, "drift_library": ["x", "y", friction],
               "diffusion_library": ["1"], "sparsity": "none", "likelihood": {"use": "always", "select": False},
               "output": out}, open(cfg, "w"))
    t0 = time.perf_counter()
    proc = subprocess.run([os.path.join(build, "identify-vehs"), cfg, "-q"], capture_output=True, text=True)
    seconds = time.perf_counter() - t0
    if proc.returncode != 0:
        sys.exit(f"identify-vehs failed on {friction}: {proc.stderr.strip()}")
    m = json.load(open(out))
    return m["drift"][friction], m["stderr"]["drift"][friction], seconds


def simulate(build, work, friction):
    """simulate-vehs's steps per second on the model with `friction`, best of three runs."""
    model = os.path.join(work, f"sim_model_{len(friction)}.json")
    json.dump({"drift": {"x": -K, "y": -C, friction: -MU}, "diffusion": {"1": TWO_D}},
              open(model, "w"))
    cfg = os.path.join(work, f"simulate_{len(friction)}.json")
    summary = os.path.join(work, f"summary_{len(friction)}.json")
    json.dump({"model": model, "trajectories": 64, "duration": 200.0, "dt": 1e-3, "scheme": "rk4_euler",
               "seed": 1, "x0": 0, "y0": 0, "output": os.path.join(work, f"sim_{len(friction)}.npy"),
               "summary": summary}, open(cfg, "w"))
    best = 0.0
    for _ in range(3):
        proc = subprocess.run([os.path.join(build, "simulate-vehs"), cfg, "-q"], capture_output=True, text=True)
        if proc.returncode != 0:
            sys.exit(f"simulate-vehs failed on {friction}: {proc.stderr.strip()}")
        best = max(best, json.load(open(summary))["steps_per_second"])
    return best


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--samples", type=int, default=4000)
    p.add_argument("--seed", type=int, default=1)
    args = p.parse_args()
    build = os.environ.get("VEHS_BIN_DIR", os.path.join(os.path.dirname(__file__), "..", "build"))
    work = tempfile.mkdtemp(prefix="vehs-user-speed-")
    csv = os.path.join(work, "rig.csv")
    x = record(np.random.default_rng(args.seed), args.samples)
    np.savetxt(csv, np.column_stack([DT * np.arange(len(x)), x]), delimiter=",", header="t,x", comments="",
               fmt="%.7g")
    rows = []
    for form in ("sign(y)", "(y>0)-(y<0)"):
        est, se, seconds = fit(build, work, csv, form)
        rows.append(seconds)
        print(f"{form:>14}: friction {-est:.4f} +- {se:.4f} m/s^2 (truth {MU}, z {(-est - MU) / se:+.2f}), "
              f"identify-vehs {seconds:.1f} s")
    print(f"likelihood fit with the expression / with the built-in term: {rows[1] / rows[0]:.2f}x")
    speed = [simulate(build, work, form) for form in ("sign(y)", "(y>0)-(y<0)")]
    print(f"simulate-vehs: {speed[0] / 1e6:.1f} M steps/s built in, {speed[1] / 1e6:.1f} M steps/s with the "
          f"expression: {speed[0] / speed[1]:.2f}x")


if __name__ == "__main__":
    sys.exit(main())
