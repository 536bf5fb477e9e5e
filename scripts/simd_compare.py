#!/usr/bin/env python3
"""Compares the outputs of two builds of vehs that differ only in their SIMD width (used by
scripts/simd-paths.sh; standard library only).

  simd_compare.py records A.npy B.npy        measurement files: bitwise, else how far they drift
  simd_compare.py statistics A.json B.json   Monte Carlo statistics: difference in standard errors
  simd_compare.py model A.json B.json        identify-vehs models: difference in standard errors
                                             (--bitwise: identical coefficients and SEs)

Prints one line per comparison and exits 1 when a bound below is broken:
  records     --bitwise: identical bytes; otherwise the same records and lengths, and the
              report says when the records separate by 1e-12, 1e-6, 1e-2 and 0.1.
  statistics  |ΔE| ≤ 1e-9·|E| when the records are bitwise equal (--bitwise), else
              |ΔE| ≤ z·√2·SE with z = 4.9 (the same seeds: the two estimates share their
              randomness until the trajectories separate, so √2·SE bounds the spread of the
              difference; 4.9 = z_bound(k ≤ 30) of tests/stat_bounds.hpp).
  model       same support; |Δc| ≤ 1e-6·SE(c) for every coefficient (rounding differences of the
              sums, amplified by the condition number of the Gram matrix ≤ 1e8: 1e8·1e-16·√n ≪ 1e-6
              of an SE that is itself ≥ 1e-3 of |c|); --bitwise: every coefficient and standard
              error equal (the Gram kernel's SIMD levels in one build: the same sums in the same
              order).
"""
import json
import math
import struct
import sys


def read_npy(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:6] != b"\x93NUMPY":
        raise SystemExit(f"{path}: not a .npy file")
    major = data[6]
    hlen = struct.unpack("<H", data[8:10])[0] if major == 1 else struct.unpack("<I", data[8:12])[0]
    start = (10 if major == 1 else 12) + hlen
    header = data[(10 if major == 1 else 12):start].decode("latin1")
    return header, data[start:]


def fields(header):
    # structured dtype: [('traj', '<i8'), ('t', '<f8'), ('x', '<f8'), ...]
    descr = header[header.index("[") : header.index("]") + 1]
    names = [p.split("'")[1] for p in descr.split("(")[1:]]
    types = [p.split("'")[3] for p in descr.split("(")[1:]]
    return names, types


def records(path):
    header, body = read_npy(path)
    names, types = fields(header)
    fmt = "<" + "".join({"<i8": "q", "<f8": "d", "<i4": "i", "<f4": "f"}[t] for t in types)
    size = struct.calcsize(fmt)
    ix, it, itraj = names.index("x"), names.index("t"), names.index("traj")
    out = {}
    for row in struct.iter_unpack(fmt, body[: len(body) // size * size]):
        out.setdefault(row[itraj], []).append((row[it], row[ix]))
    return out


def compare_records(a, b, bitwise):
    if bitwise:
        ok = open(a, "rb").read() == open(b, "rb").read()
        print(f"records    {'bitwise identical' if ok else 'DIFFER'}: {a} vs {b}")
        return ok
    ra, rb = records(a), records(b)
    ok = ra.keys() == rb.keys() and all(len(ra[k]) == len(rb.get(k, [])) for k in ra)
    levels = (1e-12, 1e-6, 1e-2, 0.1)
    reached = {lv: [] for lv in levels}
    identical, start = 0, 0.0
    for k in ra:
        xa, xb = ra[k], rb[k]
        start = max(start, abs(xa[0][1] - xb[0][1]))
        d = [abs(p[1] - q[1]) for p, q in zip(xa, xb)]
        identical += max(d) == 0.0
        for lv in levels:
            i = next((i for i, v in enumerate(d) if v > lv), None)
            if i is not None:
                reached[lv].append(xa[i][0])
    n, span = len(ra), (ra[next(iter(ra))][-1][0] if ra else 0.0)
    parts = []
    for lv in levels:
        t = sorted(reached[lv])
        med = f", median t = {t[len(t) // 2]:.3g}" if t else ""
        parts.append(f"|Δx| > {lv:g} in {len(t)}/{n}{med}")
    print(f"records    {identical}/{n} bitwise identical, first samples differ by ≤ {start:.1e}; over "
          f"t ∈ [0, {span:.3g}]: " + "; ".join(parts))
    return ok


def compare_statistics(a, b, bitwise):
    ja, jb = json.load(open(a)), json.load(open(b))
    se = ja.get("stderr", {})
    ok, worst = True, 0.0
    for k, va in ja.items():
        if not k.startswith("E[") or not isinstance(va, (int, float)):
            continue
        vb, s = jb[k], se.get(k, float("nan"))
        if bitwise:
            good = abs(va - vb) <= 1e-9 * abs(va) + 1e-300
            z = abs(va - vb) / max(abs(va), 1e-300)
        else:
            z = abs(va - vb) / (math.sqrt(2.0) * s)
            good = z <= 4.9
        worst = max(worst, z)
        ok = ok and good
    what = "relative difference" if bitwise else "difference / (√2·SE)"
    print(f"statistics largest {what}: {worst:.3g} ({'ok' if ok else 'TOO LARGE'})")
    return ok


def compare_model(a, b, bitwise=False):
    ja, jb = json.load(open(a)), json.load(open(b))
    ok, worst = True, 0.0
    if bitwise:
        same = all(ja[part] == jb[part] and ja["stderr"][part] == jb["stderr"][part]
                   for part in ("drift", "diffusion"))
        print(f"model      {'bitwise identical' if same else 'DIFFER'}: {a} vs {b}")
        return same
    for part in ("drift", "diffusion"):
        if set(ja[part]) != set(jb[part]):
            print(f"model      {part} supports differ: {sorted(ja[part])} vs {sorted(jb[part])}")
            ok = False
            continue
        for term, ca in ja[part].items():
            s = ja["stderr"][part][term]
            r = abs(ca - jb[part][term]) / s
            worst = max(worst, r)
            ok = ok and r <= 1e-6
    print(f"model      largest |Δc|/SE: {worst:.3g} ({'ok' if ok else 'TOO LARGE'})")
    return ok


def main():
    if len(sys.argv) < 4:
        raise SystemExit(__doc__)
    kind, a, b = sys.argv[1:4]
    bitwise = "--bitwise" in sys.argv[4:]
    ok = {"records": lambda: compare_records(a, b, bitwise),
          "statistics": lambda: compare_statistics(a, b, bitwise),
          "model": lambda: compare_model(a, b, bitwise)}[kind]()
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
