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


def friction_record(seed, n=1500, dt=0.02, sub=40):
    """x in mm of an oscillator with Coulomb friction (k 100 1/s^2: 16 samples per period), Heun
    on `sub` substeps, 1 % white sensor noise (not vehs's simulator)."""
    rng = np.random.default_rng(seed)
    h, x, y, xs = dt / sub, 0.0, 0.0, np.empty(n)

    def acc(x, y):
        return -100.0 * x - 1.0 * y - 40.0 * np.sign(y)  # mm/s^2

    for k in range(n):
        xs[k] = x
        for _ in range(sub):
            dw = math.sqrt(2000.0 * h) * rng.standard_normal()
            a0 = acc(x, y)
            xp, yp = x + h * y, y + h * a0 + dw
            x, y = x + 0.5 * h * (y + yp), y + 0.5 * h * (a0 + acc(xp, yp)) + dw
    return dt * np.arange(n), xs + 0.01 * np.std(xs) * rng.standard_normal(n)


def test_an_expression_term_fits_the_same_through_python_and_the_cli(tmp_path, cli):
    # a user's expression for the friction, coarse sampling, mm: the defaults run the likelihood
    # on it, and Python and the CLI give the same model
    t, x = friction_record(3)
    data = tmp_path / "rig.csv"
    np.savetxt(data, np.column_stack([t, x]), delimiter=",", header="t,x", comments="", fmt="%.9g")
    lib = ["x", "y", "(y>0)-(y<0)"]
    cli("identify-vehs", {"data": str(data), "units": {"length": "mm", "time": "s"}, "drift_library": lib,
                          "diffusion_library": ["1"], "sparsity": "none", "output": str(tmp_path / "m.json")}, tmp_path)
    cli_file = json.loads((tmp_path / "m.json").read_text())
    model, report = vehs.identify(vehs.read(data), units={"length": "mm", "time": "s"}, drift_library=lib,
                                  diffusion_library=["1"], sparsity="none")
    d = model.to_dict()
    assert report["likelihood"]["used"]
    for part in ("drift", "diffusion"):
        assert d[part] == cli_file[part]
        assert d["stderr"][part] == cli_file["stderr"][part]
    # the friction within 4.5 SE of 40 mm/s^2 (false failure 6.8e-6 for a consistent fit)
    assert abs(-d["drift"]["(y>0)-(y<0)"] - 40.0) < 4.5 * d["stderr"]["drift"]["(y>0)-(y<0)"]
