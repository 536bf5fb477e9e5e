#!/usr/bin/env python3
r"""identify-vehs with its DEFAULT settings on the coarse-sampling bistable Duffing of the issue.

User-level evidence: the records are made by this script's own numpy integrator (an independent
route, not vehs's simulator), written as CSV (traj,t,x), and `identify-vehs` is run with a config
that names only the data file and the output model (estimator "auto", default libraries and
selection). The existing benches call the library and bypass identify-vehs's own term selection.

Truth (Ito):  dX = Y dt,  dY = (X - X^3 - 0.1 Y) dt + sqrt(0.04) dB
  model-file conventions: drift {"x": +1, "x^3": -1, "y": -0.1}, diffusion {"1": 0.04} (2D = a22)
Data: 40 records x 2000 time units per data set, sampled at dt = 0.35 and 0.7 (omega*dt ~ 0.5, 1.0),
      integrated by the stochastic Heun scheme (strong order 1 for additive noise) at h = 0.007
      (50 substeps of 0.35, 100 of 0.7) after a burn-in of 200 time units from x0 ~ U(-1.5, 1.5),
      y0 = 0; sensor-noise variant: + white N(0, (0.02 sd(x))^2) on the sampled x (sd(x) pooled
      over the data set; the same underlying path as the clean set of that seed and dt).
Seeds: independent numpy Generator streams per (dt, seed); noise stream separate.

Run (from the repository root; one process at a time, low priority):
    nice -n 19 env OMP_NUM_THREADS=1 build/python-venv/bin/python bench/identify_coarse_cli.py \
        [--seeds 0-9] [--work /tmp/coarse] [--out bench/results/identify_coarse_cli.txt]
Sub-steps: `gen` (records only), `check` (E[X^2] against the exact stationary density),
`run` (identify-vehs on every condition x seed, then the summary); default: all three.
`report` rebuilds the results file from <work>/runs.json and the model files without re-running.
--identify PATH runs a copy of the binary (build/ may be relinked by other sessions mid-run).
identify-vehs is called as
    nice -n 19 env OMP_NUM_THREADS=1 build/identify-vehs --threads 1 <config.json>
with config {"data": "<csv>", "output": "<model.json>"}.

Time (measured 2026-11-25, 2 cores, load ~2): generation 20 s for 10 seeds x 2 dt (numpy, 400 lanes,
280 MB of CSV in /tmp/coarse); identify-vehs 0.2-22 s per run on one core (median 9-18 s), the
40 runs ~9 min; the whole script ~10 min.
"""
import argparse
import datetime
import json
import math
import os
import platform
import re
import resource
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
IDENTIFY = os.path.join(ROOT, "build", "identify-vehs")
IDENTIFY_RUN = IDENTIFY  # --identify: a copy of the binary (build/ may be relinked by others during a run)

BETA, SIGMA2 = 0.1, 0.04
TRUTH_DRIFT = {"x": 1.0, "x^3": -1.0, "y": -BETA}
TRUTH_DIFF = {"1": SIGMA2}
NREC, TSPAN, BURN, H = 40, 2000.0, 200.0, 0.007
DTS = (0.35, 0.7)
NOISES = (0.0, 0.02)


def drift(x, y):
    return x - x * x * x - BETA * y


def generate(dt, seeds, work):
    """Stochastic Heun, vectorised over len(seeds) x NREC lanes. Returns {seed: (NREC, N) array}."""
    sub = int(round(dt / H))
    assert abs(sub * H - dt) < 1e-12
    nsamp = int(math.floor(TSPAN / dt + 1e-9)) + 1
    nburn = int(math.ceil(BURN / H))
    rngs = [np.random.default_rng([int(round(dt * 1000)), s, 1]) for s in seeds]
    lanes = NREC * len(seeds)
    x = np.concatenate([r.uniform(-1.5, 1.5, NREC) for r in rngs])
    y = np.zeros(lanes)
    sq = math.sqrt(SIGMA2 * H)
    out = np.empty((nsamp, lanes))
    total = nburn + (nsamp - 1) * sub
    chunk = 2000
    step = 0
    k = 0  # next sample index
    t0 = time.time()
    while step < total:
        m = min(chunk, total - step)
        dW = np.concatenate([r.standard_normal((m, NREC)) for r in rngs], axis=1) * sq
        for i in range(m):
            if step >= nburn and (step - nburn) % sub == 0:
                out[k] = x
                k += 1
            f = drift(x, y)
            w = dW[i]
            xp = x + y * H
            yp = y + f * H + w
            x = x + 0.5 * (y + yp) * H
            y = y + 0.5 * (f + drift(xp, yp)) * H + w
            step += 1
    out[k] = x
    k += 1
    assert k == nsamp, (k, nsamp)
    print(f"  generated dt={dt}: {len(seeds)} seeds x {NREC} records x {nsamp} samples "
          f"({total} Heun steps, {time.time() - t0:.0f} s)", file=sys.stderr)
    return {s: out[:, j * NREC:(j + 1) * NREC].T.copy() for j, s in enumerate(seeds)}


