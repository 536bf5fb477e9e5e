#!/usr/bin/env python3
"""Writes examples/user_effect/rig.csv, the logger file of README's "your own effect" example: a
linear guide on a spring whose friction differs by direction, position in metres logged at 200 Hz
with 1 % sensor noise, time in seconds.

The rig (SI units, 50 Euler-Maruyama substeps per logged sample; vehs never sees these numbers or
this code):
    x'' = -k x - c y - Fp 1(y>0) + Fm 1(y<0) - dc y 1(y<0) + white noise of intensity 2D,
k = 987 1/s^2 (5 Hz), c = 2 1/s, Fp = 0.30 m/s^2 forward, Fm = 0.15 m/s^2 backward, dc = 4 1/s
(the backward damping c + dc = 6 1/s), 2D = 0.05 m^2/s^3 (rms x about 2 mm).

usage: make_rig_csv.py OUTPUT.csv [samples]   (standard library only; seed fixed)
"""
import math
import os
import random
import sys

out = sys.argv[1]
samples = int(sys.argv[2]) if len(sys.argv) > 2 else 20000
fs, sub = 200.0, 50
h = 1.0 / fs / sub
k, c, fp, fm, dc, two_d = 987.0, 2.0, 0.30, 0.15, 4.0, 0.05
rng = random.Random(7)
sq = math.sqrt(two_d * h)


def force(x, y):
    if y > 0:
        return -k * x - c * y - fp
    if y < 0:
        return -k * x - (c + dc) * y + fm
    return -k * x


x, y = 0.0, 0.0
xs = []
for i in range(-1000, samples):
    if i >= 0:
        xs.append(x)
    for _ in range(sub):
        a = force(x, y)
        x, y = x + h * y, y + h * a + sq * rng.gauss(0.0, 1.0)
mean = sum(xs) / len(xs)
sd = math.sqrt(sum((v - mean) ** 2 for v in xs) / len(xs))
os.makedirs(os.path.dirname(out) or ".", exist_ok=True)
with open(out, "w") as f:
    f.write("time_s,position_m\n")
    for i, v in enumerate(xs):
        f.write(f"{i / fs:.4f},{v + 0.01 * sd * rng.gauss(0.0, 1.0):.9g}\n")
