"""Python runs the CLI's data checks: every bad record identify-vehs refuses, vehs.identify refuses
with the same one-line message, whether the records come from vehs.read or from arrays."""
import numpy as np
import pytest

import vehs


def oscillator(seed, n=6000, dt=0.01):
    """A noisy bistable oscillator sampled every dt (Euler-Maruyama on a 20x finer grid), written
    by a generator of the test's own so that the readers and checks see data they never made."""
    rng = np.random.default_rng(seed)
    h = dt / 20
    x, v, out = 1.0, 0.0, np.empty(n)
    for k in range(n):
        for _ in range(20):
            x, v = x + v * h, v + (x - x ** 3 - 0.3 * v) * h + np.sqrt(0.2 * h) * rng.standard_normal()
        out[k] = x
    return out


def write_csv(path, x, dt=0.01):
    with open(path, "w") as f:
        f.write("t,x\n")
        for k, value in enumerate(x):
            f.write(f"{k * dt:.5f},{value:.6f}\n")


def bad_records():
    """(name, x): one record with one defect the data checks must stop at."""
    base = oscillator(3)
    glitch = base.copy()
    glitch[2500] += 2.0  # one sample far off its neighbours at this sampling
    dropout = base.copy()
    dropout[3000:3040] = 0.0  # a logger's dropout as zeros
    stuck = base.copy()
    stuck[1200:1300] = stuck[1200]  # a stuck sensor
    return [("glitch", glitch), ("dropout", dropout), ("stuck", stuck)]


@pytest.mark.parametrize("name,x", bad_records(), ids=[c[0] for c in bad_records()])
def test_python_refuses_what_the_cli_refuses(tmp_path, cli, name, x):
    data = tmp_path / f"{name}.csv"
    write_csv(data, x)
    proc = cli("identify-vehs", {"data": str(data), "output": str(tmp_path / "m.json")}, tmp_path, check=False)
    assert proc.returncode == 1, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1
    cli_message = lines[0].split(": error: ", 1)[1]
    with pytest.raises(vehs.Error) as read_error:
        vehs.identify(vehs.read(data))
    assert str(read_error.value) == cli_message
    # arrays: the same check, the rows named by record and sample instead of file lines
    with pytest.raises(vehs.Error, match="glitch|flat stretch"):
        vehs.identify(x, dt=0.01)
    with pytest.raises(vehs.Error, match="glitch|flat stretch"):
        vehs.diagnose(vehs.Model.paper(0.3, {1: -1.0, 3: 1.0}, 0.2, 0.0), x, dt=0.01, replicates=0,
                      suspects=False)


def test_drop_and_keep_apply_to_arrays():
    x = bad_records()[0][1]
    kept, _ = vehs.identify(x, dt=0.01, glitches="keep")
    dropped, _ = vehs.identify(x, dt=0.01, glitches="drop")
    clean, _ = vehs.identify(oscillator(3), dt=0.01)
    # the glitch inflates the fitted noise when kept; dropping it gives the clean record's fit
    assert kept.to_dict()["diffusion"] != dropped.to_dict()["diffusion"]
    d, c = dropped.to_dict()["diffusion"], clean.to_dict()["diffusion"]
    assert d.keys() == c.keys()
    for k in d:
        assert d[k] == pytest.approx(c[k], rel=0.05)


def test_read_gives_the_records_identify_vehs_fits(tmp_path, cli):
    x = oscillator(5)
    data = tmp_path / "clean.csv"
    write_csv(data, x)
    out = tmp_path / "m.json"
    cli("identify-vehs", {"data": str(data), "output": str(out)}, tmp_path)
    records = vehs.read(data)
    assert records.sizes == [len(x)]
    assert records.dt == pytest.approx(0.01)
    np.testing.assert_allclose(records.x.ravel(), np.round(x, 6), atol=1e-12)
    model, _ = vehs.identify(records)
    import json
    assert model.to_dict()["drift"] == json.loads(out.read_text())["drift"]


def test_read_errors_name_the_file(tmp_path):
    with pytest.raises(vehs.Error, match="missing.csv"):
        vehs.read(tmp_path / "missing.csv")
    bad = tmp_path / "bad.csv"
    bad.write_text("t,x\n0,1\n0.01,abc\n")
    with pytest.raises(vehs.Error, match="bad.csv"):
        vehs.read(bad)
