"""A recorded drive u from Python: vehs.simulate(drive=...) gives simulate-vehs's records with its
drive file (bitwise, shared and per trajectory), records and statistics from one run, and
vehs.identify of driven records with the likelihood (its input interpolation) gives
identify-vehs's model on the same data."""
import json

import numpy as np
import pytest

import vehs

# a driven Duffing oscillator (the drive term 'u'): confining, lightly damped
MODEL_U = vehs.Model(drift={"x": -1.0, "x^3": -1.0, "y": -0.3, "u": 0.5}, diffusion={"1": 0.02})
SIM = {"trajectories": 3, "duration": 20, "dt": 0.01, "substeps": 4, "seed": 5, "scheme": "rk4_euler"}
T = np.arange(2000) * 0.01
SHARED = np.sin(1.3 * T)
PER_RECORD = np.stack([np.sin(w * T) for w in (0.7, 1.3, 2.1)])


def write_drive(path, series):
    """The drive as simulate-vehs reads it: CSV columns traj, t, u (17 digits: exact)."""
    rows = [f"{r},{float(t)!r},{float(v)!r}" for r, u in enumerate(series) for t, v in zip(T, u)]
    path.write_text("traj,t,u\n" + "\n".join(rows) + "\n")


@pytest.mark.parametrize("name, drive", [("shared", SHARED), ("per_record", PER_RECORD)])
def test_simulate_with_a_drive_gives_the_cli_records(tmp_path, cli, name, drive):
    MODEL_U.save(tmp_path / "m.json")
    write_drive(tmp_path / "u.csv", np.atleast_2d(drive))
    cli("simulate-vehs", dict(SIM, model=str(tmp_path / "m.json"), drive={"path": str(tmp_path / "u.csv")},
                              output=str(tmp_path / "r.npy")), tmp_path)
    ref = np.load(tmp_path / "r.npy")
    r = vehs.simulate(MODEL_U, drive=drive, **SIM)
    np.testing.assert_array_equal(r.x.reshape(-1), ref["x"])
    np.testing.assert_array_equal(r.u.reshape(-1), ref["u"])
    as_list = vehs.simulate(MODEL_U, drive=list(np.atleast_2d(drive)), **SIM)  # a list of 1-D series
    np.testing.assert_array_equal(as_list.x, r.x)


def test_drive_errors_are_the_cli_messages():
    with pytest.raises(vehs.Error, match=r"^vehs.simulate: .*'drive'.*2 records: give one \(shared\) or one per "
                                         r"trajectory \(3\)"):
        vehs.simulate(MODEL_U, drive=PER_RECORD[:2], **SIM)
    with pytest.raises(vehs.Error, match="the model has a 'u' term but no drive was given"):
        vehs.simulate(MODEL_U, **SIM)
    with pytest.raises(vehs.Error, match="has 100 values but the records need 1999"):
        vehs.simulate(MODEL_U, drive=SHARED[:100], **SIM)
    with pytest.raises(vehs.Error, match="drive: must be 1-D"):
        vehs.simulate(MODEL_U, drive=np.zeros((1, 1, 2000)), **SIM)


def test_records_and_statistics_from_one_run(tmp_path, cli):
    opts = dict(SIM, trajectories=4, seed=8)
    stats = {"discard": 2, "grid": {"x": [-2, 2, 10], "y": [-2, 2, 10]}}
    r = vehs.simulate(MODEL_U, drive=SHARED, statistics=stats, **opts)
    alone = vehs.monte_carlo(MODEL_U, drive=SHARED, statistics=stats, **opts)
    assert r.statistics["E[X^2]"] == alone["E[X^2]"] and r.statistics["counts"] == alone["counts"]
    assert r.statistics["error_method"] == "batch means"  # 4 records: errors from batch means
    np.testing.assert_array_equal(r.x, vehs.simulate(MODEL_U, drive=SHARED, **opts).x)
    MODEL_U.save(tmp_path / "m.json")
    write_drive(tmp_path / "u.csv", [SHARED])
    cli("simulate-vehs", dict(opts, model=str(tmp_path / "m.json"), drive={"path": str(tmp_path / "u.csv")},
                              statistics=dict(stats, output=str(tmp_path / "s.json"))), tmp_path)
    ref = json.loads((tmp_path / "s.json").read_text())
    for name in ("E[X^2]", "E[Y^2]", "E[XY]"):
        assert r.statistics[name] == ref[name] and r.statistics["stderr"][name] == ref["stderr"][name]


