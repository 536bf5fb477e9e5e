"""Python and Dask against the CLI (issue 16), run by bench/python.sh:

1. The Fig. 5a sweep (data/fpk/fig5a.json: 7 x 7 points, 200^2 cells): fpk-stationary on 2
   threads vs vehs.dask.sweep on a LocalCluster of 2 single-thread workers (its default tasks and
   2 tasks, or BLOCKS=default,2,8,49); the same E[Y^2] at every point (bitwise), wall and CPU times (the workers' CPU
   seconds from inside them), and the overhead per task.
2. identify on 10^7 samples (the paper's data: 100 records x 10^5): identify-vehs on the .npy
   (whole run, and its work in memory as it reports it: fit.in_memory_seconds, everything but
   reading the .npy and writing the model) vs vehs.identify on the same array in memory (a
   C-contiguous float64 array: read in place, no copy) and on Records (no copy), whose report holds the same key (the binding's
   overhead: the call's wall time less it); wall and CPU times, best of REPEATS, the same threads. The load average is printed before and after each study.
"""
import json
import os
import resource
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
# tasks per Dask sweep: "default" (vehs.dask.sweep's choice: one per point up to 16 per worker) or a number
BLOCKS = [None if b == "default" else int(b) for b in os.environ.get("BLOCKS", "default,2").split(",") if b]


def child_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_cli(tool, config, work, cpu=None):
    """Wall seconds of one run of `tool` (its CPU seconds appended to `cpu` when given)."""
    path = Path(work) / f"{tool}.json"
    path.write_text(json.dumps(config))
    cpu0 = child_cpu()
    start = time.perf_counter()
    subprocess.run([str(BIN / tool), str(path), "-q"], cwd=REPO, check=True)
    wall = time.perf_counter() - start
    if cpu is not None:
        cpu.append(child_cpu() - cpu0)
    return wall


def load():
    return "load average " + ", ".join(f"{v:.1f}" for v in os.getloadavg())


def workers_cpu(client):
    """CPU seconds used so far by the worker processes (all their threads), summed."""
    return sum(client.run(time.process_time).values())


def sweep_study(work):
    import distributed

    cfg = json.loads((REPO / "data/fpk/fig5a.json").read_text())
    cfg.pop("figures")
    cfg["output"] = str(Path(work) / "fig5a.json")
    cli_cpu = []
    print(f"before: {load()}")
    cli_times = [run_cli("fpk-stationary", cfg, work, cli_cpu) for _ in range(REPEATS)]
    ref = json.loads(Path(cfg["output"]).read_text())["sweep"]
    model = vehs.Model.load(REPO / cfg["model"])
    count = len(ref["points"])
    # the CLI also solves the base model once before its sweep: time that alone to compare sweeps
    base_times, base_cpu = [], []
    for _ in range(REPEATS):
        start, cpu0 = time.perf_counter(), time.process_time()
        vehs.stationary(model, grid=cfg["grid"])
        base_times.append(time.perf_counter() - start)
        base_cpu.append(time.process_time() - cpu0)
    start = time.perf_counter()
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        startup = time.perf_counter() - start
        client.run(lambda: __import__("vehs"))  # workers import the package once
        rows = []
        for blocks in BLOCKS:
            times, cpus = [], []
            for _ in range(REPEATS):
                cpu0, client0 = workers_cpu(client), time.process_time()
                got = vehs.dask.sweep(client, model, cfg["sweep"], grid=cfg["grid"], blocks=blocks)
                times.append(got["seconds"])
                cpus.append(workers_cpu(client) - cpu0 + time.process_time() - client0)
                same = all(p == q for p, q in zip(got["points"], ref["points"]))
                assert same and len(got["points"]) == count, "dask sweep differs from the CLI sweep"
            rows.append((got["tasks"], min(times), min(cpus), got["task_seconds"]))
    cli_sweep = min(cli_times) - min(base_times)
    cli_sweep_cpu = min(cli_cpu) - min(base_cpu)
    print(f"Fig. 5a sweep, {count} points, grid {cfg['grid']}: E[X^2], E[Y^2], E[XY], wells identical to the CLI at every point")
    print(f"  fpk-stationary (2 threads): {min(cli_times):.2f} s wall ({min(cli_cpu):.1f} CPU s), of which the base-model "
          f"solve {min(base_times):.2f} s ({min(base_cpu):.1f} CPU s): sweep {cli_sweep:.2f} s wall, {cli_sweep_cpu:.1f} CPU s")
    print(f"  LocalCluster start (2 worker processes): {startup:.2f} s (once per session, not counted)")
    for blocks, t, cpu, task_seconds in rows:
        per_task = (t - cli_sweep) / blocks
        print(f"  vehs.dask.sweep, {blocks:3d} tasks: {t:.2f} s wall = {t / cli_sweep:.3f} x the CLI sweep; "
              f"overhead {per_task * 1e3:+.0f} ms per task; {cpu:.1f} CPU s (workers + client) = "
              f"{cpu / cli_sweep_cpu:.3f} x the CLI sweep's, {(cpu - cli_sweep_cpu) / blocks * 1e3:+.0f} ms per task; "
              f"task times {min(task_seconds):.2f} to {max(task_seconds):.2f} s")
    print(f"after: {load()}")


