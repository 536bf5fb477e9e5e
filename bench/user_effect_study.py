#!/usr/bin/env python3
"""Seed study of a user-defined effect, "directional_friction" (Coulomb and viscous friction
per direction of motion, written as four drift expressions), through the executables.

The rig (this file's own generator, not vehs's simulator; stochastic Heun at 50 substeps per
sample, numpy only), in metres and seconds:
    x'' = -k x - f(x') + sqrt(2D) xi(t),
    f(y) = Fp 1(y>0) - Fm 1(y<0) + cp y 1(y>0) + cm y 1(y<0),
k 987 1/s^2 (5 Hz), Fp 0.30, Fm 0.15 m/s^2, cp 2, cm 6 1/s, 2D 5e-2 m^2/s^3 (rms x about 2 mm,
rms y 60 mm/s: Coulomb and viscous friction dissipate about 42 % and 58 % of the noise's power; at
2D 6e-3 rms x would be 0.44 mm and cp rms(y) 0.03 m/s^2, a tenth of Fp); sampled at
dt = 5e-3 s (40 samples per period) after a burn-in of 2000 samples, 1 % white sensor noise
(sd 0.01 rms(x)); written as a data logger's CSV ("time_s,position_m", %.9g).

The user effect, as identify-vehs's "effects" entry and diagnose-vehs's "user_effects" entry:
    {"name": "directional_friction",
     "drift": {"Fp": "-(y>0)", "Fm": "(y<0)", "cp": "-y*(y>0)", "cm": "-y*(y<0)"}}
(each parameter is the coefficient of its drift expression: all four are positive here).

Per seed:
  1. identify-vehs, drift_library ["x"] with the user effect (defaults otherwise): Fp, Fm,
     cp, cm and k (= -coef of x) with SE and z = (estimate - truth)/SE; "within" when all |z| <= 3.
  2. the baseline: identify-vehs, drift_library ["x", "y"], no effect; then diagnose-vehs on it
     with "user_effects" [SUSPECT], the same friction written on top of the baseline's damping y
     (Fp, Fm and dc = cm - cp: with y in the model, viscous damping per direction is one extra
     term, not two): is it recommended first, is it confirmed, the first-ranked score suspect and
     its z, the verdict, the seconds of each tool; then identify-vehs on diagnose's refit.json
     (the baseline's terms and the named effect): Fp, Fm, dc, c = cp and k within 3 SE.
Prints a block per seed, tables and the line
    "within 3 SE: a/N seeds; named first: b/N; confirmed: c/N".

Usage (from the repository root):
    python bench/user_effect_study.py --build build --seeds 10 [--seed0 1] [--samples 20000]
        [--records 1] [--jobs 1] [--json results.json]
    python bench/user_effect_study.py --check          (the generator alone: rms, friction share)
    python bench/user_effect_study.py --diagnose-only --samples 40000   (step 2 without its refit)
At most --jobs (1 or 2) tool processes run at a time; with 2 each tool gets --threads 1."""
import argparse
import concurrent.futures
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

# ----------------------------------------------------------------------------- the rig
K = 987.0            # 1/s^2  (omega = 31.4 rad/s, 5 Hz)
FP, FM = 0.30, 0.15  # m/s^2  Coulomb friction for y > 0 / y < 0
CP, CM = 2.0, 6.0    # 1/s    viscous friction for y > 0 / y < 0
TWO_D = 5e-2         # m^2/s^3 (diffusion a22 = 2D): rms x about 2 mm; Coulomb and viscous friction
                     # each dissipate about half of the noise's power (--check)
DT, SUB, BURN = 5e-3, 50, 2000
NOISE_SHARE = 0.01   # sensor noise sd / rms(x)

TRUTH = {"Fp": FP, "Fm": FM, "cp": CP, "cm": CM, "k": K}
EFFECT = {"name": "directional_friction",
          "drift": {"Fp": "-(y>0)", "Fm": "(y<0)", "cp": "-y*(y>0)", "cm": "-y*(y<0)"}}
