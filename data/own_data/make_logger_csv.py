#!/usr/bin/env python3
"""Writes the example logger file of README's "Your own data" section, the way a data logger
writes one: '#' comment lines, ';' delimiters, a time column in seconds with 6 decimals and
+-0.2 ms jitter, the displacement in mm, the shaker's base acceleration in m/s^2, a 2 s gap
(buffer overflow) and a sensor dropout (a run of NaN / empty fields).

The harvester (SI units, integrated here with 20 Euler-Maruyama substeps per logged sample; vehs
never sees these numbers or this code): a bistable beam with wells at +-2 mm,
    x'' = -beta x' + k1 x - k3 x^3 + a(t),
beta = 3.14 1/s, k1 = 987 1/s^2, k3 = 2.47e8 1/(m^2 s^2); the base acceleration a(t) is broadband
(correlation time 1 ms, far below the 3.3 ms logging interval), so the harvester sees it as
white noise of intensity 2D = 2.07e-3 m^2/s^3; the logger samples it at 300 Hz.
In the logged units (mm, s): k1 = 987, k3 = 247 1/(mm^2 s^2), 2D = 2070 mm^2/s^3.

usage: make_logger_csv.py OUTPUT.csv [seconds]   (standard library only; seed fixed)
"""
import math
import random
import sys

out = sys.argv[1]
seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 600.0
fs = 300.0
sub = 20
dt = 1.0 / fs / sub
beta, k1, k3, two_d = 3.14, 987.0, 2.47e8, 2.07e-3
rng = random.Random(20261124)
x, v = 2e-3, 0.0
n = int(seconds * fs)
gap = (int(200 * fs), int(202 * fs))         # 2 s lost
dropout = (int(400 * fs), int(400 * fs) + 7)  # 7 samples: NaN, then empty fields
sd = math.sqrt(two_d * dt)
with open(out, "w", newline="") as f:
    f.write("# LabLogger 4.2 export\r\n# channel 1: laser displacement sensor, mm\r\n")
    f.write("# channel 2: base accelerometer, m/s^2\r\n# sample rate: 300 Hz\r\n")
    f.write('"time_s";"disp_mm";"base_acc"\r\n')
    for i in range(n):
        acc_sum = 0.0
        for _ in range(sub):
            kick = rng.gauss(0.0, sd)
            acc_sum += kick / dt
            v += (-beta * v + k1 * x - k3 * x ** 3) * dt + kick
            x += v * dt
        if gap[0] <= i < gap[1]:
            continue
        t = i / fs + rng.uniform(-2e-4, 2e-4)
        if dropout[0] <= i < dropout[1]:
            disp = "NaN" if i == dropout[0] else ""
        else:
            disp = "%.5f" % (1e3 * x)
        f.write("%.6f;%s;%.4f\r\n" % (t, disp, acc_sum / sub))
