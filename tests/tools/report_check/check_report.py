#!/usr/bin/env python3
"""The diagnose report as a reviewer opens it, checked in headless Chromium.

A driven rig (Duffing oscillator with a base-acceleration input and sensor noise, from this
script's own stochastic Heun stepper) goes through identify-vehs and diagnose-vehs; the report's
index.html is opened with `chromium --headless=new --dump-dom` and must
  - render (a DOM comes back, every embedded figure decoded: data-figures-loaded = n/n),
  - log nothing to the console (--enable-logging=stderr prints every console message and every
    uncaught error as a CONSOLE line; the page's own script logs nothing),
  - open with the top card holding the verdict, the next step and the parameter table (with
    standard errors and units),
  - show measured vs simulated with a fit percentage and the residual-input cross-correlation,
  - have no "Where the model fails" section when the verdict is adequate.

Usage: check_report.py BIN_DIR WORK_DIR. Skips (exit 0, with a message) when chromium is missing
and VEHS_REQUIRE_CHROMIUM is unset; fails when it is set.
"""
import json
import math
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile

K1, K3, BETA, GAMMA, A22 = 2500.0, 300.0, 5.0, 800.0, 2000.0
DT, NOISE_SD = 0.002, 0.003


def write_rig(path, n, seed):
    """t, x (mm, with white sensor noise), u (m/s^2): stochastic Heun, 10 substeps per sample."""
    rng = random.Random(seed)
    freqs = [2.0 + 18.0 * i / 11.0 for i in range(12)]
    phases = [rng.uniform(0, 2 * math.pi) for _ in freqs]
    amp = math.sqrt(2.0 / len(freqs))

    def drive(t):
        return amp * sum(math.sin(2 * math.pi * f * t + p) for f, p in zip(freqs, phases))

    def b2(x, y, u):
        return -K1 * x - K3 * x ** 3 - BETA * y + GAMMA * u

    sub = 10
    h = DT / sub
    sq = math.sqrt(A22 * h)
    x = y = t = 0.0
    with open(path, "w") as f:
        f.write("t,x,u\n")
        for i in range(n):
            f.write("%.6f,%.9g,%.9g\n" % (i * DT, x + NOISE_SD * rng.gauss(0, 1), drive(i * DT)))
            for _ in range(sub):
                dw = sq * rng.gauss(0, 1)
                u0, u1 = drive(t), drive(t + h)
                a0 = b2(x, y, u0)
                xp, yp = x + y * h, y + a0 * h + dw
                a1 = b2(xp, yp, u1)
                x += 0.5 * (y + yp) * h
                y += 0.5 * (a0 + a1) * h + dw
                t += h


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("FAILED: %s\n%s%s" % (" ".join(cmd), r.stdout, r.stderr))
    return r.stdout


def chromium_dom(html):
    """The DOM after load and the console lines of the page."""
    profile = tempfile.mkdtemp(prefix="vehs_report_check_")
    try:
        r = subprocess.run(
            ["chromium", "--headless=new", "--disable-gpu", "--no-sandbox", "--no-first-run",
             "--disable-background-networking", "--disable-component-update", "--disable-sync",
             "--enable-logging=stderr", "--v=0", "--user-data-dir=" + profile,
             "--virtual-time-budget=5000", "--dump-dom", "file://" + os.path.abspath(html)],
            capture_output=True, text=True, timeout=180)
    finally:
        shutil.rmtree(profile, ignore_errors=True)
    console = [l for l in r.stderr.splitlines() if ":CONSOLE" in l]
    return r.returncode, r.stdout, console


def section(dom, ident):
    m = re.search(r'<section id="%s"[^>]*>(.*?)</section>' % ident, dom, re.S)
    return m.group(1) if m else ""


def main():
    bin_dir, work = sys.argv[1], sys.argv[2]
    if shutil.which("chromium") is None:
        if os.environ.get("VEHS_REQUIRE_CHROMIUM"):
            sys.exit("FAILED: chromium is not installed and VEHS_REQUIRE_CHROMIUM is set "
                     "(scripts/install-deps.sh installs it)")
        print("SKIPPED: chromium is not installed (set VEHS_REQUIRE_CHROMIUM=1 to make this a failure)")
        return
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    rig = os.path.join(work, "rig.csv")
    write_rig(rig, 40000, 5)
    units = {"length": "mm", "time": "s", "input": "m/s^2"}
    ident = {"data": [rig], "output": os.path.join(work, "model.json"), "units": units,
             "drift_library": ["x", "x^3", "y", "u"], "diffusion_library": ["1"]}
    with open(os.path.join(work, "identify.json"), "w") as f:
        json.dump(ident, f)
    run([os.path.join(bin_dir, "identify-vehs"), os.path.join(work, "identify.json"), "-q"])
    report = os.path.join(work, "report")
    diag = {"model": os.path.join(work, "model.json"), "data": [rig], "units": units,
            "output": os.path.join(work, "diagnosis.json"), "report": report,
            "replicates": 2, "parameter_draws": 2, "fpk": False}
    with open(os.path.join(work, "diagnose.json"), "w") as f:
        json.dump(diag, f)
    run([os.path.join(bin_dir, "diagnose-vehs"), os.path.join(work, "diagnose.json"), "-q"])
    with open(os.path.join(work, "diagnosis.json")) as f:
        verdict = json.load(f)["verdict"]

    html = os.path.join(report, "index.html")
    rc, dom, console = chromium_dom(html)
    problems = []
    if rc != 0 or "<body" not in dom:
        problems.append("chromium did not render the page (exit %d)" % rc)
    loaded = re.search(r'data-figures-loaded="(\d+)/(\d+)"', dom)
    if not loaded or loaded.group(1) != loaded.group(2) or loaded.group(2) == "0":
        problems.append("figures not all decoded: %s" % (loaded.group(0) if loaded else "no status"))
    if console:
        problems.append("console messages: " + " | ".join(console))
    card = section(dom, "top-card")
    if not card:
        problems.append("no top card (section id=top-card)")
    elif not dom[dom.find("<section"):].startswith('<section id="top-card"'):
        problems.append("the top card is not the first section")
    for what, pattern in [("the verdict", r"Verdict: (ADEQUATE|INADEQUATE)"), ("the next step", r"Next step"),
                          ("the parameter table", r"<th>parameter</th><th>value</th><th>standard error</th><th>unit</th>"),
                          ("the drive's coefficient with its unit", r"drift\[u\]</td><td>[^<]+</td><td>[^<]+</td><td>\(mm/s\^2\)/\(m/s\^2\)")]:
        if not re.search(pattern, card):
            problems.append("the top card lacks %s" % what)
    if not re.search(r"fit -?[0-9.]+ %", dom):
        problems.append("no fit percentage of measured vs simulated")
    for fig in ("measured_vs_simulated", "residual_input_xcorr"):
        if 'id="%s"' % fig not in dom:
            problems.append("no figure " + fig)
    if verdict == "adequate" and "Where the model fails" in dom:
        problems.append("an adequate model has a 'Where the model fails' section")
    if problems:
        sys.exit("FAILED (%s):\n  " % html + "\n  ".join(problems))
    print("report OK: %s (verdict %s, %s figures, top card with verdict, next step and parameters)"
          % (html, verdict, loaded.group(2)))


if __name__ == "__main__":
    main()
