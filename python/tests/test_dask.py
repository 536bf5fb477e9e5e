"""Sweeps and ensembles on a dask.distributed LocalCluster equal the single-machine results:
the CLI's sweep point by point, bit for bit; the Monte Carlo statistics of one run."""
import json

import pytest

import vehs
import vehs.dask

distributed = pytest.importorskip("distributed")

SWEEP = {"2D": [0.025, 0.04, 2], "2Q": [0.0, 0.03, 2]}  # a corner of Fig. 5a: 2 x 2 points
GRID = {"x": 200, "y": 200}  # Fig. 5a's grid (coarser ones leave mass on the boundary)


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as c:
        yield c


def test_dask_sweep_equals_the_cli_sweep(repo, tmp_path, cli, client):
    cli("fpk-stationary", {"model": "data/fpk/learned_model.json", "grid": GRID, "sweep": SWEEP,
                           "output": str(tmp_path / "fpk.json")}, tmp_path)
    ref = json.loads((tmp_path / "fpk.json").read_text())["sweep"]
    model = vehs.Model.load(repo / "data/fpk/learned_model.json")
    assert sum("error" not in p for p in ref["points"]) >= 2  # points failing on the boundary mass fail alike
    for blocks in (2, None):  # one task per worker; the default: one task per point
        got = vehs.dask.sweep(client, model, SWEEP, grid=GRID, blocks=blocks)
        assert got["tasks"] == (blocks or 4)
        assert got["grid"] == ref["grid"]
        assert len(got["points"]) == 4 and got["failed_points"] == ref["failed_points"]
        for p, q in zip(got["points"], ref["points"]):
            assert p == q  # parameters, E[X^2], E[Y^2], E[XY], boundary mass, wells: bitwise
    local = vehs.sweep(model, SWEEP, grid=GRID)
    assert local["points"] == ref["points"]
    # a worker analyses a sweep once: its later blocks reuse the symbolic factorisation
    kept = client.run(lambda: len(__import__("vehs.dask").dask._PLANS))
    assert all(n <= 1 for n in kept.values()) and sum(kept.values()) >= 1, kept


def test_dask_ensemble_equals_one_run_and_the_cli(client, cli, tmp_path):
    model = vehs.Model.paper(0.1, {1: -1.0, 3: 1.0}, 0.02, 0.01)
    model.save(tmp_path / "model.json")
    opts = dict(duration=50, dt=0.01, substeps=2, seed=9)
    stats = {"discard": 5, "grid": {"x": [-2, 2, 20], "y": [-2, 2, 20]}}
    cli("simulate-vehs", dict(opts, model=str(tmp_path / "model.json"), trajectories=20,
                              statistics=dict(stats, output=str(tmp_path / "mc.json"))), tmp_path)
    ref = json.loads((tmp_path / "mc.json").read_text())
    one = vehs.monte_carlo(model, trajectories=20, statistics=stats, **opts)
    merged = vehs.dask.ensemble(client, model, 20, block=7, statistics=stats, **opts)  # blocks of 7, 7, 6
    for name in ("E[X^2]", "E[Y^2]", "E[XY]", "E[X^4]"):
        assert merged[name] == one[name] == ref[name]
        assert merged["stderr"][name] == one["stderr"][name] == ref["stderr"][name]
    assert merged["record_means"] == one["record_means"]
    assert merged["counts"] == one["counts"]  # histograms: the same counts


def test_small_dask_ensembles_merge_the_batch_means(client, cli, tmp_path):
    """Fewer than 16 records: the standard errors come from every record's batch means, merged
    over blocks exactly as one run computes them."""
    model = vehs.Model.paper(0.1, {1: -1.0, 3: 1.0}, 0.02, 0.01)
    model.save(tmp_path / "model.json")
    opts = dict(duration=40, dt=0.01, substeps=2, seed=4)
    stats = {"discard": 2, "batches": 8}
    cli("simulate-vehs", dict(opts, model=str(tmp_path / "model.json"), trajectories=5,
                              statistics=dict(stats, output=str(tmp_path / "mc.json"))), tmp_path)
    ref = json.loads((tmp_path / "mc.json").read_text())
    one = vehs.monte_carlo(model, trajectories=5, statistics=stats, **opts)
    merged = vehs.dask.ensemble(client, model, 5, block=2, statistics=stats, **opts)  # blocks of 2, 2, 1
    assert merged["error_method"] == one["error_method"] == ref["error_method"] == "batch means"
    for name in ("E[X^2]", "E[Y^2]", "E[XY]", "E[X^4]"):
        assert merged[name] == one[name] == ref[name]
        assert merged["stderr"][name] == one["stderr"][name] == ref["stderr"][name]
    with pytest.raises(vehs.Error, match="'statistics.batches' is not used"):
        vehs.dask.ensemble(client, model, 16, block=8, statistics=stats, **dict(opts, duration=10))