SUSPECT = {"name": "directional_friction", "drift": {"Fp": "-(y>0)", "Fm": "(y<0)", "dc": "-y*(y<0)"}}
SUSPECT_TRUTH = {"Fp": FP, "Fm": FM, "dc": CM - CP, "c": CP, "k": K}
UNITS = {"length": "m", "time": "s"}
COLUMNS = {"t": "time_s", "x": "position_m"}


def friction(y, fp=FP, fm=FM, cp=CP, cm=CM):
    """f(y) of x'' = -k x - f(y) + noise."""
    pos, neg = y > 0, y < 0
    return fp * pos - fm * neg + cp * y * pos + cm * y * neg


def simulate(seeds, samples, dt=DT, sub=SUB, burn=BURN, k=K, two_d=TWO_D, noise_share=NOISE_SHARE,
             fric=friction, chunk=500):
    """One record of `samples` samples per seed, all seeds integrated together (vectorised over
    seeds; every seed has its own generator, so a record does not depend on the other seeds).
    Stochastic Heun (predictor-corrector on the drift, the same Wiener increment in both stages)
    at h = dt/sub from x = y = 0, sampled every dt after `burn` samples. Returns (x_measured,
    x_true, y_true), each of shape (samples, len(seeds)); the sensor noise has sd
    noise_share * rms(x_true) per record."""
    rngs = [np.random.default_rng([int(s), 20251129]) for s in seeds]
    m = len(rngs)
    h = dt / sub
    sq = math.sqrt(two_d * h)
    x, y = np.zeros(m), np.zeros(m)
    xs, ys = np.empty((samples, m)), np.empty((samples, m))

    def acc(x, y):
        return -k * x - fric(y)

    i = -burn
    while i < samples:
        n = min(chunk, samples - i)
        dw = sq * np.stack([r.standard_normal((n, sub)) for r in rngs], axis=-1)  # (n, sub, m)
        for a in range(n):
            if i + a >= 0:
                xs[i + a], ys[i + a] = x, y
            for b in range(sub):
                w = dw[a, b]
                a0 = acc(x, y)
                xp, yp = x + h * y, y + h * a0 + w
                x, y = x + 0.5 * h * (y + yp), y + 0.5 * h * (a0 + acc(xp, yp)) + w
        i += n
    rms = np.sqrt(np.mean(xs ** 2, axis=0))
    noise = np.stack([r.standard_normal(samples) for r in rngs], axis=-1)
    return xs + noise_share * rms * noise, xs, ys


def write_csv(path, x, dt=DT):
    """A data logger's CSV: header "time_s,position_m", rows t [s], x [m] as %.9g."""
    t = dt * np.arange(len(x))
    np.savetxt(path, np.column_stack([t, x]), delimiter=",", header="time_s,position_m",
               comments="", fmt="%.9g")


def rig_check(x, y, two_d=TWO_D, dt=DT):
    """The numbers that say whether the friction matters on these records (x, y: true states,
    columns = records)."""
    pos, neg = y > 0, y < 0
    # stationary energy balance: E[y f(y)] = D = two_d / 2 (power injected by the noise)
    coulomb_power = np.mean(FP * y * pos - FM * y * neg)
    viscous_power = np.mean(CP * y * y * pos + CM * y * y * neg)
    rms_y = float(np.sqrt(np.mean(y ** 2)))
    return {
        "rms_x_m": float(np.sqrt(np.mean(x ** 2))),
        "mean_x_m": float(np.mean(x)),
        "rms_y_m_s": rms_y,
        "share_y_positive": float(np.mean(pos)),
        "power_coulomb_share": float(coulomb_power / (two_d / 2)),
        "power_viscous_share": float(viscous_power / (two_d / 2)),
        "power_balance": float((coulomb_power + viscous_power) / (two_d / 2)),
        "rms_restoring_kx_m_s2": float(K * np.sqrt(np.mean(x ** 2))),
        "rms_friction_m_s2": float(np.sqrt(np.mean(friction(y) ** 2))),
        "cp_rms_y_m_s2": CP * rms_y, "cm_rms_y_m_s2": CM * rms_y,
        # the noise's acceleration averaged over one sample and over one period
        "noise_acc_per_sample_m_s2": math.sqrt(two_d / dt),
        "noise_acc_per_period_m_s2": math.sqrt(two_d / (2 * math.pi / math.sqrt(K))),
    }