def identify_study(work):
    npy = Path(work) / "paper.npy"
    sim = json.loads((REPO / "data/paper/simulate.json").read_text())
    sim["output"] = str(npy)
    run_cli("simulate-vehs", sim, work)
    cfg = {"data": [str(npy)], "output": str(Path(work) / "learned.json")}
    cli, cli_cpu, cli_fit, cli_memory = [], [], [], []
    print(f"before: {load()}")
    for _ in range(REPEATS):
        cli.append(run_cli("identify-vehs", cfg, work, cli_cpu))
        fit = json.loads(Path(cfg["output"]).read_text())["fit"]
        cli_fit.append(fit["seconds"])
        cli_memory.append(fit["in_memory_seconds"])
    x = np.ascontiguousarray(np.load(npy)["x"].reshape(sim["trajectories"], -1))  # the array in memory
    # the CLI's dt, as its reader estimates it from the file's t column (1.5e-18 below 0.001 for
    # these 10^7 samples: with dt = 0.001 itself the coefficients differ at 1e-13 relative)
    dt = json.loads(Path(cfg["output"]).read_text())["data"]["dt"]

    def timed(call):
        start, cpu0 = time.perf_counter(), time.process_time()
        out = call()
        return out, time.perf_counter() - start, time.process_time() - cpu0

    array_runs = [timed(lambda: vehs.identify(x, dt=dt)) for _ in range(REPEATS)]
    model = array_runs[0][0][0]
    records = vehs.as_records(x, dt=dt)
    records_runs = [timed(lambda: vehs.identify(records)) for _ in range(REPEATS)]
    learned = vehs.Model.load(cfg["output"])
    same = all(model.to_dict()["drift"][k] == v for k, v in learned.drift.items())
    memory = min(cli_memory)
    print(f"identify, {x.size:.0e} samples, {vehs.max_threads()} threads, best of {REPEATS} (wall; CPU s beside):")
    print(f"  identify-vehs, whole run (reads the .npy, writes the model): {min(cli):.3f} s ({min(cli_cpu):.2f} CPU s)")
    print(f"  identify-vehs, its work in memory (fit.in_memory_seconds):  {memory:.3f} s "
          f"(the identification itself, fit.seconds: {min(cli_fit):.3f} s)")
    for name, runs in (("vehs.identify(array) (no copy):   ", array_runs), ("vehs.identify(Records) (no copy):  ", records_runs)):
        wall, cpu = min(r[1] for r in runs), min(r[2] for r in runs)
        own = min(r[0][1]["fit"]["in_memory_seconds"] for r in runs)
        print(f"  {name} {wall:.3f} s ({cpu:.2f} CPU s) = {wall / memory:.3f} x the CLI's work in memory "
              f"(its own in_memory_seconds {own:.3f} s: binding {1e3 * (wall - own):+.1f} ms); "
              f"{wall / min(cli):.3f} x the whole run (CPU {cpu / min(cli_cpu):.3f} x)")
    viewed = records._core.is_view("x") and records._core.address("x") == x.ctypes.data
    print(f"  drift coefficients bitwise equal to the CLI's: {same}; the array read in place (no copy): {viewed}")
    print(f"after: {load()}")


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as work:
        which = sys.argv[1:] or ["sweep", "identify"]
        if "sweep" in which:
            sweep_study(work)
        if "identify" in which:
            identify_study(work)
