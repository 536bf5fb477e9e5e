"""vehs.identify and identify-vehs run one fit (vehs::fit): on a driven record sampled coarsely
(the input enters the library, the likelihood refines from several starts, with its selection and
bias correction) the model from Python equals the CLI's bitwise, and stderr = sqrt(diag(covariance))."""
import json
import math

import numpy as np
import pytest

import vehs


def driven_record(seed, n=3000, dt=0.15, sub=40):
    """A damped Duffing oscillator driven by an AR(1) input held over each interval, integrated by
    Euler-Maruyama with `sub` substeps, with white sensor noise (not vehs's simulator)."""
    rng = np.random.default_rng(seed)
    e = rng.standard_normal(n)
    u = np.empty(n)
    u[0] = e[0]
    for k in range(1, n):
        u[k] = 0.3 * u[k - 1] + math.sqrt(1 - 0.09) * e[k]
    h, x, y, xs = dt / sub, 0.0, 0.0, np.empty(n)
    for k in range(n):
        xs[k] = x
        for _ in range(sub):
            f = -0.3 * y - x - 0.5 * x ** 3 + 0.8 * u[k]
            x, y = x + h * y, y + h * f + math.sqrt(0.05 * h) * rng.standard_normal()
    return dt * np.arange(n), xs + 0.005 * rng.standard_normal(n), u


def test_python_model_equals_the_cli_model_bitwise(tmp_path, cli):
    t, x, u = driven_record(11)
    data = tmp_path / "rig.csv"
    np.savetxt(data, np.column_stack([t, x, u]), delimiter=",", header="t,x,u", comments="", fmt="%.9g")
    cli("identify-vehs", {"data": str(data), "output": str(tmp_path / "m.json")}, tmp_path)
    cli_file = json.loads((tmp_path / "m.json").read_text())
    model, report = vehs.identify(vehs.read(data))
    d = model.to_dict()
    assert report["likelihood"]["used"]  # the path under test: the likelihood with its starts
    assert "u" in d["drift"] and cli_file["data"]["input"]["added"]
    for part in ("drift", "diffusion"):
        assert d[part] == cli_file[part]
        assert d["stderr"][part] == cli_file["stderr"][part]
    assert d["likelihood"] == cli_file["likelihood"]
    starts = [(s["start"], s["status"], s.get("log_likelihood")) for s in d["estimator"]["likelihood_starts"]]
    assert starts == [(s["start"], s["status"], s.get("log_likelihood")) for s in cli_file["estimator"]["likelihood_starts"]]
    cov = cli_file["covariance"]
    se = dict(zip(cov["parameters"], np.sqrt(np.diag(np.asarray(cov["matrix"])))))
    for part in ("drift", "diffusion"):
        for term, s in cli_file["stderr"][part].items():
            assert s == se[f"{part}[{term}]"], (part, term)


def test_typed_options_are_read_once_and_set_by_name(tmp_path):
    t, x, u = driven_record(12, n=1500)
    options = vehs.FitOptions(drift_library=["x", "x^3", "y", "u"], diffusion_library=["1"])
    assert options.drift_library == ["x", "x^3", "y", "u"] and options.likelihood_use == "auto"
    options.likelihood_use = "never"
    model, report = vehs.identify(x, dt=0.15, u=u, options=options)
    assert not report["likelihood"]["used"] and set(model.to_dict()["drift"]) <= {"x", "x^3", "y", "u"}
    with pytest.raises(vehs.Error, match="likelihood_use"):
        options.likelihood_use = "sometimes"
    with pytest.raises(vehs.Error, match="'estimator'"):
        vehs.FitOptions(estimator="best")
    glitched = x.copy()
    glitched[700] += 100.0
    with pytest.raises(vehs.Error, match="glitch"):
        vehs.identify(glitched, dt=0.15, u=u, options=options)
    options.glitches = "drop"
    vehs.identify(glitched, dt=0.15, u=u, options=options)
    with pytest.raises(TypeError):
        vehs.identify(x, dt=0.15, options=options, estimator="uli")