def self_test():
    """Unit checks of the generator: the linear case against its exact variances, the Heun step
    against the energy balance, and the CSV format."""
    ok = True
    # linear oscillator, damping c: var(y) = 2D / (2c), var(x) = var(y) / k (exact, stationary)
    c = 4.0
    _, xs, ys = simulate(range(1, 9), 20000, fric=lambda y: c * y)
    vy, vx = np.mean(ys ** 2), np.mean(xs ** 2)
    vy0, vx0 = TWO_D / (2 * c), TWO_D / (2 * c) / K
    # 8 records of 100 s, correlation time 1/(c/2) = 0.5 s: ~1600 independent blocks -> ~5 % sd
    good = abs(vy / vy0 - 1) < 0.08 and abs(vx / vx0 - 1) < 0.08
    ok &= good
    print(f"linear check (c {c}): var(y) {vy:.4g} vs {vy0:.4g} ({vy / vy0 - 1:+.1%}), var(x) {vx:.4g} "
          f"vs {vx0:.4g} ({vx / vx0 - 1:+.1%}): {'ok' if good else 'FAIL'}")
    # the same seed gives the same record whatever the other seeds (the states bitwise; the
    # sensor noise's scale, a mean over a strided column, to the last bit)
    a, xa, _ = simulate([3, 4], 300)
    b, xb, _ = simulate([4], 300)
    good = np.array_equal(xa[:, 1], xb[:, 0]) and np.allclose(a[:, 1], b[:, 0], rtol=1e-12, atol=0)
    ok &= good
    print(f"record independent of the other seeds: {'ok' if good else 'FAIL'}")
    # the rig: energy balance and sensor noise
    xm, xs, ys = simulate(range(1, 5), 20000)
    chk = rig_check(xs, ys)
    good = abs(chk["power_balance"] - 1) < 0.05
    ok &= good
    print(f"rig energy balance E[y f(y)] / D = {chk['power_balance']:.3f}: {'ok' if good else 'FAIL'}")
    share = np.std(xm - xs, axis=0) / np.sqrt(np.mean(xs ** 2, axis=0))
    good = bool(np.all(np.abs(share - NOISE_SHARE) < 0.1 * NOISE_SHARE))
    ok &= good
    print(f"sensor noise sd / rms(x) per record {np.round(share, 4).tolist()}: {'ok' if good else 'FAIL'}")
    with tempfile.TemporaryDirectory() as work:
        p = os.path.join(work, "r.csv")
        write_csv(p, xm[:5, 0])
        lines = open(p).read().splitlines()
        good = lines[0] == "time_s,position_m" and lines[2].split(",")[0] == "0.005" and len(lines) == 6
        ok &= good
        print(f"CSV {lines[:3]}: {'ok' if good else 'FAIL'}")
    print_check(chk)
    return ok


def print_check(chk):
    print(f"rig: rms x {chk['rms_x_m'] * 1e3:.3f} mm (mean {chk['mean_x_m'] * 1e6:+.1f} um), rms y "
          f"{chk['rms_y_m_s'] * 1e3:.2f} mm/s, y > 0 {chk['share_y_positive']:.1%} of the time")
    print(f"     power dissipated: Coulomb {chk['power_coulomb_share']:.1%}, viscous "
          f"{chk['power_viscous_share']:.1%} of D (balance {chk['power_balance']:.3f})")
    print(f"     accelerations [m/s^2]: rms k x {chk['rms_restoring_kx_m_s2']:.3f}, rms friction "
          f"{chk['rms_friction_m_s2']:.3f}; Fp {FP}, Fm {FM}, cp rms(y) {chk['cp_rms_y_m_s2']:.3f}, "
          f"cm rms(y) {chk['cm_rms_y_m_s2']:.3f}; noise sqrt(2D/dt) {chk['noise_acc_per_sample_m_s2']:.3f}, "
          f"sqrt(2D/T) {chk['noise_acc_per_period_m_s2']:.3f}")


