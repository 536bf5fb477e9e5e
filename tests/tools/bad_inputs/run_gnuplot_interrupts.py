#!/usr/bin/env python3
"""An interrupt while gnuplot draws a figure stops the tool, gnuplot with it, and leaves nothing.

A stand-in gnuplot first on the PATH writes a partial figure and a log into its folder, says that
it started, and then waits. Each case sends SIGTERM to the tool, or SIGINT to the tool's whole
process group (Ctrl-C in a terminal), once the stand-in runs, and checks: exit status 128 +
signal, no file created or changed in the case folder (no figure folder, staging folder, .log or
partial .svg), and the stand-in gone (the tool stops its child).

Usage: run_gnuplot_interrupts.py BIN_DIR
"""
import json
import os
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_bad_inputs import make_fixtures, snapshot  # noqa: E402
from run_injection import driven_fixtures  # noqa: E402

STAND_IN = """#!/bin/sh
echo '<svg partial' > "$(basename "$1" .gp).svg"
echo "stand-in gnuplot $$" >&2
echo $$ > "{started}"
exec sleep 60
"""

CONFIGS = {
    "fpk-stationary": {"model": "model.json", "grid": {"x": 60, "y": 60}, "output": "fpk.json", "figures": "figs"},
    "identify-vehs": {"data": ["data.csv"], "output": "learned.json", "figures": "figs"},
    "diagnose-vehs": {"model": "model.json", "data": ["data.csv"], "output": "diag.json", "replicates": 0,
                      "suspects": False, "report": "rep"},
    "simulate-vehs": {"model": "driven_model.json",
                      "validate": {"data": "driven.csv", "columns": {"x": "x", "u": "u"}, "dt": 0.01, "skip": 10,
                                   "segments": [{"name": "a", "first": 0, "last": 1500}], "figure": True,
                                   "output": "val.json"}},
}


def alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    with open(f"/proc/{pid}/stat") as f:  # a zombie is gone for our purpose
        return f.read().split()[2] != "Z"


def run_case(bindir, fixtures, work, tool, sig, group):
    d = tempfile.mkdtemp(prefix="case_", dir=work)
    for f in os.listdir(fixtures):
        shutil.copy(os.path.join(fixtures, f), d)
    with open(os.path.join(d, "cfg.json"), "w") as f:
        json.dump(CONFIGS[tool], f)
    fake = os.path.join(work, f"bin_{os.path.basename(d)}")
    os.mkdir(fake)
    started = os.path.join(work, f"started_{os.path.basename(d)}")
    with open(os.path.join(fake, "gnuplot"), "w") as f:
        f.write(STAND_IN.format(started=started))
    os.chmod(os.path.join(fake, "gnuplot"), stat.S_IRWXU)
    before = snapshot(d)
    env = dict(os.environ, PATH=fake + os.pathsep + os.environ["PATH"], OMP_NUM_THREADS="1")
    p = subprocess.Popen([os.path.join(bindir, tool), "-q", "cfg.json"], cwd=d, env=env, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, start_new_session=True)
    problems = []
    t0 = time.time()
    while not os.path.exists(started) and p.poll() is None and time.time() - t0 < 120:
        time.sleep(0.05)
    if not os.path.exists(started):
        p.kill()
        out, err = p.communicate()
        return [f"gnuplot never started (status {p.returncode}): {err.decode()[-300:]}"]
    time.sleep(0.2)
    with open(started) as f:
        child = int(f.read().strip() or 0)
    if group:
        os.killpg(p.pid, sig)
    else:
        p.send_signal(sig)
    try:
        _, err = p.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        p.kill()
        _, err = p.communicate()
        problems.append("the tool did not stop within 30 s")
    if p.returncode != 128 + sig:
        problems.append(f"exit status {p.returncode}, not {128 + sig}: {err.decode().strip()[-200:]}")
    if child and alive(child):
        problems.append("gnuplot still runs")
        os.kill(child, signal.SIGKILL)
    after = snapshot(d)
    changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
    if changed:
        problems.append("files left: " + ", ".join(changed[:6]))
    shutil.rmtree(d, ignore_errors=True)
    return problems


def main():
    bindir = os.path.abspath(sys.argv[1])
    work = tempfile.mkdtemp(prefix="vehs_gnuplot_interrupts_")
    fixtures = os.path.join(work, "fixtures")
    os.mkdir(fixtures)
    make_fixtures(bindir, fixtures)
    driven_fixtures(fixtures)
    passed = failed = 0
    for tool in CONFIGS:
        for sig, group in ((signal.SIGTERM, False), (signal.SIGINT, True)):
            name = f"{tool}: {signal.Signals(sig).name}{' to the process group' if group else ''} while gnuplot runs"
            problems = run_case(bindir, fixtures, work, tool, sig, group)
            if problems:
                failed += 1
                print(f"FAIL {name}: {'; '.join(problems)}")
            else:
                passed += 1
                print(f"ok   {name}")
    shutil.rmtree(work, ignore_errors=True)
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
