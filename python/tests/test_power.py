"""Mean power of a driven model (issue 35): vehs.power gives simulate-vehs's mean_power number
for number; its standard error covers an exactly known power; fpk-stationary on a driven model
names the command that gives its power; vehs.stationary and vehs.plot.power speak watts."""
import json

import numpy as np
import pytest

import vehs
import vehs.plot  # noqa: E402

# a linear oscillator driven by a held (zoh) white sequence u and by white noise
K, BETA, G, A22, DT = 1.0, 0.5, 0.8, 0.1, 0.05
LINEAR = {"drift": {"x": -K, "y": -BETA, "u": G}, "diffusion": {"1": A22}, "units": {"length": "mm", "time": "s"}}
CE = 0.2  # electrical damping [N s/m]


def exact_sample_eyy():
    """E[Y^2] at the sampling instants of dX = Y dt, dY = (-K X - BETA Y + G u_k) dt + sqrt(A22) dB
    with u_k iid N(0, 1) held over each interval: the discrete Lyapunov equation
    S = A S A' + B B' + Q (A, B, Q by Van Loan's block exponential)."""
    F = np.array([[0.0, 1.0], [-K, -BETA]])

    def expm(M):  # scaling and squaring with a long Taylor series (small, well-scaled matrices)
        s = max(0, int(np.ceil(np.log2(max(np.abs(M).sum(axis=1).max(), 1e-16)))) + 4)
        X, term, out = M / 2 ** s, np.eye(len(M)), np.eye(len(M))
        for k in range(1, 30):
            term = term @ X / k
            out = out + term
        for _ in range(s):
            out = out @ out
        return out

    big = np.zeros((4, 4))
    big[:2, :2], big[:2, 2:], big[2:, 2:] = -F, np.diag([0.0, A22]), F.T
    E = expm(big * DT)
    A = E[2:, 2:].T
    Q = A @ E[:2, 2:]
    aug = np.zeros((3, 3))
    aug[:2, :2], aug[:2, 2] = F, [0.0, G]
    B = expm(aug * DT)[:2, 2]
    S = np.zeros((2, 2))
    for _ in range(20000):
        S = A @ S @ A.T + np.outer(B, B) + Q
    return S[1, 1]


def records(n_records=8, n=40000, seed=3):
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((n_records, n))
    x = 0.1 * rng.standard_normal((n_records, n))  # only x[:, 0] is used (the start)
    return vehs.as_records(x, DT, u)


def test_power_covers_the_exact_power_of_a_driven_linear_oscillator():
    truth = exact_sample_eyy()
    p = vehs.power(vehs.Model.from_dict(LINEAR), records(), harvester={"electrical_damping": CE}, seed=11,
                   parameters=False, substeps=20, statistics={"discard": 20.0})
    assert p["stderr"] > 0 and p["stderr"] < 0.03 * p["watts"]  # precise enough to fail on a wrong mean
    assert p["watts"] == pytest.approx(CE * 1e-6 * p["E[Y^2]"], rel=1e-12)
    z = (p["E[Y^2]"] - truth) / p["E[Y^2]_stderr"]
    assert abs(z) < 4.5, (p, truth)  # false failure ~1e-5 when the standard error is honest


def test_power_from_python_equals_the_cli(tmp_path, cli):
    rec = records(n_records=3, n=2000, seed=5)
    model = dict(LINEAR, covariance={"parameters": ["drift[y]", "drift[u]"], "matrix": [[1e-3, 2e-4], [2e-4, 4e-3]]})
    (tmp_path / "m.json").write_text(json.dumps(model))
    u = rec.u
    rows = [f"{r},{i * DT!r},{float(v)!r}" for r in range(u.shape[0]) for i, v in enumerate(u[r])]
    (tmp_path / "u.csv").write_text("traj,t,u\n" + "\n".join(rows) + "\n")
    cfg = {"model": str(tmp_path / "m.json"), "drive": {"path": str(tmp_path / "u.csv")}, "trajectories": 3,
           "duration": 2000 * DT, "dt": DT, "substeps": 10, "seed": 7, "x0": [float(v) for v in rec.x[:, 0]],
           "y0": 0.0, "harvester": {"electrical_damping": CE},
           "statistics": {"output": str(tmp_path / "s.json"), "parameters": True}}
    cli("simulate-vehs", cfg, tmp_path)
    ref = json.loads((tmp_path / "s.json").read_text())["mean_power"]
    p = vehs.power(vehs.Model.load(tmp_path / "m.json"), rec, harvester={"electrical_damping": CE}, seed=7)
    for k in ref:
        assert p[k] == ref[k], k
    assert ref["parameter_stderr"] > 0 and ref["watts"] > 0


def test_fpk_on_a_driven_model_names_the_power_command(tmp_path, cli):
    (tmp_path / "m.json").write_text(json.dumps(LINEAR))
    proc = cli("fpk-stationary", {"model": str(tmp_path / "m.json"), "output": str(tmp_path / "o.json")}, tmp_path,
               check=False)
    assert proc.returncode == 1
    assert "simulate-vehs" in proc.stderr and len(proc.stderr.strip().splitlines()) == 1
    with pytest.raises(vehs.Error, match="simulate-vehs"):
        vehs.stationary(vehs.Model.from_dict(LINEAR))


def test_stationary_and_plot_give_watts():
    m = vehs.Model.from_dict({"drift": {"x": -1.0, "y": -0.5}, "diffusion": {"1": 0.1},
                              "units": {"length": "mm", "time": "s"}})
    s = vehs.stationary(m, harvester={"electrical_damping": CE})
    assert s.power["watts"] == pytest.approx(CE * 1e-6 * 0.1 / (2 * 0.5), rel=2e-2)  # E[Y^2] = a22 / (2 beta)
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    est = {"watts": 1e-7, "stderr": 1e-8, "E[Y^2]": 1.0, "E[Y^2]_stderr": 0.1}
    ax = vehs.plot.power({"rig A": est, "rig B": dict(est, watts=2e-7)})
    assert "W" in ax.get_ylabel() and len(ax.containers) == 1  # one errorbar container


def test_statistics_with_a_band_limited_drive_give_the_power(tmp_path, cli):
    """simulate-vehs refused 'statistics' with a drive applied as the model was fitted
    (band_limited); now it writes the mean power, and the held drive gives a different one."""
    rec = records(n_records=2, n=4000, seed=9)
    rows = [f"{r},{i * DT!r},{float(v)!r}" for r in range(2) for i, v in enumerate(rec.u[r])]
    (tmp_path / "u.csv").write_text("traj,t,u\n" + "\n".join(rows) + "\n")
    out = {}
    for how in ("band_limited", "zoh"):
        model = dict(LINEAR, estimator={"input": how})
        (tmp_path / f"{how}.json").write_text(json.dumps(model))
        cfg = {"model": str(tmp_path / f"{how}.json"), "drive": {"path": str(tmp_path / "u.csv")}, "trajectories": 2,
               "duration": 4000 * DT, "dt": DT, "substeps": 8, "seed": 2, "harvester": {"electrical_damping": CE},
               "statistics": {"output": str(tmp_path / f"{how}_s.json")}}
        cli("simulate-vehs", cfg, tmp_path)
        out[how] = json.loads((tmp_path / f"{how}_s.json").read_text())["mean_power"]
        assert out[how]["watts"] > 0 and 0 < out[how]["stderr"] < 0.2 * out[how]["watts"]
    assert out["band_limited"]["watts"] != out["zoh"]["watts"]
