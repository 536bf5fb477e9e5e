#!/usr/bin/env python3
"""No text of a config, model or data file can run a command (issue 36).

Every figure is drawn by gnuplot. Each case puts a payload that would run `touch MARKER` (a file
outside the case folder) into a unit, a label, a segment name or an output folder, in every form
an attacker could use: a closing single quote followed by gnuplot's system(), a newline starting
a new gnuplot command, backquotes, and shell quoting and substitution for the paths. Each run
must leave no marker; a run that succeeds must have rendered its figures (so the text did reach
gnuplot), and one that refuses its input must do so with one line on stderr.

Usage: run_injection.py BIN_DIR [--only SUBSTRING] [--verbose]
"""
import argparse
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_bad_inputs import MODEL, make_fixtures  # noqa: E402  (the trial's fixtures)


LABEL_FORMS = {
    "quote then system()": "m'; system('touch {m}'); a='",
    "quote then system() with double quotes": "m'; system(\"touch {m}\"); a='",
    "newline then system()": "m\nsystem('touch {m}')\n",
    "carriage return then system()": "m\rsystem('touch {m}')\r",
    "backquotes": "m`touch {m}`",
    "double-quoted backquotes": "m\"`touch {m}`\"",
    "backslash before the quote": "m\\'; system('touch {m}'); a='\\",
    "macro": "@a'; a = \"system('touch {m}')\"; b='",
}
"""Texts for units and labels: each would touch its marker if pasted into a gnuplot string."""

PATH_FORMS = {
    "shell quote": "f'; touch {m}; echo '",
    "shell comment": "f'; touch {m} #",
    "command substitution": "r'$(touch {m})'",
    "backquotes": "r`touch {m}`",
    "gnuplot system()": "g'; system('touch {m}'); a='",
}
"""Folder names: each would touch its marker if pasted into a shell command or a gnuplot string."""


def payload(forms, markers):
    """One text holding every form, each touching its own marker: a run shows which form ran."""
    return " ".join(text.format(m=markers[name]) for name, text in forms.items())


def driven_fixtures(d):
    """A driven linear oscillator's record (t, x, u) and its model, for simulate-vehs validate."""
    import math
    rows = ["t,x,u"]
    x, v, dt = 0.0, 0.0, 0.01
    for k in range(2000):
        u = math.sin(0.7 * k * dt) + 0.5 * math.sin(2.3 * k * dt)
        rows.append(f"{k * dt:.4f},{x:.6f},{u:.6f}")
        for _ in range(10):
            a = -x - 0.2 * v + u
            x, v = x + v * dt / 10, v + a * dt / 10
    with open(os.path.join(d, "driven.csv"), "w") as f:
        f.write("\n".join(rows) + "\n")
    with open(os.path.join(d, "driven_model.json"), "w") as f:
        json.dump({"drift": {"x": -1.0, "y": -0.2, "u": 1.0}, "diffusion": {"1": 1e-4}}, f)


def cases(label_markers, path_markers):
    """(name, tool, config, files): `files` maps names to JSON written into the case folder."""
    text, folder = payload(LABEL_FORMS, label_markers), payload(PATH_FORMS, path_markers)
    # identify-vehs refuses a unit of more than one line, so its quotes are tried on one line too
    one_line = payload({k: v for k, v in LABEL_FORMS.items() if not any(c in v for c in "\n\r")}, label_markers)
    units = {"length": text, "time": "s"}
    model = dict(MODEL, units=units)
    files = {"model_u.json": model}
    fpk = {"grid": {"x": 60, "y": 60}, "output": "fpk.json", "figures": "figs"}
    validate = {"data": "driven.csv", "columns": {"x": "x", "u": "u"}, "dt": 0.01, "skip": 10, "figure": True}
    diagnose = {"data": ["data.csv"], "output": "diag.json", "replicates": 0, "suspects": False}
    return [
        ("units in a model file", "fpk-stationary", dict(fpk, model="model_u.json"), files),
        ("units in an inline model", "fpk-stationary", dict(fpk, model=model), {}),
        ("units on a sweep's figures", "fpk-stationary",
         dict(fpk, model="model_u.json", grid={"x": 50, "y": 50}, sweep={"2D": [0.01, 0.03, 2]}), files),
        ("units in the config", "identify-vehs",
         {"data": ["data.csv"], "output": "learned.json", "figures": "figs", "units": units}, {}),
        ("one-line units in the config", "identify-vehs",
         {"data": ["data.csv"], "output": "learned.json", "figures": "figs", "units": {"length": one_line}}, {}),
        ("units in the model file", "diagnose-vehs", dict(diagnose, model="model_u.json"), files),
        ("validate unit and segment name", "simulate-vehs",
         {"model": "driven_model.json",
          "validate": dict(validate, segments=[{"name": text, "first": 0, "last": 1500}], unit=text,
                           output="val.json")}, {}),
        ("figures folder", "fpk-stationary", dict(fpk, model="model.json", figures=folder), {}),
        ("figures folder", "identify-vehs", {"data": ["data.csv"], "output": "learned.json", "figures": folder}, {}),
        ("report folder", "diagnose-vehs", dict(diagnose, model="model.json", report=folder), {}),
        ("validate output name", "simulate-vehs",
         {"model": "driven_model.json",
          "validate": dict(validate, segments=[{"name": "a", "first": 0, "last": 1500}], output=folder + ".json")},
         {}),
    ]


