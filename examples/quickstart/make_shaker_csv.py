#!/usr/bin/env python3
"""Writes examples/quickstart/shaker.csv, the logger file of README's quickstart: a bistable beam
on a shaker, tip displacement in mm and base acceleration in m/s^2 logged at 500 Hz, written the
way a data logger writes it ('#' comment lines, ';' delimiters, quoted names, time in seconds).

The harvester (SI units, 20 Euler-Maruyama substeps per logged sample; vehs never sees these
numbers or this code):
    x'' = -beta x' + k1 x - k3 x^3 - mu sign(x') + g a(t) + white noise of intensity 2D,
beta = 4 1/s, k1 = 400 1/s^2, k3 = 1e8 1/(m^2 s^2) (wells at +-2 mm), mu = 0.3 m/s^2 (clamp
friction), g = 1; a(t) is the recorded base acceleration, a smooth broadband signal (a sum of
sines between 5 and 40 Hz, amplitude 1 m/s^2); 2D = 1e-3 m^2/s^3.
In the logged units (mm, s): k1 = 400, k3 = 100 1/(mm^2 s^2), mu = 300 mm/s^2, 2D = 1000 mm^2/s^3.

usage: make_shaker_csv.py OUTPUT.csv [seconds]   (standard library only; seed fixed)
"""
import math
import random
import sys

out = sys.argv[1]
seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 10.0
fs, sub = 500.0, 20
dt = 1.0 / fs / sub
beta, k1, k3, mu, gain, two_d = 4.0, 400.0, 1e8, 0.3, 1.0, 1e-3
rng = random.Random(35)
lines = [(5.0 + 35.0 * rng.random(), 2 * math.pi * rng.random()) for _ in range(24)]
amp = 1.0 * math.sqrt(2.0 / len(lines))


def base_acc(t):
    return amp * sum(math.sin(2 * math.pi * f * t + p) for f, p in lines)


x, v = 2e-3, 0.0
sd = math.sqrt(two_d * dt)
with open(out, "w", newline="") as f:
    f.write("# LabLogger 4.2 export\r\n# channel 1: laser displacement sensor, mm\r\n")
    f.write("# channel 2: base accelerometer, m/s^2\r\n# sample rate: 500 Hz\r\n")
    f.write('"time_s";"disp_mm";"base_acc"\r\n')
    for i in range(int(seconds * fs)):
        t = i / fs
        f.write("%.6f;%.5f;%.4f\r\n" % (t, 1e3 * x, base_acc(t)))
        for s in range(sub):
            a = base_acc(t + s * dt)
            fric = mu * (1.0 if v > 0 else -1.0 if v < 0 else 0.0)
            v += (-beta * v + k1 * x - k3 * x ** 3 - fric + gain * a) * dt + rng.gauss(0.0, sd)
            x += v * dt
