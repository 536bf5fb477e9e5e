#!/usr/bin/env python3
"""Outputs survive kills, concurrent history appends and full disks (issue 36).

Kill trial, for simulate-vehs (statistics + records), fpk-stationary (json + density + figures),
diagnose-vehs (json + report + history) and identify-vehs (model + figures): a first run writes
the old outputs; then, for every k from 1 until the run is no longer killed, a copy of that
folder gets
  run 2  other settings, killed by SIGKILL just before the k-th rename of its commit
         (VEHS_TEST_KILL_AT_RENAME=k, docs/outputs.md),
  run 3  the same settings, which must repair what run 2 left (one stderr line) and is itself
         killed at its first rename,
  check  every output file is as run 1 left it, or every one as run 2 meant it (its staged
         files count as written): never a mix, no stray file,
  run 4  a normal run: status 0, no .vehs-staging.*, .vehs-tmp.* or lock file left.
History trial: 4 processes x 2 diagnose-vehs runs appending to one history file keep 8 entries.
Full-disk trial: identify-vehs and fpk-stationary with figures under RLIMIT_FSIZE (SIGXFSZ
ignored, so writes fail with EFBIG): status 1, one stderr line naming EFBIG's "File too large",
nothing left in the folder.

Usage: run_commit_safety.py BIN_DIR [--only kill|history|disk] [--keep DIR]
"""
import argparse
import concurrent.futures
import hashlib
import json
import os
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time

MODEL = {"drift": {"x": -1.0, "x^3": 7.7, "x^5": -16.3, "x^7": 12.5, "x^9": -3.1, "y": -0.1},
         "diffusion": {"1": 0.02, "x^2": 0.01}}
FPK_MODEL = {"drift": {"x": -1.0, "x^3": -1.0, "y": -0.2}, "diffusion": {"1": 0.05}}  # resolved on 40x40
FIXTURES = {"model.json", "fpk_model.json", "data.csv", "bin/sh"}
DIAGNOSE = {"model": "model.json", "data": ["data.csv"], "replicates": 0, "suspects": False,
            "score_suspects": False, "confirm": False, "fpk": False, "parameter_uncertainty": "off"}

# tool -> (old settings, new settings); outputs in sub-folders so that a commit spans folders
CASES = {
    "simulate-vehs": (
        {"model": "model.json", "trajectories": 2, "duration": 5, "dt": 0.01, "seed": 1, "output": "out/sim.csv",
         "statistics": {"output": "out/st.json", "grid": {"x": [-1.5, 1.5, 8], "y": [-1.5, 1.5, 8]}}},
        {"seed": 2}),
    "fpk-stationary": (
        {"model": "fpk_model.json", "grid": {"x": 40, "y": 40}, "output": "fpk.json", "density": "out/density.csv",
         "figures": "figs"},
        {"grid": {"x": 44, "y": 44}}),
    "diagnose-vehs": (
        dict(DIAGNOSE, output="diag.json", report="rep", history="hist.json", label="old"),
        {"label": "new"}),
    "identify-vehs": (
        {"data": ["data.csv"], "output": "learned.json", "figures": "figs", "drift_library": {"K1": 11, "K2": 3}},
        {"drift_library": {"K1": 9, "K2": 3}}),
}


def run_tool(bindir, tool, folder, config, kill_at=None, name="cfg.json", preexec=None, timeout=120, plots=True):
    with open(os.path.join(folder, name), "w") as f:
        json.dump(config, f)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    if not plots:  # a PATH without gnuplot: figures are scripts and CSVs (diagnose draws a dozen; time)
        env["PATH"] = os.path.join(folder, "bin")
    env.pop("VEHS_TEST_KILL_AT_RENAME", None)
    if kill_at is not None:
        env["VEHS_TEST_KILL_AT_RENAME"] = str(kill_at)
    p = subprocess.Popen([os.path.join(bindir, tool), "-q", "--threads", "1", name], cwd=folder, env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, preexec_fn=preexec)
    out, err = p.communicate(timeout=timeout)
    return p.pid, p.returncode, err


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def is_bookkeeping(name):
    return name.startswith(".vehs-") or name.endswith(".lock")


def state(folder):
    """{relative path: hash} of the outputs (no fixtures, configs, staging folders or locks)."""
    s = {}
    for root, dirs, files in os.walk(folder):
        dirs[:] = [d for d in dirs if not d.startswith(".vehs-staging.")]
        for n in files:
            rel = os.path.relpath(os.path.join(root, n), folder)
            if rel in FIXTURES or rel.endswith("cfg.json") or is_bookkeeping(n):
                continue
            s[rel] = digest(os.path.join(root, n))
    return s


