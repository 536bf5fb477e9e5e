#!/usr/bin/env python3
"""The cost of the likelihood's several starts: identify-vehs with the defaults (estimator auto:
brief fits from every moment fit, the full refinement from the highest) against the likelihood
started from one moment fit (estimator uli or forward, likelihood always), on a config's data.

Usage: likelihood_starts_cost.py [CONFIG ...]   (default: Silverbox's defaults and the quickstart)
Prints wall seconds and the final log L of each run."""
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
DEFAULT = ["data/silverbox/identify_defaults.json", "examples/quickstart/identify.json"]


def run(build, cfg):
    t0 = time.perf_counter()
    proc = subprocess.run([os.path.join(build, "identify-vehs"), cfg, "-q"], capture_output=True, text=True, cwd=ROOT)
    if proc.returncode != 0:
        sys.exit(f"identify-vehs {cfg}: {proc.stderr.strip()}")
    return time.perf_counter() - t0


def main():
    build = os.environ.get("VEHS_BIN_DIR", os.path.join(ROOT, "build"))
    work = tempfile.mkdtemp(prefix="vehs-starts-")
    for config in sys.argv[1:] or DEFAULT:
        base = json.load(open(os.path.join(ROOT, config)))
        rows = {}
        for est in ("auto", "uli", "forward"):
            c = dict(base, output=os.path.join(work, f"model_{est}.json"))
            if est != "auto":
                c["estimator"], c["likelihood"] = est, {"use": "always"}
            path = os.path.join(work, f"identify_{est}.json")
            json.dump(c, open(path, "w"))
            seconds = run(build, path)
            log_l = json.load(open(c["output"]))["likelihood"]["log_likelihood"]
            rows[est] = seconds
            print(f"{config}: {est:>8}: {seconds:6.1f} s, log L {log_l:.1f}")
        print(f"{config}: the defaults' starts cost {rows['auto'] / rows['uli']:.2f}x the uli start alone, "
              f"{rows['auto'] / rows['forward']:.2f}x the forward start alone")


if __name__ == "__main__":
    sys.exit(main())