def run(bindir, fixtures, work, markers, case, verbose):
    name, tool, config, files = case
    d = tempfile.mkdtemp(prefix="case_", dir=work)
    for f in os.listdir(fixtures):
        shutil.copy(os.path.join(fixtures, f), d)
    for f, content in files.items():
        with open(os.path.join(d, f), "w") as fh:
            json.dump(content, fh)
    with open(os.path.join(d, "cfg.json"), "w") as fh:
        json.dump(config, fh)
    p = subprocess.run([os.path.join(bindir, tool), "-q", "cfg.json"], cwd=d, capture_output=True, timeout=300,
                       env=dict(os.environ, OMP_NUM_THREADS="1"))
    err = p.stderr.decode("utf-8", "replace")
    problems = []
    for form, marker in markers.items():
        if os.path.exists(marker):
            problems.append(f"a command ran ({form})")
            os.remove(marker)
    if p.returncode == 0:
        svgs = glob.glob(os.path.join(d, "**", "*.svg"), recursive=True)
        if not svgs:
            problems.append("exit 0 but no figure rendered")
        if any(".vehs-staging" in s for s in svgs):
            problems.append("a staging folder was left")
    elif p.returncode >= 128 or p.returncode < 0:
        problems.append(f"killed by a signal (status {p.returncode})")
    elif len([ln for ln in err.splitlines() if ln.strip()]) != 1:
        problems.append(f"refused with {len(err.splitlines())} lines on stderr")
    if problems:
        print(f"FAIL {tool}: {name}: {'; '.join(problems)}\n     stderr: {err.strip()[:300]}")
    elif verbose:
        print(f"ok   {tool}: {name} (status {p.returncode}) {err.strip()[:120]}")
    shutil.rmtree(d, ignore_errors=True)
    return not problems


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bindir")
    ap.add_argument("--only", default="")
    ap.add_argument("--verbose", action="store_true")
    a = ap.parse_args()
    bindir = os.path.abspath(a.bindir)
    if shutil.which("gnuplot") is None:
        print("FAIL gnuplot is not on the PATH: the figures, and so this check, cannot run")
        return 1
    work = tempfile.mkdtemp(prefix="vi", dir="/tmp")  # short: the markers' paths go into folder names
    markers = {f"{kind}: {form}": os.path.join(work, f"{kind[0]}{i}")
               for kind, forms in (("label", LABEL_FORMS), ("path", PATH_FORMS)) for i, form in enumerate(forms)}
    label_markers = {form: markers[f"label: {form}"] for form in LABEL_FORMS}
    path_markers = {form: markers[f"path: {form}"] for form in PATH_FORMS}
    fixtures = os.path.join(work, "fixtures")
    os.mkdir(fixtures)
    make_fixtures(bindir, fixtures)
    driven_fixtures(fixtures)
    all_cases = [c for c in cases(label_markers, path_markers) if a.only in f"{c[1]}: {c[0]}"]
    failed = sum(not run(bindir, fixtures, work, markers, c, a.verbose) for c in all_cases)
    shutil.rmtree(work, ignore_errors=True)
    print(f"{len(all_cases) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
