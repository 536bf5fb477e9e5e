"""README's "your own effect" example (examples/user_effect/): a linear guide whose friction
differs by direction, logged in metres with 1 % sensor noise. The baseline (x, y) is fitted with
the defaults; diagnose-vehs, given the user's directional_friction in a few lines of config,
names it, confirms it by a refit and writes it into refit.json, whose fit recovers the
generator's parameters; the same through Python. The generator is seeded: deterministic
(false-failure probability 0 on a given build); the tolerances of 3 standard errors leave room
for a build's last-digit differences. About 5 minutes (expression terms in the likelihood, the
twins and the draws): marked long (scripts/test-long.sh)."""
import json
import subprocess
import sys

import pytest

import vehs

pytestmark = pytest.mark.long

# the generator's parameters (examples/user_effect/make_rig_csv.py)
TRUTH = {"x": -987.0, "y": -2.0, "-(y>0)": 0.30, "(y<0)": 0.15, "-y*(y<0)": 4.0}
EFFECT = {"name": "directional_friction", "drift": {"Fp": "-(y>0)", "Fm": "(y<0)", "dc": "-y*(y<0)"}}


@pytest.fixture(scope="module")
def rig(repo, tmp_path_factory):
    csv = tmp_path_factory.mktemp("user_effect") / "rig.csv"
    subprocess.run([sys.executable, str(repo / "examples/user_effect/make_rig_csv.py"), str(csv)], check=True)
    return csv


def example(repo, name, **changes):
    return dict(json.loads((repo / "examples/user_effect" / name).read_text()), **changes)


def assert_near_truth(model):
    for term, true in TRUTH.items():
        value, se = model["drift"][term], model["stderr"]["drift"][term]
        assert abs(value - true) < 3 * se, f"drift[{term}] {value} +- {se}, generator {true}"


def test_the_example_config_names_the_users_effect_and_its_refit_recovers_it(repo, rig, tmp_path, cli):
    def run(tool, config):
        cli(tool, dict(config, data=[str(rig)]), tmp_path)
        return json.loads(open(config["output"]).read())

    run("identify-vehs", example(repo, "identify.json", output=str(tmp_path / "model.json")))
    d = run("diagnose-vehs", example(repo, "diagnose.json", model=str(tmp_path / "model.json"),
                                     output=str(tmp_path / "diagnosis.json"), report=str(tmp_path / "report")))
    assert d["verdict"] == "inadequate"
    assert d["recommended"][0] == "directional_friction", d["conclusion"]
    refit = json.loads((tmp_path / "report/refit.json").read_text())
    assert EFFECT in refit["effects"]
    model = run("identify-vehs", refit)
    assert_near_truth(model)
    params = {e["name"]: e for e in model["effect_params"]}["directional_friction"]
    assert params["user"] is True and set(params["params"]) == {"Fp", "Fm", "dc"}
    again = run("diagnose-vehs", example(repo, "diagnose.json", model=str(tmp_path / "report/refit_model.json"),
                                         output=str(tmp_path / "diagnosis2.json"), report=str(tmp_path / "report2")))
    assert again["verdict"] == "adequate", again["conclusion"]


def test_python_takes_the_same_user_effect(repo, rig):
    records = vehs.read(measurement=str(repo / "examples/user_effect/rig.json"), data=[str(rig)])
    model, _ = vehs.identify(records, drift_library=["x", "y"], diffusion_library=["1"])
    d = vehs.diagnose(model, records, user_effects=[EFFECT])
    assert d.result["recommended"][0] == "directional_friction", d.result["conclusion"]
    refit, _ = d.refit(records)
    assert_near_truth(refit.to_dict())