def write_csv(path, X, dt):
    n = X.shape[1]
    t = np.arange(n) * dt
    with open(path, "w") as f:
        f.write("traj,t,x\n")
        for r in range(X.shape[0]):
            block = np.column_stack([np.full(n, r), t, X[r]])
            np.savetxt(f, block, fmt=["%d", "%.17g", "%.17g"], delimiter=",")


def data_path(work, dt, noise, seed):
    return os.path.join(work, f"bistable_dt{dt:.2f}_noise{noise:.2f}_seed{seed}.csv")


def cmd_gen(seeds, work):
    os.makedirs(work, exist_ok=True)
    meta = {}
    for dt in DTS:
        todo = [s for s in seeds if not all(os.path.exists(data_path(work, dt, nz, s)) for nz in NOISES)]
        if not todo:
            continue
        sets = generate(dt, todo, work)
        for s, X in sets.items():
            np.save(os.path.join(work, f"clean_dt{dt:.2f}_seed{s}.npy"), X)
            sdx = float(X.std())
            for nz in NOISES:
                Xn = X
                if nz > 0:
                    rn = np.random.default_rng([int(round(dt * 1000)), s, 2])
                    Xn = X + nz * sdx * rn.standard_normal(X.shape)
                write_csv(data_path(work, dt, nz, s), Xn, dt)
                meta[f"{dt:.2f}_{nz:.2f}_{s}"] = {"sd_x": sdx, "noise_sd": nz * sdx}
    mp = os.path.join(work, "meta.json")
    old = json.load(open(mp)) if os.path.exists(mp) else {}
    old.update(meta)
    json.dump(old, open(mp, "w"), indent=1)


def exact_moments():
    """Stationary p(x, y) ∝ exp(-(2 beta / sigma^2)(y^2/2 + U(x))), U = -x^2/2 + x^4/4."""
    c = 2 * BETA / SIGMA2
    x = np.linspace(-5, 5, 400001)
    w = np.exp(-c * (-x * x / 2 + x ** 4 / 4))
    ex2 = np.trapezoid(x * x * w, x) / np.trapezoid(w, x)
    return ex2, 1.0 / c  # E[Y^2] = sigma^2 / (2 beta)


def cmd_check(seeds, work, lines):
    ex2, ey2 = exact_moments()
    lines.append(f"E[X^2] check: exact (quadrature of p(x) ∝ exp(-5 U(x))) = {ex2:.6f}")
    for dt in DTS:
        per_set = []
        allrec = []
        for s in seeds:
            X = np.load(os.path.join(work, f"clean_dt{dt:.2f}_seed{s}.npy"))
            rec = (X ** 2).mean(axis=1)  # per-record time average; records independent
            per_set.append((s, rec.mean(), rec.std(ddof=1) / math.sqrt(len(rec))))
            allrec.append(rec)
        s0, m0, e0 = per_set[0]
        lines.append(f"  dt {dt}: seed {s0} alone (40 records): E[X^2] = {m0:.5f} +- {e0:.5f}  "
                     f"(diff {(m0 - ex2) / e0:+.2f} SE)")
        a = np.concatenate(allrec)
        m, e = a.mean(), a.std(ddof=1) / math.sqrt(len(a))
        lines.append(f"  dt {dt}: all {len(seeds)} seeds ({len(a)} records): E[X^2] = {m:.5f} +- {e:.5f}  "
                     f"(diff {(m - ex2) / e:+.2f} SE)")
    lines.append(f"  (E[Y^2] exact = sigma^2/(2 beta) = {ey2:.4f}; not checked: velocity not recorded)")


def parse_term(name):
    """(px, py) of a monomial term name; None for others."""
    if name == "1":
        return (0, 0)
    px = py = 0
    for f in name.split("*"):
        m = re.fullmatch(r"([xy])(?:\^(\d+))?", f)
        if not m:
            return None
        p = int(m.group(2) or 1)
        if m.group(1) == "x":
            px += p
        else:
            py += p
    return (px, py)


