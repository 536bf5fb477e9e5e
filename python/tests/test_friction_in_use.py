"""vehs.read takes what the tools' configs take (issue 35, "friction in use"): globs in data (the
matching files in byte order), a measurement file holding the data keys once, and the same
one-line errors; vehs.identify's estimator error lists likelihood."""
import json

import numpy as np
import pytest

import vehs


def write_run(path, n, seed):
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.normal(size=n)) * 0.01
    x -= np.linspace(0, x[-1], n)
    path.write_text("time_s,disp\n" + "\n".join(f"{0.01 * i!r},{float(v)!r}" for i, v in enumerate(x)) + "\n")


def test_read_takes_a_glob_in_byte_order_and_names_a_pattern_that_matches_nothing(tmp_path):
    for name, n in (("run_b.csv", 300), ("run_a.csv", 200), ("run_10.csv", 100)):
        write_run(tmp_path / name, n, n)
    r = vehs.read(str(tmp_path / "run_*.csv"), columns={"t": "time_s", "x": "disp"})
    assert list(r.sizes) == [100, 200, 300]
    one = [vehs.read(str(tmp_path / n), columns={"t": "time_s", "x": "disp"}).x.ravel()
           for n in ("run_10.csv", "run_a.csv", "run_b.csv")]
    np.testing.assert_array_equal(r.x, np.concatenate(one))
    with pytest.raises(vehs.Error, match=r"^vehs.read: 'data': \".*trial_\*\.csv\" matches no file$"):
        vehs.read([str(tmp_path / "run_a.csv"), str(tmp_path / "trial_*.csv")], columns={"t": "time_s", "x": "disp"})


def test_read_takes_the_data_keys_from_a_measurement_file(tmp_path):
    write_run(tmp_path / "run_1.csv", 500, 1)
    rig = tmp_path / "rig.json"
    rig.write_text(json.dumps({"data": str(tmp_path / "run_*.csv"), "columns": {"t": "time_s", "x": "disp"}}))
    assert vehs.read(measurement=str(rig)).x.size == 500
    with pytest.raises(vehs.Error, match=r"unknown key 'colums' in a measurement file"):
        rig.write_text(json.dumps({"data": str(tmp_path / "run_1.csv"), "colums": {"x": "disp"}}))
        vehs.read(measurement=str(rig))


def test_identify_lists_likelihood_among_the_estimators():
    x = vehs.simulate(vehs.Model(drift={"x": -1.0, "y": -0.3}, diffusion={"1": 0.1}), trajectories=1, duration=50,
                      dt=0.01, seed=1)
    with pytest.raises(vehs.Error, match=r"'estimator' must be one of auto, paper, forward, uli, noisy, likelihood "
                                         r"\(got 'maximum_likelihood'\)"):
        vehs.identify(x, estimator="maximum_likelihood")