# ----------------------------------------------------------------------------- the tools
def run_tool(exe, cfg_path, cfg, threads):
    with open(cfg_path, "w") as f:
        json.dump(cfg, f, indent=1)
    cmd = [exe, cfg_path, "-q"] + (["--threads", str(threads)] if threads else [])
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    return p.returncode, p.stderr.strip(), time.perf_counter() - t0


def tail(text, n=6):
    return "\n".join(text.splitlines()[-n:])


def effect_estimates(model, name=EFFECT["name"]):
    """(params, stderr) of the user effect in an identify-vehs model file: its effect_params entry,
    else its effects entry, else the coefficients of its drift expressions."""
    for key in ("effect_params", "effects"):
        for e in model.get(key) or []:
            if isinstance(e, dict) and e.get("name") == name and e.get("params"):
                return dict(e["params"]), dict(e.get("stderr") or {}), key
    drift = model.get("drift") or {}
    sed = (model.get("stderr") or {}).get("drift") or {}
    params, se = {}, {}
    for p, expr in EFFECT["drift"].items():
        if expr in drift:
            params[p], se[p] = drift[expr], sed.get(expr)
    return params, se, "drift terms"


def fit_effect(build, work, csv, tag, threads, library):
    out = os.path.join(work, f"{tag}_effect_model.json")
    cfg = {"data": csv, "columns": COLUMNS, "units": UNITS, "drift_library": library,
           "diffusion_library": ["1"], "effects": [EFFECT], "output": out}
    rc, err, sec = run_tool(os.path.join(build, "identify-vehs"), out + ".cfg.json", cfg, threads)
    row = {"seconds": sec, "rc": rc, "library": library}
    if rc != 0 or not os.path.exists(out):
        row["error"] = tail(err) or f"exit {rc}, no model written"
        return row
    m = json.load(open(out))
    params, se, source = effect_estimates(m)
    drift, sed = m.get("drift") or {}, (m.get("stderr") or {}).get("drift") or {}
    if "x" in drift:
        params["k"], se["k"] = -drift["x"], sed.get("x")
    diff, sedf = m.get("diffusion") or {}, (m.get("stderr") or {}).get("diffusion") or {}
    row_a22 = {"estimate": diff.get("1"), "stderr": sedf.get("1")}
    row.update(source=source, drift=drift, drift_stderr=sed, estimate={}, stderr={}, z={},
               a22=row_a22, refined=(m.get("estimator") or {}).get("refined"),
               estimator=(m.get("estimator") or {}).get("used"))
    if err:
        row["stderr_text"] = tail(err)
    for p, t in TRUTH.items():
        v, s = params.get(p), se.get(p)
        row["estimate"][p], row["stderr"][p] = v, s
        row["z"][p] = (v - t) / s if v is not None and s else None
    row["within_3se"] = all(z is not None and abs(z) <= 3 for z in row["z"].values())
    return row


