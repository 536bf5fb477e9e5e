"""Sweeps and Monte Carlo ensembles on dask.distributed, merged exactly as one machine merges them.

* :func:`sweep` splits fpk-stationary's parameter sweep into blocks of points. The client makes
  the sweep's plan once (the grid: the envelope of all points' automatic domains, and the points
  without a domain; ``fpk::plan_sweep``) and ships it with every block; each worker process
  makes the symbolic factorisation (of the first solvable point, as the single-machine sweep
  does) once per sweep and keeps it for all its blocks. A block solves only its own points
  (``SweepOptions::block_first/last``), so the merged points are the CLI's, bit for bit.
* :func:`ensemble` splits a Monte Carlo ensemble into blocks of records. A record's random
  stream is keyed by its id (``first_record``), so a block's records are the same records; the
  merge combines the record means (or, for fewer than 16 records, every record's batch means) in
  record order with the library's own ``combine_independent`` and adds the histogram counts, as
  ``simulate_statistics`` does on one machine.

``client`` is a ``distributed.Client``: ``Client(LocalCluster(n_workers=2, threads_per_worker=1))``
here, ``Client("tcp://scheduler:8786")`` on a cluster (the workers need vehs installed).
"""
import json
import math

from . import _vehs
from .model import Model
from .options import options_json


def _worker_threads(threads):
    if threads:
        _vehs.set_threads(int(threads))


# Worker-level cache of analysed sweep plans (a worker process solves many blocks of one sweep):
# keyed by the model, the options and the client's plan, so a block reuses the symbolic
# factorisation its worker made for an earlier block of the same sweep.
_PLANS = {}
_PLANS_KEPT = 4


def _analysed_plan(model, model_key, text, plan_json):
    key = (model_key, text, plan_json)
    plan = _PLANS.get(key)
    if plan is None:
        if len(_PLANS) >= _PLANS_KEPT:
            _PLANS.pop(next(iter(_PLANS)))
        plan = _PLANS[key] = _vehs.SweepPlan.analysed(model._core, text, plan_json)
    return plan


def _sweep_block(model_dict, text, plan_json, first, last, threads):
    _worker_threads(threads)
    model = Model.from_dict(model_dict)
    plan = _analysed_plan(model, json.dumps(model_dict, sort_keys=True), text, plan_json)
    return json.loads(_vehs.sweep(model._core, text, first, last, None, plan))


def _workers(client):
    return max(1, len(client.scheduler_info().get("workers", {})))