def intended(folder, pid):
    """The outputs as the killed run `pid` meant them: what is in place, its staged files over it."""
    s = state(folder)
    for root, dirs, files in os.walk(folder):
        if os.path.basename(root) == f".vehs-staging.{pid}":
            for n in files:
                if not is_bookkeeping(n):
                    rel = os.path.relpath(os.path.join(os.path.dirname(root), n), folder)
                    s[rel] = digest(os.path.join(root, n))
    return s


def leftovers(folder):
    return sorted(os.path.relpath(os.path.join(root, n), folder)
                  for root, dirs, files in os.walk(folder) for n in dirs + files if is_bookkeeping(n))


def make_fixtures(bindir, folder):
    with open(os.path.join(folder, "model.json"), "w") as f:
        json.dump(MODEL, f)
    with open(os.path.join(folder, "fpk_model.json"), "w") as f:
        json.dump(FPK_MODEL, f)
    os.makedirs(os.path.join(folder, "bin"))
    os.symlink(shutil.which("sh") or "/bin/sh", os.path.join(folder, "bin", "sh"))
    gen = {"model": "model.json", "trajectories": 4, "duration": 60, "dt": 0.01, "seed": 5,
           "x0": {"uniform": [-1.0, 1.0]}, "record_velocity": False, "output": "data.csv"}
    _, status, err = run_tool(bindir, "simulate-vehs", folder, gen, name="gen.json")
    os.remove(os.path.join(folder, "gen.json"))
    if status != 0:
        raise SystemExit("fixtures: simulate-vehs failed: " + err)


def mismatch(got, old, new):
    def diff(ref):
        return sorted(p for p in set(got) | set(ref) if got.get(p) != ref.get(p))
    return [] if got in (old, new) else [f"not old: {diff(old)[:4]}; not new: {diff(new)[:4]}"]


def kill_one(bindir, base, tool, k, workdir):
    """Runs 2-4 for rename k in a copy of `base`; returns (problems, run 2 was killed)."""
    old_cfg, change = CASES[tool]
    new_cfg = dict(old_cfg, **change)
    plots = tool != "diagnose-vehs"

    def run(*args, **kw):
        return run_tool(*args, plots=plots, **kw)

    d = os.path.join(workdir, f"{tool}-k{k}")
    shutil.copytree(base, d, symlinks=True)
    old = state(d)
    pid, status, err = run(bindir, tool, d, new_cfg, kill_at=k)
    if status == 0:
        return [], False
    if status != -signal.SIGKILL:
        return [f"{tool} k={k}: run 2 status {status}, not SIGKILL: {err.strip()[:200]}"], False
    new = intended(d, pid)
    problems = []
    _, status3, err3 = run(bindir, tool, d, new_cfg, kill_at=1)
    if status3 != -signal.SIGKILL:
        problems.append(f"run 3 status {status3} (expected SIGKILL at rename 1): {err3.strip()[:200]}")
    if "interrupted run" not in err3:
        problems.append(f"run 3 printed no repair line: {err3.strip()[:200]!r}")
    got = state(d)
    problems += mismatch(got, old, new)
    entries_before = None
    if tool == "diagnose-vehs":
        entries_before = len(json.load(open(os.path.join(d, "hist.json")))["entries"])
    _, status4, err4 = run(bindir, tool, d, new_cfg)
    if status4 != 0:
        problems.append(f"run 4 status {status4}: {err4.strip()[:200]}")
    if leftovers(d):
        problems.append(f"left after run 4: {leftovers(d)}")
    if tool == "diagnose-vehs" and status4 == 0:
        after = len(json.load(open(os.path.join(d, "hist.json")))["entries"])
        if after != entries_before + 1:
            problems.append(f"history: {entries_before} entries before run 4, {after} after")
    if not problems:
        shutil.rmtree(d)
    return [f"{tool} k={k}: {p}" for p in problems], True