def baseline_and_diagnose(build, work, csv, tag, threads, refit=True):
    name = EFFECT["name"]
    base = os.path.join(work, f"{tag}_baseline_model.json")
    cfg = {"data": csv, "columns": COLUMNS, "units": UNITS, "drift_library": ["x", "y"],
           "diffusion_library": ["1"], "output": base}
    rc, err, sec = run_tool(os.path.join(build, "identify-vehs"), base + ".cfg.json", cfg, threads)
    row = {"identify_seconds": sec, "identify_rc": rc}
    if rc != 0 or not os.path.exists(base):
        row["error"] = "baseline identify-vehs: " + (tail(err) or f"exit {rc}")
        return row
    row["baseline_drift"] = json.load(open(base)).get("drift")
    out = os.path.join(work, f"{tag}_diagnosis.json")
    cfg = {"model": base, "data": csv, "columns": COLUMNS, "units": UNITS, "output": out,
           "user_effects": [SUSPECT]}
    rc, err, sec = run_tool(os.path.join(build, "diagnose-vehs"), out + ".cfg.json", cfg, threads)
    row.update(diagnose_seconds=sec, diagnose_rc=rc)
    if rc != 0 or not os.path.exists(out):
        row["error"] = "diagnose-vehs: " + (tail(err) or f"exit {rc}")
        return row
    if err:
        row["diagnose_stderr"] = tail(err)
    d = json.load(open(out))
    row["diagnosis_keys"] = list(d.keys())
    rec = d.get("recommended") or []
    row.update(verdict=d.get("verdict"), conclusion=d.get("conclusion"), recommended=rec,
               named_first=bool(rec) and rec[0] == name, timings=d.get("timings"))
    ss = d.get("score_suspects") or []
    if isinstance(ss, dict):
        ss = ss.get("ranked") or ss.get("effects") or []
    if ss:
        top = ss[0]
        row["top_score_suspect"] = {k: top.get(k) for k in ("effect", "z", "significant")}
    mine = [s for s in ss if isinstance(s, dict) and s.get("effect") == name]
    if mine:
        row["score_suspect"] = {k: mine[0].get(k) for k in ("z", "significant", "params", "params_stderr")}
        row["score_rank"] = ss.index(mine[0]) + 1
    held = [s for s in (d.get("suspects") or []) if isinstance(s, dict) and s.get("effect") == name]
    if held:
        row["heldout_suspect"] = {k: held[0].get(k) for k in ("evidence", "z", "significant", "params")}
    conf = d.get("confirmation") or {}
    ce = [e for e in (conf.get("effects") or []) if isinstance(e, dict) and e.get("effect") == name]
    row["confirmed"] = bool(ce and ce[0].get("confirmed"))
    if ce:
        row["confirmation"] = {k: ce[0].get(k) for k in ("confirmed", "reason", "loglik_z", "params",
                                                          "params_stderr", "error")}
    refit_cfg = os.path.join(os.path.dirname(out), os.path.basename(out).replace(".json", "_report"), "refit.json")
    if refit and row["named_first"] and os.path.exists(refit_cfg):
        row["refit"] = refit_with_suspect(build, refit_cfg, threads)
    return row


def refit_with_suspect(build, refit_cfg, threads):
    """identify-vehs on diagnose's refit.json: Fp, Fm, dc, c and k with z against SUSPECT_TRUTH."""
    cfg = json.load(open(refit_cfg))
    rc, err, sec = run_tool(os.path.join(build, "identify-vehs"), refit_cfg + ".run.json", cfg, threads)
    row = {"seconds": sec, "rc": rc}
    if rc != 0 or not os.path.exists(cfg["output"]):
        row["error"] = tail(err) or f"exit {rc}"
        return row
    m = json.load(open(cfg["output"]))
    drift, sed = m.get("drift") or {}, (m.get("stderr") or {}).get("drift") or {}
    est, se = {}, {}
    for p, term in SUSPECT["drift"].items():
        est[p], se[p] = drift.get(term), sed.get(term)
    est["c"], se["c"] = (-drift["y"], sed.get("y")) if "y" in drift else (None, None)
    est["k"], se["k"] = (-drift["x"], sed.get("x")) if "x" in drift else (None, None)
    row["estimate"], row["stderr"] = est, se
    row["z"] = {p: (est[p] - t) / se[p] if est.get(p) is not None and se.get(p) else None
                for p, t in SUSPECT_TRUTH.items()}
    row["within_3se"] = all(z is not None and abs(z) <= 3 for z in row["z"].values())
    return row


def one_seed(seed, rec, args, work, threads):
    """rec: (measured x, true x, true y) of this seed."""
    tag = f"seed{seed}"
    x, xs, ys = rec
    per = len(x) // args.records
    csvs = []
    for r in range(args.records):
        p = os.path.join(work, f"{tag}_r{r}.csv")
        write_csv(p, x[r * per:(r + 1) * per])
        csvs.append(p)
    csv = csvs[0] if len(csvs) == 1 else csvs
    row = {"seed": seed, "rig": rig_check(xs, ys, two_d=args.two_d)}
    if args.diagnose_only:
        row["effect_fit"] = {"skipped": True, "error": "skipped (--diagnose-only)", "seconds": 0.0}
    else:
        row["effect_fit"] = fit_effect(args.build, work, csv, tag, threads, args.effect_library.split(","))
    row["diagnose"] = baseline_and_diagnose(args.build, work, csv, tag, threads, refit=not args.diagnose_only)
    return row


def fmt(v, s, z):
    if v is None:
        return "missing"
    return f"{v:.4g}±{s:.2g} ({z:+.2f})" if s else f"{v:.4g}±? "


