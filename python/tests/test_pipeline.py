"""The paper's pipeline from Python gives the CLI's numbers on the same data: the same records
(bitwise), the same identified model, the same stationary moments."""
import json

import numpy as np
import pytest

import vehs

# the paper's simulate.json (Eq. 27, Eq. 30 scheme, seed 27), 10 records x 10^5 samples
SIM = {"trajectories": 10, "duration": 100, "dt": 0.001, "substeps": 1, "scheme": "rk4_euler", "seed": 27,
       "x0": {"uniform": [-1.5, 1.5]}}


@pytest.fixture(scope="module")
def paper(repo, tmp_path_factory, cli):
    work = tmp_path_factory.mktemp("paper")
    cli("simulate-vehs", dict(SIM, model="data/paper/truth.json", output=str(work / "m.npy")), work)
    cli("identify-vehs", {"data": [str(work / "m.npy")], "output": str(work / "learned.json")}, work)
    cli("fpk-stationary", {"model": "data/fpk/learned_model.json", "grid": {"x": 200, "y": 200},
                           "output": str(work / "fpk.json")}, work)
    return work


def test_simulate_gives_the_cli_records(repo, paper):
    truth = vehs.Model.load(repo / "data/paper/truth.json")
    r = vehs.simulate(truth, **SIM)
    m = np.load(paper / "m.npy")
    np.testing.assert_array_equal(r.x.reshape(-1), m["x"])


def test_identify_gives_the_cli_model(repo, paper):
    cli_model = vehs.Model.load(paper / "learned.json").to_dict()
    truth = vehs.Model.load(repo / "data/paper/truth.json")
    records = vehs.simulate(truth, **SIM)
    for data in (records, np.load(paper / "m.npy")["x"].reshape(10, -1)):
        model, report = vehs.identify(data, dt=0.001)
        d = model.to_dict()
        assert set(d["drift"]) == set(cli_model["drift"]) and set(d["diffusion"]) == set(cli_model["diffusion"])
        for part in ("drift", "diffusion"):
            for term, c in cli_model[part].items():
                # bitwise: the same records, the same estimator code, the same dt (the CLI's from
                # the file's t column, which holds i * dt exactly enough to give dt back)
                assert d[part][term] == c, (part, term)
                assert d["stderr"][part][term] == cli_model["stderr"][part][term], (part, term)
        assert report["estimator"]["used"] == cli_model["estimator"]["used"]
        # the same work in memory, timed the same way as identify-vehs times it (bench/python.sh
        # identify compares the call's wall time with the CLI's fit.in_memory_seconds)
        assert report["fit"]["in_memory_seconds"] >= report["fit"]["seconds"] > 0
    cli_fit = json.loads((paper / "learned.json").read_text())["fit"]
    assert cli_fit["in_memory_seconds"] >= cli_fit["seconds"] > 0


def test_stationary_gives_the_cli_moments(repo, paper):
    cli_fpk = json.loads((paper / "fpk.json").read_text())
    s = vehs.stationary(vehs.Model.load(repo / "data/fpk/learned_model.json"), grid={"x": 200, "y": 200})
    assert s.moments["E[Y^2]"] == cli_fpk["E[Y^2]"]
    assert s.moments["E[X^2]"] == cli_fpk["E[X^2]"]
