"""Bad input raises vehs.Error (a ValueError) with the CLI's one-line messages."""
import numpy as np
import pytest

import vehs

MODEL = vehs.Model.paper(0.1, {1: -1.0, 3: 1.0}, 0.02, 0.01)


def test_unknown_and_bad_keys_name_the_key():
    with pytest.raises(vehs.Error, match=r"^vehs.identify: unknown key 'estimater'.*estimator"):
        vehs.identify(np.zeros(100), dt=0.01, estimater="uli")
    with pytest.raises(vehs.Error, match=r"^vehs.simulate: .*'dt'"):
        vehs.simulate(MODEL, dt=-1.0)
    with pytest.raises(vehs.Error, match=r"'dt' must be a finite number"):
        vehs.simulate(MODEL, dt=float("nan"))
    with pytest.raises(vehs.Error, match="output"):
        vehs.simulate(MODEL, output="x.npy")  # files are the CLI's business


def test_bad_data_name_the_record_and_sample():
    x = np.cos(np.linspace(0, 20, 2000)).reshape(2, 1000)
    x[1, 17] = np.nan
    with pytest.raises(vehs.Error, match="record") as e:
        vehs.identify(x, dt=0.01)
    assert "\n" not in str(e.value)
    with pytest.raises(vehs.Error, match="dt"):
        vehs.identify(x, dt=0.0)
    with pytest.raises(vehs.Error):
        vehs.identify(np.zeros((2, 2, 2)), dt=0.01)


def test_same_message_as_the_cli(tmp_path, cli):
    bad = {"model": "data/paper/truth.json", "grid": {"x": 40, "y": 40}, "scheme": "fluxx",
           "output": str(tmp_path / "o.json")}
    proc = cli("fpk-stationary", bad, tmp_path, check=False)
    assert proc.returncode == 1
    cli_message = proc.stderr.strip().splitlines()[-1]
    with pytest.raises(vehs.Error) as e:
        vehs.stationary(MODEL, grid={"x": 40, "y": 40}, scheme="fluxx")
    # "<config file>: 'scheme' ..." vs "vehs.stationary: 'scheme' ...": the same after the prefix
    assert cli_message.split(".json: ", 1)[1] == str(e.value).split("vehs.stationary: ", 1)[1]


def test_diverging_simulation_and_unsolvable_density():
    unconfined = vehs.Model(drift={"x": 1.0, "y": -0.1}, diffusion={"1": 0.02})
    with pytest.raises(vehs.Error, match="confin"):
        vehs.simulate(unconfined, trajectories=1, duration=1, dt=0.01)
    with pytest.raises(vehs.Error):
        vehs.stationary(unconfined, grid={"x": 40, "y": 40})