def print_seed(r):
    e, d = r["effect_fit"], r["diagnose"]
    if "error" in e:
        first = f"identify with the effect FAILED ({e['seconds']:.1f} s): {e['error']}"
    else:
        first = (f"identify+effect {e['seconds']:.1f} s: "
                 + ", ".join(f"{p} {fmt(e['estimate'][p], e['stderr'][p], e['z'][p])}" for p in TRUTH)
                 + f"; within 3 SE: {'yes' if e['within_3se'] else 'NO'}")
    print(f"seed {r['seed']}: rms x {r['rig']['rms_x_m'] * 1e3:.3f} mm, rms y {r['rig']['rms_y_m_s'] * 1e3:.1f} mm/s")
    print("  " + first)
    if "error" in d:
        print(f"  baseline/diagnose FAILED: {d['error']}")
    else:
        top = d.get("top_score_suspect") or {}
        z = top.get("z")
        print(f"  baseline identify {d['identify_seconds']:.1f} s, diagnose {d['diagnose_seconds']:.1f} s: "
              f"verdict {d['verdict']}; recommended {d['recommended']}; named first "
              f"{'yes' if d['named_first'] else 'no'}; confirmed {'yes' if d['confirmed'] else 'no'}; "
              f"top score suspect {top.get('effect')} z {z if z is None else round(z, 2)}")
        print(f"  conclusion: {d['conclusion']}")
        rf = d.get("refit")
        if rf and "error" in rf:
            print(f"  refit.json FAILED ({rf['seconds']:.1f} s): {rf['error']}")
        elif rf:
            print(f"  refit.json {rf['seconds']:.1f} s: "
                  + ", ".join(f"{p} {fmt(rf['estimate'][p], rf['stderr'][p], rf['z'][p])}" for p in SUSPECT_TRUTH)
                  + f"; within 3 SE: {'yes' if rf['within_3se'] else 'NO'}")
    sys.stdout.flush()