def a22(diff, x):
    v = np.zeros_like(x)
    for name, c in diff.items():
        p = parse_term(name)
        if p is None or p[1] != 0:
            continue  # only x-monomials at y = 0 here
        v += c * x ** p[0]
    return v


def binary_info(path):
    import hashlib
    md5 = hashlib.md5(open(path, "rb").read()).hexdigest()
    st = os.stat(path)
    return f"{path} md5 {md5} mtime {datetime.datetime.fromtimestamp(st.st_mtime, datetime.timezone.utc):%Y-%m-%d %H:%M:%S UTC}"


def run_one(cfg_path, log_path):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    env = dict(os.environ, OMP_NUM_THREADS="1")
    p = subprocess.run(["nice", "-n", "19", IDENTIFY_RUN, "--threads", "1", cfg_path],
                       capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    with open(log_path, "w") as f:
        f.write(p.stdout)
        f.write("\n--- stderr ---\n")
        f.write(p.stderr)
    return p.returncode, wall, cpu, p.stdout, p.stderr


def analyse(model, X, meta):
    drift, diff = model.get("drift", {}), model.get("diffusion", {})
    se = model.get("stderr", {})
    sed, sef = se.get("drift", {}), se.get("diffusion", {})
    res = {"drift": drift, "diffusion": diff, "z_true": {}, "spurious": {}, "missing": []}
    for part, truth, est, ses in (("drift", TRUTH_DRIFT, drift, sed), ("diffusion", TRUTH_DIFF, diff, sef)):
        for t, v in truth.items():
            if t in est:
                res["z_true"][f"{part}[{t}]"] = ((est[t] - v) / ses[t] if ses.get(t) else float("nan"),
                                                 est[t], ses.get(t))
            else:
                res["missing"].append(f"{part}[{t}]")
        for t, v in est.items():
            if t not in truth:
                res["spurious"][f"{part}[{t}]"] = (v / ses[t] if ses.get(t) else float("nan"), v, ses.get(t))
    res["exact"] = (set(drift) == set(TRUTH_DRIFT) and set(diff) == set(TRUTH_DIFF))
    res["beta_rel"] = (-drift.get("y", 0.0) - BETA) / BETA
    xs = np.linspace(X.min(), X.max(), 2001)
    wide = np.linspace(-3, 3, 2001)
    res["a22_min_data"] = float(a22(diff, xs).min())
    res["a22_min_wide"] = float(a22(diff, wide).min())
    lead = max(diff, key=lambda n: (parse_term(n) or (0, 0))[0]) if diff else None
    res["a22_neg_large_x"] = bool(lead and diff[lead] < 0 and (parse_term(lead) or (0, 0))[0] > 0)
    est = model.get("estimator", {})
    samp = model.get("sampling", {})
    lik = model.get("likelihood", {})
    res["est_used"] = est.get("used")
    res["refined"] = est.get("refined")
    res["adequacy"] = est.get("sampling_adequacy")
    res["verdict"] = samp.get("verdict")
    res["noise_share"] = samp.get("noise_share")
    res["stride"] = est.get("stride")
    res["sensor_noise_sd"] = samp.get("sensor_noise_sd")
    res["lik_measurement_sd"] = lik.get("measurement_sd") if lik else None
    res["lik_bias_corr"] = lik.get("bias_correction") if lik else None
    res["lik_selection"] = lik.get("selection") if lik else None
    res["true_noise_sd"] = meta["noise_sd"]
    # the moment fit (before the likelihood refinement): the SSR path's chosen step
    sel = model.get("selection", {})
    try:
        md = sel["drift"]["path"][sel["drift"]["chosen_step"]]["terms"]
        mf = sel["diffusion"]["path"][sel["diffusion"]["chosen_step"]]["terms"]
        res["moment"] = {"drift": md, "diffusion": mf,
                         "beta_rel": (-md.get("y", 0.0) - BETA) / BETA,
                         "a22_min_data": float(a22(mf, xs).min()),
                         "exact": set(md) == set(TRUTH_DRIFT) and set(mf) == set(TRUTH_DIFF)}
    except (KeyError, IndexError, TypeError):
        res["moment"] = None
    return res


def fmt_terms(d):
    return ",".join(d.keys())


def cmd_run(seeds, work, lines, conds):
    meta = json.load(open(os.path.join(work, "meta.json")))
    per = {}
    for dt, nz in conds:
        for s in seeds:
            tag = f"dt{dt:.2f}_noise{nz:.2f}_seed{s}"
            cfg = os.path.join(work, f"cfg_{tag}.json")
            out = os.path.join(work, f"model_{tag}.json")
            if os.path.exists(out):
                os.remove(out)
            json.dump({"data": data_path(work, dt, nz, s), "output": out}, open(cfg, "w"))
            rc, wall, cpu, so, se = run_one(cfg, os.path.join(work, f"log_{tag}.txt"))
            X = np.load(os.path.join(work, f"clean_dt{dt:.2f}_seed{s}.npy"))
            rec = {"dt": dt, "noise": nz, "seed": s, "rc": rc, "wall": wall, "cpu": cpu,
                   "stderr_tail": se.strip().splitlines()[-3:] if se.strip() else [],
                   "warnings": [l for l in se.splitlines() if "warn" in l.lower()]}
            if rc == 0 and os.path.exists(out):
                rec.update(analyse(json.load(open(out)), X, meta[f"{dt:.2f}_{nz:.2f}_{s}"]))
            per.setdefault((dt, nz), []).append(rec)
            print(f"  {tag}: rc {rc}, {wall:.1f} s wall, {cpu:.1f} s cpu", file=sys.stderr)
            json.dump({f"{k[0]}_{k[1]}": v for k, v in per.items()},
                      open(os.path.join(work, "runs.json"), "w"), indent=1, default=str)
    summarise(per, lines)


def cmd_report(work, lines):
    """Rebuild the summary from runs.json (rc, wall, cpu, stderr) and the model files."""
    meta = json.load(open(os.path.join(work, "meta.json")))
    raw = json.load(open(os.path.join(work, "runs.json")))
    per = {}
    for key, recs in raw.items():
        for r in recs:
            dt, nz, s = r["dt"], r["noise"], r["seed"]
            tag = f"dt{dt:.2f}_noise{nz:.2f}_seed{s}"
            base = {k: r[k] for k in ("dt", "noise", "seed", "rc", "wall", "cpu", "stderr_tail", "warnings")}
            out = os.path.join(work, f"model_{tag}.json")
            if base["rc"] == 0 and os.path.exists(out):
                X = np.load(os.path.join(work, f"clean_dt{dt:.2f}_seed{s}.npy"))
                base.update(analyse(json.load(open(out)), X, meta[f"{dt:.2f}_{nz:.2f}_{s}"]))
            per.setdefault((dt, nz), []).append(base)
    summarise(per, lines)


def summarise(per, lines):
    head = ("condition            runs exit0 exact  spurious terms seen (count; z)                      "
            "max|z|true  cover95  beta rel.err mean (sd)  neg a22 (data/|x|<=3/lead<0)  lik used  median wall")
    summary = [head]
    msum = ["", "MOMENT FIT BEFORE THE LIKELIHOOD (the SSR path's chosen step, kept in the model file's `selection`;"
            " not the model written)",
            "condition            exact  drift supports (count)                         diffusion supports (count)"
            "             beta rel.err mean  a22<0 over data"]
    detail = []
    for (dt, nz), recs in per.items():
        ok = [r for r in recs if r["rc"] == 0 and "drift" in r]
        exact = sum(r["exact"] for r in ok)
        spur = {}
        for r in ok:
            for k, (z, v, e) in r["spurious"].items():
                spur.setdefault(k, []).append(z)
        sp = "; ".join(f"{k} x{len(v)} z[{','.join(f'{z:+.1f}' for z in v)}]" for k, v in sorted(spur.items())) or "-"
        zt = [abs(z) for r in ok for (z, v, e) in r["z_true"].values() if z == z]
        cover = sum(a <= 1.959964 for a in zt)
        ntrue = sum(len(TRUTH_DRIFT) + len(TRUTH_DIFF) for r in ok)
        br = np.array([r["beta_rel"] for r in ok]) if ok else np.array([np.nan])
        negd = sum(r["a22_min_data"] < 0 for r in ok)
        negw = sum(r["a22_min_wide"] < 0 for r in ok)
        negl = sum(r["a22_neg_large_x"] for r in ok)
        lik = sum(1 for r in ok if r.get("refined") == "likelihood")
        walls = sorted(r["wall"] for r in recs)
        med = walls[len(walls) // 2] if len(walls) % 2 else 0.5 * (walls[len(walls) // 2 - 1] + walls[len(walls) // 2])
        summary.append(
            f"dt {dt:.2f} noise {nz*100:.0f}%   {len(recs):4d} {sum(r['rc']==0 for r in recs):5d} {exact:5d}  {sp:50s}  "
            f"{max(zt) if zt else float('nan'):9.2f}  {cover}/{ntrue}  {100*br.mean():+7.2f}% ({100*br.std(ddof=1) if len(br)>1 else 0:.2f}%)"
            f"      {negd}/{negw}/{negl}                    {lik}/{len(ok)}   {med:7.1f} s")
        mo = [r["moment"] for r in ok if r.get("moment")]
        if mo:
            cnt = lambda key: "; ".join(f"{k} x{v}" for k, v in sorted(
                {t: sum(1 for m in mo if ",".join(m[key]) == t) for t in {",".join(m[key]) for m in mo}}.items()))
            msum.append(f"dt {dt:.2f} noise {nz*100:.0f}%   {sum(m['exact'] for m in mo):3d}/{len(mo)}  {cnt('drift'):45s}  "
                        f"{cnt('diffusion'):35s}  {100*np.mean([m['beta_rel'] for m in mo]):+7.2f}%        "
                        f"{sum(m['a22_min_data'] < 0 for m in mo)}/{len(mo)}")
        for r in recs:
            if r["rc"] != 0 or "drift" not in r:
                detail.append(f"dt {dt:.2f} noise {nz*100:.0f}% seed {r['seed']}: EXIT {r['rc']} wall {r['wall']:.1f}s  stderr: {' | '.join(r['stderr_tail'])}")
                continue
            zs = " ".join(f"{k}={v:+.5g}±{e:.2g}(z{z:+.2f})" for k, (z, v, e) in r["z_true"].items())
            ss = " ".join(f"{k}={v:+.4g}±{e:.2g}(z{z:+.1f})" for k, (z, v, e) in r["spurious"].items()) or "none"
            ad = r.get("adequacy") or {}
            detail.append(
                f"dt {dt:.2f} noise {nz*100:.0f}% seed {r['seed']}: rc 0 wall {r['wall']:.1f}s cpu {r['cpu']:.1f}s | "
                f"drift {fmt_terms(r['drift'])} | diffusion {fmt_terms(r['diffusion'])} | exact {'yes' if r['exact'] else 'NO'}"
                f"\n    true: {zs}\n    spurious: {ss}   missing: {','.join(r['missing']) or 'none'}"
                f"\n    beta rel.err {100*r['beta_rel']:+.2f}%  min a22 over data x {r['a22_min_data']:.4g}, over |x|<=3 {r['a22_min_wide']:.4g}"
                f"\n    estimator used {r['est_used']} stride {r['stride']} refined {r['refined']}; sampling verdict {r['verdict']} "
                f"noise_share {r['noise_share']}; adequacy omega_dt {ad.get('omega_dt')} vouched {ad.get('vouched')} "
                f"likelihood {ad.get('likelihood')}"
                f"\n    sensor noise sd: true {r['true_noise_sd']:.4g}, sampling.sensor_noise_sd {r['sensor_noise_sd']}, "
                f"likelihood.measurement_sd {r['lik_measurement_sd']}; likelihood selection {r['lik_selection']}; "
                f"bias_correction {json.dumps(r['lik_bias_corr']) if r['lik_bias_corr'] else None}"
                + (f"\n    moment fit (before the likelihood): drift "
                   + " ".join(f"{k}={v:+.4g}" for k, v in r["moment"]["drift"].items()) + " | diffusion "
                   + " ".join(f"{k}={v:+.4g}" for k, v in r["moment"]["diffusion"].items())
                   + f" | beta rel.err {100*r['moment']['beta_rel']:+.2f}%" if r.get("moment") else "")
                + (f"\n    stderr warnings: {' | '.join(r['warnings'])}" if r["warnings"] else ""))
    pt = ["", "PER TRUE TERM (over the runs that kept it): mean z (+- its SE), sd z, 95 % coverage, mean relative error"]
    for (dt, nz), recs in per.items():
        ok = [r for r in recs if r["rc"] == 0 and "drift" in r]
        for name in [f"drift[{t}]" for t in TRUTH_DRIFT] + [f"diffusion[{t}]" for t in TRUTH_DIFF]:
            zs = np.array([r["z_true"][name][0] for r in ok if name in r["z_true"]])
            tv = TRUTH_DRIFT.get(name[6:-1]) if name.startswith("drift") else TRUTH_DIFF.get(name[10:-1])
            rel = np.array([(r["z_true"][name][1] - tv) / abs(tv) for r in ok if name in r["z_true"]])
            if len(zs) > 1:
                pt.append(f"dt {dt:.2f} noise {nz*100:.0f}%  {name:15s} mean z {zs.mean():+.2f} (+-{zs.std(ddof=1)/math.sqrt(len(zs)):.2f})"
                          f"  sd z {zs.std(ddof=1):.2f}  cover {int((abs(zs) <= 1.959964).sum())}/{len(zs)}"
                          f"  mean rel.err {100*rel.mean():+.2f}% (+-{100*rel.std(ddof=1)/math.sqrt(len(rel)):.2f}%)")
    lines.extend(["", "SUMMARY (z = (estimate - truth)/SE for true terms, estimate/SE for spurious;"
                  " cover95 = true-term intervals covering the truth; neg a22 = fits whose a22(x) < 0 somewhere"
                  " over the data's x range / over |x|<=3 / whose highest-power diffusion coefficient is negative;"
                  " lik used = estimator.refined == likelihood)"] + summary + msum + pt + ["", "PER SEED"] + detail)


def parse_seeds(s):
    if "-" in s:
        a, b = s.split("-")
        return list(range(int(a), int(b) + 1))
    return [int(v) for v in s.split(",")]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", nargs="?", default="all", choices=["all", "gen", "check", "run", "report"])
    ap.add_argument("--seeds", default="0-9")
    ap.add_argument("--gen-seeds", default=None, help="seeds to generate (default: --seeds)")
    ap.add_argument("--work", default="/tmp/coarse")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "identify_coarse_cli.txt"))
    ap.add_argument("--identify", default=IDENTIFY, help="identify-vehs binary (default build/identify-vehs)")
    ap.add_argument("--note", default="", help="a line added to the results header")
    ap.add_argument("--conditions", default="all", help="e.g. 0.35:0,0.7:0.02")
    a = ap.parse_args()
    seeds = parse_seeds(a.seeds)
    global IDENTIFY_RUN
    IDENTIFY_RUN = os.path.abspath(a.identify)
    conds = [(dt, nz) for dt in DTS for nz in NOISES]
    if a.conditions != "all":
        conds = [tuple(float(v) for v in c.split(":")) for c in a.conditions.split(",")]
    if a.what in ("all", "gen"):
        cmd_gen(parse_seeds(a.gen_seeds) if a.gen_seeds else seeds, a.work)
    lines = [f"# {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M UTC}  {platform.machine()}, "
             f"{os.cpu_count()} cores, load average at start {' '.join(f'{v:.2f}' for v in os.getloadavg())}",
             f"# command: nice -n 19 env OMP_NUM_THREADS=1 {sys.executable} bench/identify_coarse_cli.py "
             + " ".join(sys.argv[1:]),
             f"# binary: {binary_info(IDENTIFY_RUN)}",
             f"# identify-vehs: {IDENTIFY_RUN} --threads 1 <config>; config = {{\"data\": <csv>, \"output\": <model>}} (all defaults)",
             *([f"# note: {a.note}"] if a.note else []),
             f"# truth: drift x +1, x^3 -1, y -0.1; diffusion 1: 0.04. {NREC} records x {TSPAN:g} time units, Heun h = {H}, "
             f"burn-in {BURN:g}; seeds {a.seeds}", ""]
    if a.what in ("all", "check"):
        cmd_check(seeds, a.work, lines)
    if a.what == "report":
        if os.path.exists(a.out):
            old = open(a.out).read().splitlines()
            hdr = [l for l in old[:8] if l.startswith("#")]
            fin = [l for l in old if l.startswith("# finished")]
            lines = ["# (report rebuilt " + f"{datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M UTC}"
                     + " from the run's runs.json and model files; the run's header follows)"] + hdr + fin + [""]
        cmd_check(seeds, a.work, lines)
        cmd_report(a.work, lines)
    if a.what in ("all", "run"):
        cmd_run(seeds, a.work, lines, conds)
        lines.append("")
        lines.append(f"# finished {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M UTC}, load average "
                     f"{' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    text = "\n".join(lines) + "\n"
    print(text)
    if a.what in ("all", "run", "report"):
        os.makedirs(os.path.dirname(a.out), exist_ok=True)
        with open(a.out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