def sweep(client, model, sweep, grid=None, blocks=None, threads=1, **options):
    """vehs.sweep on a Dask cluster: ``blocks`` tasks of contiguous points (last parameter
    fastest, as fpk-stationary orders them). The default, one task per point up to 16 per worker,
    lets Dask balance points of very different costs (a point the shared grid does not resolve
    is solved again on its own, finer grid) as the CLI's dynamic schedule does; a task costs
    little besides its points (the worker keeps the sweep's analysis). ``threads``: library
    threads per task (1 with one thread per worker). Returns the same dict as :func:`vehs.sweep`,
    with ``seconds`` the wall time and ``tasks`` the number of tasks."""
    import time

    options["sweep"] = sweep
    if grid is not None:
        options["grid"] = grid
    text = options_json("vehs.dask.sweep", options)
    start = time.perf_counter()
    plan_json = _vehs.sweep_plan(model._core, text)  # the options checked, the grid envelope made, once, here
    count = len(json.loads(plan_json)["errors"])
    blocks = max(1, min(count, blocks or 16 * _workers(client)))
    bounds = [(count * b // blocks, count * (b + 1) // blocks) for b in range(blocks)]
    model_dict = model.to_dict()
    futures = [client.submit(_sweep_block, model_dict, text, plan_json, lo, hi, threads, pure=False)
               for lo, hi in bounds]
    parts = client.gather(futures)
    merged = dict(parts[0])
    points = []
    for part in parts:  # each block lists its own points
        points.extend(part["points"])
    merged["points"] = points
    merged["failed_points"] = sum(1 for p in points if "error" in p)
    merged["seconds"] = time.perf_counter() - start
    merged["threads"] = threads
    merged["tasks"] = blocks
    merged["task_seconds"] = [p["seconds"] for p in parts]
    return merged


def _ensemble_block(model_dict, options, first, count, offset, threads):
    _worker_threads(threads)
    opts = dict(options, trajectories=count, first_record=first)
    for key in ("x0", "y0"):  # values per record: this block's slice
        if isinstance(opts.get(key), (list, tuple)):
            opts[key] = list(opts[key])[offset:offset + count]
    model = Model.from_dict(model_dict)
    return json.loads(_vehs.monte_carlo(model._core, options_json("vehs.dask.ensemble", opts), None))


def merge_statistics(parts):
    """Merges the statistics of consecutive blocks of records (each from vehs.monte_carlo) into
    those of the whole ensemble, as simulate_statistics computes them on one machine: with at
    least ``min_records_for_spread`` (16) records the standard errors come from the spread of the
    record means, with fewer from the batch means of every record (in record order)."""
    first = parts[0]
    records = sum(p["records"] for p in parts)
    spread = records >= first["min_records_for_spread"]
    n = float(first["samples_per_record"])
    lengths = first["batch_lengths"]
    out = {}
    stderr = {}
    means = {}
    batch_means = {}
    for name in first["record_means"]:
        values = [v for p in parts for v in p["record_means"][name]]
        batches = [v for p in parts for v in p["batch_means"][name]]
        if spread:
            out[name], stderr[name] = _vehs.combine_independent(values, [n] * len(values))
        else:
            out[name], stderr[name] = _vehs.combine_independent(batches, lengths * records)
        means[name] = values
        batch_means[name] = batches
    out["stderr"] = stderr
    out["records"] = records
    out["samples_per_record"] = first["samples_per_record"]
    out["discard"] = first["discard"]
    out["error_method"] = "independent records" if spread else "batch means"
    if "histograms" in first:
        out["histograms"] = first["histograms"]
        counts = {k: [sum(c) for c in zip(*(p["counts"][k] for p in parts))] for k in ("px", "py", "pxy")}
        outside = [sum(c) for c in zip(*(p["counts"]["outside"] for p in parts))]
        total = [sum(c) for c in zip(*(p["counts"]["total"] for p in parts))]
        h = dict(first["histograms"])
        for i, key in enumerate(("outside_fraction_x", "outside_fraction_y", "outside_fraction_xy")):
            h[key] = outside[i] / total[i] if total[i] > 0 else 0.0
        out["histograms"] = h
        out["counts"] = dict(counts, outside=outside, total=total)
    out["record_means"] = means
    out["batch_means"] = batch_means
    out["batch_lengths"] = lengths
    out["min_records_for_spread"] = first["min_records_for_spread"]
    return out


def ensemble(client, model, trajectories, block=None, threads=1, statistics=None, **options):
    """vehs.monte_carlo on a Dask cluster: blocks of ``block`` records (default: one block per
    worker), record ids first_record + 0 ... trajectories - 1 as on one machine."""
    first_record = int(options.pop("first_record", 0))
    options["statistics"] = {} if statistics is None else statistics
    block = block or math.ceil(trajectories / _workers(client))
    model_dict = model.to_dict()
    futures = [client.submit(_ensemble_block, model_dict, options, first_record + lo, min(block, trajectories - lo),
                             lo, threads, pure=False) for lo in range(0, trajectories, block)]
    merged = merge_statistics(client.gather(futures))
    if "batches" in options["statistics"] and merged["error_method"] != "batch means":
        raise _vehs.Error(f"vehs.dask.ensemble: 'statistics.batches' is not used: with {trajectories} >= "
                          f"{merged['min_records_for_spread']} records the standard errors come from the spread "
                          "of the records")
    return merged