def print_tables(rows):
    print(f"\nidentify-vehs, drift_library {rows and rows[0]['effect_fit'].get('library')} + directional_friction: "
          "estimate ± SE (z)")
    print("seed | " + " | ".join(f"{p} (truth {t:g})" for p, t in TRUTH.items()) + " | within | s")
    for r in rows:
        e = r["effect_fit"]
        if "error" in e:
            print(f"{r['seed']:4d} | error: {e['error'].splitlines()[-1] if e['error'] else ''}")
            continue
        print(f"{r['seed']:4d} | " + " | ".join(fmt(e["estimate"][p], e["stderr"][p], e["z"][p]) for p in TRUTH)
              + f" | {'yes' if e['within_3se'] else 'NO'} | {e['seconds']:.1f}")
    print(f"\nbaseline [x, y] + diagnose-vehs with user_effects [{json.dumps(SUSPECT)}]")
    print("seed | verdict | recommended | first | confirmed | top score suspect (z) | DF score z | id s | diag s")
    for r in rows:
        d = r["diagnose"]
        if "error" in d:
            print(f"{r['seed']:4d} | error: {d['error'].splitlines()[-1] if d['error'] else ''}")
            continue
        top = d.get("top_score_suspect") or {}
        dfz = (d.get("score_suspect") or {}).get("z")
        zt = top.get("z")
        print(f"{r['seed']:4d} | {d['verdict']} | {','.join(d['recommended']) or '-'} | "
              f"{'yes' if d['named_first'] else 'no'} | {'yes' if d['confirmed'] else 'no'} | "
              f"{top.get('effect')} ({'?' if zt is None else f'{zt:.2f}'}) | "
              f"{'?' if dfz is None else f'{dfz:.2f}'} | {d['identify_seconds']:.1f} | {d['diagnose_seconds']:.1f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=os.environ.get("VEHS_BUILD_DIR", "build"))
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--seed0", type=int, default=1)
    ap.add_argument("--samples", type=int, default=20000, help="samples per seed")
    ap.add_argument("--records", type=int, default=1, help="records the samples are cut into")
    ap.add_argument("--jobs", type=int, default=1, choices=(1, 2), help="seeds run at once")
    ap.add_argument("--json", default=None, help="write the per-seed results here")
    ap.add_argument("--effect-library", default="x",
                    help="drift_library of the fit with the effect (note: y is spanned by cp's and cm's terms)")
    ap.add_argument("--two-d", type=float, default=TWO_D, help="noise intensity 2D [m^2/s^3]")
    ap.add_argument("--check", action="store_true", help="check the generator only")
    ap.add_argument("--diagnose-only", action="store_true",
                    help="step 2's baseline and diagnosis only (no fit with the effect, no refit)")
    a = ap.parse_args()
    if a.check:
        return 0 if self_test() else 1
    a.build = os.path.abspath(a.build)
    for tool in ("identify-vehs", "diagnose-vehs"):
        if not os.access(os.path.join(a.build, tool), os.X_OK):
            sys.exit(f"{tool} not found in {a.build}")
    print(f"truth: k {K} 1/s^2, Fp {FP}, Fm {FM} m/s^2, cp {CP}, cm {CM} 1/s, 2D {a.two_d} m^2/s^3; dt {DT} s, "
          f"{SUB} Heun substeps, {a.samples} samples per seed in {a.records} record(s), "
          f"{NOISE_SHARE:.0%} sensor noise; user effect {json.dumps(EFFECT)}")
    seeds = list(range(a.seed0, a.seed0 + a.seeds))
    threads = 1 if a.jobs == 2 else 0
    t0 = time.perf_counter()
    xm, xs, ys = simulate(seeds, a.samples, two_d=a.two_d)  # all seeds at once (numpy across seeds)
    recs = {s: (xm[:, j], xs[:, j:j + 1], ys[:, j:j + 1]) for j, s in enumerate(seeds)}
    print(f"generated {len(seeds)} x {a.samples} samples in {time.perf_counter() - t0:.0f} s", flush=True)
    rows = []
    with tempfile.TemporaryDirectory(prefix="vehs-user-effect-") as work:
        if a.jobs == 1:
            for s in seeds:
                rows.append(one_seed(s, recs[s], a, work, threads))
                print_seed(rows[-1])
        else:
            with concurrent.futures.ThreadPoolExecutor(max_workers=2) as ex:
                futs = {s: ex.submit(one_seed, s, recs[s], a, work, threads) for s in seeds}
                for s in seeds:
                    rows.append(futs[s].result())
                    print_seed(rows[-1])
    print_tables(rows)
    n = len(rows)
    within = sum(bool(r["effect_fit"].get("within_3se")) for r in rows)
    first = sum(bool(r["diagnose"].get("named_first")) for r in rows)
    confirmed = sum(bool(r["diagnose"].get("confirmed")) for r in rows)
    sec = lambda key, sub: [r[key][sub] for r in rows if sub in r[key]]
    print(f"\nseconds (median, max): identify+effect {np.median(sec('effect_fit', 'seconds')):.1f}, "
          f"{max(sec('effect_fit', 'seconds')):.1f}; baseline identify "
          f"{np.median(sec('diagnose', 'identify_seconds')):.1f}, {max(sec('diagnose', 'identify_seconds')):.1f}"
          + (f"; diagnose {np.median(sec('diagnose', 'diagnose_seconds')):.1f}, "
             f"{max(sec('diagnose', 'diagnose_seconds')):.1f}" if sec('diagnose', 'diagnose_seconds') else "")
          + f"; study {time.perf_counter() - t0:.0f} s wall")
    refits = [r["diagnose"]["refit"] for r in rows if r["diagnose"].get("refit")]
    print(f"within 3 SE: {within}/{n} seeds; named first: {first}/{n}; confirmed: {confirmed}/{n}")
    print(f"refit.json run on {len(refits)}/{n} seeds (those named first), within 3 SE (Fp, Fm, dc, c, k): "
          f"{sum(bool(rf.get('within_3se')) for rf in refits)}/{len(refits)}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"truth": TRUTH, "effect": EFFECT, "samples": a.samples, "records": a.records,
                       "seeds": rows, "summary": {"within_3se": within, "named_first": first,
                                                  "confirmed": confirmed, "n": n}}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