def kill_trial(bindir, fixtures, workdir):
    problems = []
    for tool, (old_cfg, _) in CASES.items():
        base = os.path.join(workdir, f"{tool}-base")
        shutil.copytree(fixtures, base, symlinks=True)
        _, status, err = run_tool(bindir, tool, base, old_cfg, plots=tool != "diagnose-vehs")
        if status != 0:
            problems.append(f"{tool}: the first run failed ({status}): {err.strip()[:200]}")
            continue
        t0, killed, done = time.time(), 0, False
        with concurrent.futures.ThreadPoolExecutor(2) as pool:  # two renames at a time
            for k in range(1, 200, 2):
                for p, was_killed in pool.map(lambda kk: kill_one(bindir, base, tool, kk, workdir), (k, k + 1)):
                    problems += p
                    killed += was_killed
                    done = done or not was_killed
                if done:
                    break
        print(f"  {tool}: killed at renames 1..{killed} ({time.time() - t0:.1f} s)")
        if killed < 3:
            problems.append(f"{tool}: only {killed} commit renames were killed (VEHS_TEST_KILL_AT_RENAME ignored?)")
    return problems


def history_trial(bindir, fixtures, workdir, processes=4, runs=2):
    d = os.path.join(workdir, "history")
    shutil.copytree(fixtures, d, symlinks=True)

    def worker(i):
        errs = []
        for r in range(runs):
            cfg = dict(DIAGNOSE, output=f"diag{i}.json", report=f"rep{i}", history="hist.json", label=f"p{i}r{r}")
            _, status, err = run_tool(bindir, "diagnose-vehs", d, cfg, name=f"cfg{i}.json")
            if status != 0:
                errs.append(f"process {i} run {r}: status {status}: {err.strip()[:200]}")
        return errs

    with concurrent.futures.ThreadPoolExecutor(processes) as pool:
        problems = [e for errs in pool.map(worker, range(processes)) for e in errs]
    labels = sorted(e["label"] for e in json.load(open(os.path.join(d, "hist.json")))["entries"])
    want = sorted(f"p{i}r{r}" for i in range(processes) for r in range(runs))
    if labels != want:
        problems.append(f"history: {len(labels)} of {len(want)} entries kept ({labels})")
    if leftovers(d):
        problems.append(f"history: left {leftovers(d)}")
    return problems


def disk_trial(bindir, fixtures, workdir):
    cases = [("identify-vehs", {"data": ["data.csv"], "output": "learned.json", "figures": "figs"}),
             ("fpk-stationary", {"model": "fpk_model.json", "grid": {"x": 40, "y": 40}, "output": "fpk.json",
                                 "figures": "figs"})]
    problems = []
    for tool, cfg in cases:
        for limit in (2000, 12000):
            d = os.path.join(workdir, f"disk-{tool}-{limit}")
            shutil.copytree(fixtures, d, symlinks=True)
            with open(os.path.join(d, "cfg.json"), "w") as f:
                json.dump(cfg, f)
            before = sorted(os.listdir(d))

            def full_disk(limit=limit):
                signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
                resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

            _, status, err = run_tool(bindir, tool, d, cfg, preexec=full_disk)
            lines = err.strip().splitlines()
            after = sorted(os.listdir(d))
            where = f"{tool} with files limited to {limit} bytes"
            if status != 1:
                problems.append(f"{where}: status {status}, expected 1")
            if len(lines) != 1:
                problems.append(f"{where}: {len(lines)} stderr lines: {lines[:3]}")
            elif "File too large" not in lines[0]:  # the write's own error (EFBIG), not a guess
                problems.append(f"{where}: the error does not say why: {lines[0]}")
            if after != before:
                problems.append(f"{where}: the folder changed: {sorted(set(after) ^ set(before))}")
    return problems


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bindir")
    ap.add_argument("--only", choices=["kill", "history", "disk"])
    ap.add_argument("--keep")
    a = ap.parse_args()
    a.bindir = os.path.abspath(a.bindir)
    workdir = a.keep or tempfile.mkdtemp(prefix="vehs_commit_safety_")
    os.makedirs(workdir, exist_ok=True)
    fixtures = os.path.join(workdir, "fixtures")
    os.makedirs(fixtures, exist_ok=True)
    make_fixtures(a.bindir, fixtures)
    problems = []
    for name, trial in (("kill", kill_trial), ("history", history_trial), ("disk", disk_trial)):
        if a.only in (None, name):
            t0 = time.time()
            p = trial(a.bindir, fixtures, workdir)
            print(f"{name}: {len(p)} problems ({time.time() - t0:.1f} s)")
            problems += p
    for p in problems:
        print("FAIL", p)
    if not a.keep and not problems:
        shutil.rmtree(workdir)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
