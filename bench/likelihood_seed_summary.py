#!/usr/bin/env python3
"""Per-parameter summary over the seeds of a `bench_likelihood synthetic` run from its
VEHS_PROGRESS log (stderr), for runs stopped before their own summary or split over processes.

  likelihood_seed_summary.py paper|bistable LOG...

Reads, per seed, either the `z seed S NAME Z rel R` lines (z with the fit's SEs; `z2`: with
VEHS_SECOND_COVARIANCE's; `zu`: the maximum before the bias correction, with its own SEs) or the parameter block printed after each fit (`  NAME VALUE +- SE`,
the last block before the next seed's first fit line; z against the model's truth; the
measurement noise, whose truth varies by seed, is left out). Prints, as the bench does, per
parameter: mean z (+- 1/sqrt(n)), sd of z with its 95 % interval (chi-square, n - 1 degrees of
freedom), mean relative error +- its SE, 95 % coverage.
"""
import math
import re
import sys

TRUTH = {
    "paper": {"drift[x]": -1.0, "drift[x^3]": 7.7, "drift[x^5]": -16.3, "drift[x^7]": 12.5, "drift[x^9]": -3.1,
              "drift[y]": -0.1, "diffusion[1]": 0.02, "diffusion[x^2]": 0.01},
    "bistable": {"drift[x]": 1.0, "drift[x^3]": -1.0, "drift[y]": -0.1, "diffusion[1]": 0.04},
}
Z_LINE = re.compile(r"^z(2?|u) seed (\d+) (\S+) ([-+0-9.eE]+) rel ([-+0-9.eE]+)$")
PARAM_LINE = re.compile(r"^  (\S+)\s+([-+0-9.eE]+) \+-\s+([-+0-9.eE]+)$")


def chi2_quantile(k, p):
    """Wilson-Hilferty (as bench_likelihood.cpp)."""
    z = -1.959964 if p < 0.5 else 1.959964
    c = 2.0 / (9.0 * k)
    return k * (1.0 - c + z * math.sqrt(c)) ** 3


def read(paths, truth):
    first, second, uncorrected = {}, {}, {}  # name -> list of (z, rel)
    for path in paths:
        block, blocks = {}, []
        for line in open(path, encoding="utf-8"):
            line = line.rstrip("\n")
            m = Z_LINE.match(line)
            if m:
                {"": first, "2": second, "u": uncorrected}[m.group(1)].setdefault(m.group(3), []).append((float(m.group(4)), float(m.group(5))))
                continue
            m = PARAM_LINE.match(line)
            if m:
                block[m.group(1)] = (float(m.group(2)), float(m.group(3)))
            elif block:
                blocks.append(block)
                block = {}
        if block:
            blocks.append(block)
        if not any(Z_LINE.match(l) for l in open(path, encoding="utf-8")):
            for b in blocks:
                for name, (value, se) in b.items():
                    if name in truth:
                        first.setdefault(name, []).append(((value - truth[name]) / se, (value - truth[name]) / abs(truth[name])))
    return first, second, uncorrected


def summarise(label, params):
    for name, pairs in sorted(params.items()):
        n = len(pairs)
        zs = [p[0] for p in pairs]
        rs = [p[1] for p in pairs]
        mz, mr = sum(zs) / n, sum(rs) / n
        sz = math.sqrt(sum((z - mz) ** 2 for z in zs) / (n - 1)) if n > 1 else float("nan")
        sr = math.sqrt(sum((r - mr) ** 2 for r in rs) / (n - 1)) if n > 1 else float("nan")
        lo = sz * math.sqrt((n - 1) / chi2_quantile(n - 1, 0.975)) if n >= 6 else float("nan")
        hi = sz * math.sqrt((n - 1) / chi2_quantile(n - 1, 0.025)) if n >= 6 else float("nan")
        cover = sum(abs(z) <= 1.959964 for z in zs)
        print(f"  {label:28s} {name:26s} mean z {mz:+6.2f} (+-{1 / math.sqrt(n):.2f}) sd z {sz:5.2f} [{lo:4.2f}, {hi:4.2f}]  "
              f"mean rel.err {100 * mr:+7.2f} % +- {100 * sr / math.sqrt(n):5.2f} %  cover {cover}/{n}")


def main():
    if len(sys.argv) < 3 or sys.argv[1] not in TRUTH:
        sys.exit(__doc__)
    first, second, uncorrected = read(sys.argv[2:], TRUTH[sys.argv[1]])
    summarise(sys.argv[1], first)
    if second:
        print("the same estimates with the second covariance choice's standard errors:")
        summarise(sys.argv[1], second)
    if uncorrected:
        print("the maximum before the bias correction, with its own standard errors (\"zu\"):")
        summarise(sys.argv[1], uncorrected)


if __name__ == "__main__":
    main()
