#!/usr/bin/env python3
"""A ball-screw positioning axis under closed-loop control (issue 33's rig), simulated from
continuous time: m x'' = F - c x' - Fc sign(x') + F0 + force noise, m 95 kg, c 200 N s/m, Fc 20 N,
F0 -3 N; F from a PD controller at 1 kHz (held between samples, saturated at 400 N) tracking
bang-bang references; the encoder quantised to 0.05 um. Writes t,x,u (u = F in N, x in m) and
prints the truth in identify-vehs's parameters (beta = c/m, mu = Fc/m, drift[1] = F0/m,
drift[u] = 1/m, 2D = (sigma_F/m)^2). RIG_SIGMA_F sets the force noise sigma_F (N/sqrt(Hz),
default 2; 0.05 is the nearly deterministic motion of a real axis).

Usage: positioning_rig.py OUT.csv SEED [--seconds S]
Then:  identify-vehs with {"data": OUT.csv, "drift_library": ["1", "y", "u"],
       "effects": ["coulomb_friction"], "units": {"length": "m", "time": "s", "input": "N"}}"""
import argparse
import numpy as np

M, C, FC, F0 = 95.0, 200.0, 20.0, -3.0
Q = 5e-8          # encoder step (m)
DT = 1e-3         # controller and logger period (s)
SIGMA_F = float(__import__("os").environ.get("RIG_SIGMA_F", "2.0"))  # process force noise (N/sqrt(Hz))


def simulate(seed, seconds, sub=50):
    rng = np.random.default_rng(seed)
    n = int(round(seconds / DT))
    h = DT / sub
    kp, kd = 4.0e5, 9.0e3
    x, v = 0.0, 0.0
    xs, us = np.empty(n), np.empty(n)
    ref, next_switch, x_prev_q = 0.0, 0.0, 0.0
    for k in range(n):
        t = k * DT
        if t >= next_switch:
            ref = rng.choice([-1.0, 1.0]) * rng.uniform(0.002, 0.02)
            next_switch = t + rng.uniform(0.3, 1.2)
        xq = Q * np.round(x / Q)
        vq = (xq - x_prev_q) / DT
        x_prev_q = xq
        f = kp * (ref - xq) - kd * vq
        f = float(np.clip(f, -400.0, 400.0))
        xs[k], us[k] = xq, f
        for _ in range(sub):  # Euler-Maruyama on a fine grid, the force held
            dw = rng.standard_normal() * np.sqrt(h)
            a = (f - C * v - FC * np.sign(v) + F0) / M
            x, v = x + v * h, v + a * h + SIGMA_F / M * dw
    return xs, us


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("seed", type=int)
    ap.add_argument("--seconds", type=float, default=20.0)
    a = ap.parse_args()
    x, u = simulate(a.seed, a.seconds)
    with open(a.out, "w") as f:
        f.write("t,x,u\n")
        for k in range(len(x)):
            f.write(f"{k * DT:.3f},{x[k]:.8e},{u[k]:.6f}\n")
    print("truth: beta", C / M, "mu", FC / M, "offset", F0 / M, "gain", 1 / M, "a22", (SIGMA_F / M) ** 2)


if __name__ == "__main__":
    main()