def test_identify_with_the_likelihood_and_its_input_gives_the_cli_model(tmp_path, cli):
    # coarse sampling (omega dt ~ 0.3): the likelihood with a linearly interpolated input
    opts = dict(SIM, trajectories=2, duration=300, dt=0.25, substeps=25)
    u = np.sin(0.9 * np.arange(1200) * 0.25)
    MODEL_U.save(tmp_path / "m.json")
    (tmp_path / "u.csv").write_text("t,u\n" + "\n".join(f"{i * 0.25!r},{float(v)!r}" for i, v in enumerate(u)) + "\n")
    cli("simulate-vehs", dict(opts, model=str(tmp_path / "m.json"), drive={"path": str(tmp_path / "u.csv")},
                              output=str(tmp_path / "r.npy")), tmp_path)
    keys = {"drift_library": ["x", "x^3", "y", "u"], "diffusion_library": ["1"], "sparsity": "none",
            "estimator": "likelihood", "likelihood": {"input": "linear", "covariance": "fisher"}}
    cli("identify-vehs", dict(keys, data=[str(tmp_path / "r.npy")], output=str(tmp_path / "fit.json")), tmp_path)
    ref = json.loads((tmp_path / "fit.json").read_text())
    records = vehs.simulate(MODEL_U, drive=u, **opts)
    model, report = vehs.identify(records, **keys)
    d = model.to_dict()
    assert report["likelihood"]["used"] and d["estimator"]["refined"] == "likelihood"
    assert d["estimator"]["input"] == ref["estimator"]["input"] == "linear"
    for part in ("drift", "diffusion"):
        for term, c in ref[part].items():
            assert d[part][term] == c, (part, term)  # the same records, the same code: bitwise
            assert d["stderr"][part][term] == ref["stderr"][part][term], (part, term)
    assert d["likelihood"]["log_likelihood"] == ref["likelihood"]["log_likelihood"]
    # the same fit from plain arrays (x and u: C-contiguous float64, read in place)
    model2, _ = vehs.identify(records.x, dt=0.25, u=records.u, **keys)
    assert model2.to_dict()["drift"] == d["drift"]


def test_likelihood_errors_are_the_cli_messages():
    x = vehs.simulate(MODEL_U, drive=SHARED, **SIM)
    with pytest.raises(vehs.Error, match=r"^vehs.identify: .*likelihood.covariance"):
        vehs.identify(x, drift_library=["x", "x^3", "y", "u"], likelihood={"covariance": "hessian"})
    with pytest.raises(vehs.Error, match="contradicts estimator"):
        vehs.identify(x, estimator="likelihood", likelihood={"use": "never"})
    with pytest.raises(vehs.Error, match=r"'samples' must be \[first, last\]"):
        vehs.identify(x.x[0], dt=0.01, samples=[0, 5])
    with pytest.raises(vehs.Error, match="unknown key 'figures'"):
        vehs.identify(x, figures="out")  # files are the CLI's business


def test_identify_study_gives_the_cli_study(tmp_path, cli):
    """identify-vehs's consistency study (Table 4) from Python: the same JSON as the CLI's."""
    truth = vehs.Model.paper(0.1, {1: -1.0, 3: 1.0}, 0.02, 0.01)
    truth.save(tmp_path / "truth.json")
    study = {"dt": [0.01], "samples": [2000], "repeats": 2, "records": 2, "seed": 3}
    keys = {"drift_library": {"K1": 4, "K2": 1}, "diffusion_library": {"M": 0}}
    cli("identify-vehs", dict(keys, study=dict(study, truth=str(tmp_path / "truth.json")),
                              output=str(tmp_path / "study.json")), tmp_path)
    ref = json.loads((tmp_path / "study.json").read_text())
    got = vehs.identify_study(dict(study, truth=truth), **keys)
    assert got["table"].strip()

    def numbers(study):  # everything but the timings
        return [{k: v for k, v in p.items() if not k.startswith("seconds")} for p in study["points"]]

    assert numbers(got) == numbers(ref) and got["points"] and got.keys() - {"table"} == ref.keys() - {"config"}
    with pytest.raises(vehs.Error, match="runs the moment estimators only"):
        vehs.identify_study(dict(study, truth=truth), estimator="likelihood")
