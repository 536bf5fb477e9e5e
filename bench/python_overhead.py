"""Python and Dask against the CLI (issue 16), run by bench/python.sh:

1. The Fig. 5a sweep (data/fpk/fig5a.json: 7 x 7 points, 200^2 cells): fpk-stationary on 2
   threads vs vehs.dask.sweep on a LocalCluster of 2 single-thread workers (2 tasks, and one task
   per point); the same E[Y^2] at every point (bitwise), wall times, and the overhead per task.
2. identify on 10^7 samples (the paper's data: 100 records x 10^5): identify-vehs on the .npy
   (whole run, and the identification alone as it reports it) vs vehs.identify on the same array
   in memory (one copy into the library) and on Records (no copy); wall times, best of REPEATS,
   the same threads.
"""
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import vehs
import vehs.dask

REPO = Path(__file__).resolve().parents[1]
BIN = Path(os.environ.get("VEHS_BIN_DIR", REPO / "build"))
REPEATS = int(os.environ.get("REPEATS", "3"))


def run_cli(tool, config, work):
    path = Path(work) / f"{tool}.json"
    path.write_text(json.dumps(config))
    start = time.perf_counter()
    subprocess.run([str(BIN / tool), str(path), "-q"], cwd=REPO, check=True)
    return time.perf_counter() - start


def sweep_study(work):
    import distributed

    cfg = json.loads((REPO / "data/fpk/fig5a.json").read_text())
    cfg.pop("figures")
    cfg["output"] = str(Path(work) / "fig5a.json")
    cli_times = [run_cli("fpk-stationary", cfg, work) for _ in range(REPEATS)]
    ref = json.loads(Path(cfg["output"]).read_text())["sweep"]
    model = vehs.Model.load(REPO / cfg["model"])
    count = len(ref["points"])
    # the CLI also solves the base model once before its sweep: time that alone to compare sweeps
    base_times = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        vehs.stationary(model, grid=cfg["grid"])
        base_times.append(time.perf_counter() - start)
    start = time.perf_counter()
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        startup = time.perf_counter() - start
        client.run(lambda: __import__("vehs"))  # workers import the package once
        rows = []
        for blocks in (2, count):
            times = []
            for _ in range(REPEATS):
                got = vehs.dask.sweep(client, model, cfg["sweep"], grid=cfg["grid"], blocks=blocks)
                times.append(got["seconds"])
                same = all(p == q for p, q in zip(got["points"], ref["points"]))
                assert same and len(got["points"]) == count, "dask sweep differs from the CLI sweep"
            rows.append((blocks, min(times), got["task_seconds"]))
    cli_sweep = min(cli_times) - min(base_times)
    print(f"Fig. 5a sweep, {count} points, grid {cfg['grid']}: E[X^2], E[Y^2], E[XY], wells identical to the CLI at every point")
    print(f"  fpk-stationary (2 threads): {min(cli_times):.2f} s wall, of which the base-model solve "
          f"{min(base_times):.2f} s: sweep {cli_sweep:.2f} s")
    print(f"  LocalCluster start (2 worker processes): {startup:.2f} s (once per session, not counted)")
    for blocks, t, task_seconds in rows:
        per_task = (t - cli_sweep) / blocks
        print(f"  vehs.dask.sweep, {blocks:3d} tasks: {t:.2f} s wall = {t / cli_sweep:.3f} x the CLI sweep; "
              f"overhead {per_task * 1e3:+.0f} ms per task (sum of task times {sum(task_seconds):.2f} s)")


def identify_study(work):
    npy = Path(work) / "paper.npy"
    sim = json.loads((REPO / "data/paper/simulate.json").read_text())
    sim["output"] = str(npy)
    run_cli("simulate-vehs", sim, work)
    cfg = {"data": [str(npy)], "output": str(Path(work) / "learned.json")}
    cli, cli_identify = [], []
    for _ in range(REPEATS):
        cli.append(run_cli("identify-vehs", cfg, work))
        cli_identify.append(json.loads(Path(cfg["output"]).read_text())["fit"]["seconds"])
    x = np.ascontiguousarray(np.load(npy)["x"].reshape(sim["trajectories"], -1))  # the array in memory
    array_times, records_times = [], []
    for _ in range(REPEATS):
        start = time.perf_counter()
        model, report = vehs.identify(x, dt=sim["dt"])
        array_times.append(time.perf_counter() - start)
    records = vehs.as_records(x, dt=sim["dt"])
    for _ in range(REPEATS):
        start = time.perf_counter()
        vehs.identify(records)
        records_times.append(time.perf_counter() - start)
    learned = vehs.Model.load(cfg["output"])
    same = all(model.to_dict()["drift"][k] == v for k, v in learned.drift.items())
    ident = min(cli_identify)
    print(f"identify, {x.size:.0e} samples, {vehs.max_threads()} threads, best of {REPEATS} (wall):")
    print(f"  identify-vehs, whole run (reads the .npy, writes the model): {min(cli):.3f} s")
    print(f"  identify-vehs, the identification itself (its fit.seconds):  {ident:.3f} s")
    print(f"  vehs.identify(array) (one copy in):  {min(array_times):.3f} s = {min(array_times) / ident:.3f} x the "
          f"identification, {min(array_times) / min(cli):.3f} x the whole run")
    print(f"  vehs.identify(Records) (no copy):    {min(records_times):.3f} s = {min(records_times) / ident:.3f} x the "
          f"identification, {min(records_times) / min(cli):.3f} x the whole run")
    print(f"  drift coefficients bitwise equal to the CLI's: {same}")


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as work:
        which = sys.argv[1:] or ["sweep", "identify"]
        if "sweep" in which:
            sweep_study(work)
        if "identify" in which:
            identify_study(work)
