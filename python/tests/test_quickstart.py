"""README's quickstart, run as written: a shaker rig's logger file with a recorded input
(examples/quickstart/) through identify -> diagnose -> the named effect -> mean power in W, from
Python and from the CLI. The data file is fixed and every step is seeded, so these checks are
deterministic (false-failure probability 0 on a given build); the tolerances of 3 standard errors
leave room for a build's last-digit differences."""
import json
import re
import subprocess

import pytest

import vehs

UNITS = {"length": "mm", "time": "s", "input": "m/s^2"}
CE = 0.05  # electrical damping of power.json and README [N s/m]
# the generator's parameters in the logged units (examples/quickstart/make_shaker_csv.py)
TRUTH = {"drift": {"x": 400.0, "x^3": -100.0, "y": -4.0, "x*y": 0.0, "sign(y)": -300.0, "u": 1000.0},
         "diffusion": {"1": 1000.0}}


def logged_power(repo):
    """c_e E[Y^2] of the logged record, Y by central differences of x (mm/s -> m/s)."""
    rows = [line.split(";") for line in (repo / "examples/quickstart/shaker.csv").read_text().splitlines()
            if line and line[0].isdigit()]
    x = [float(r[1]) for r in rows]
    dt = float(rows[1][0]) - float(rows[0][0])
    v2 = [((x[i + 1] - x[i - 1]) / (2 * dt)) ** 2 for i in range(1, len(x) - 1)]
    return CE * 1e-6 * sum(v2) / len(v2)


def assert_near_truth(model_dict):
    for part, terms in TRUTH.items():
        assert set(model_dict[part]) == set(terms), part
        for term, true in terms.items():
            value, se = model_dict[part][term], model_dict["stderr"][part][term]
            assert abs(value - true) < 3 * se, f"{part}[{term}] {value} +- {se}, generator {true}"


@pytest.fixture(scope="module")
def python_run(repo, tmp_path_factory):
    report = tmp_path_factory.mktemp("quickstart") / "py_report"
    records = vehs.read(measurement=str(repo / "examples/quickstart/shaker.json"), data=[
        str(repo / "examples/quickstart/shaker.csv")])
    first, _ = vehs.identify(records)  # the defaults; units from shaker.json
    d = vehs.diagnose(first, records, report=str(report))
    refit, _ = d.refit(records)
    again = vehs.diagnose(refit, records)
    p = vehs.power(refit, records, harvester={"electrical_damping": CE}, seed=1)
    return dict(first=first, diagnosis=d, refit=refit, again=again, power=p)


def test_the_input_enters_the_model_by_default(python_run):
    assert "u" in python_run["first"].to_dict()["drift"]


def test_the_models_carry_the_measurement_files_units(python_run):
    for name in ("first", "refit"):
        units = python_run[name].to_dict()["units"]
        assert {k: units[k] for k in UNITS} == UNITS, name


def test_a_diagnosis_without_a_refit_says_so():
    d = vehs.Diagnosis(verdict="adequate", score=0.5, suspects=[], report=None, result={"refit_config": None})
    with pytest.raises(vehs.Error, match=r"recommends no refit"):
        d.refit([0.0, 1.0, 0.0], dt=0.1)


def test_diagnose_names_the_hidden_friction_and_the_refit_is_adequate(python_run):
    assert python_run["diagnosis"].verdict == "inadequate"
    assert python_run["diagnosis"].result["recommended"] == ["coulomb_friction"]
    assert python_run["again"].verdict == "adequate"
    assert_near_truth(python_run["refit"].to_dict())


def test_power_is_in_watts_and_agrees_with_the_logged_record(repo, python_run):
    p = python_run["power"]
    assert p["watts"] == pytest.approx(CE * 1e-6 * p["E[Y^2]"], rel=1e-12)
    assert abs(p["watts"] - logged_power(repo)) < 3 * p["stderr"]


def test_the_cli_quickstart_gives_what_readme_quotes(repo, tmp_path, cli, python_run):
    out = tmp_path

    def run(tool, config):
        cli(tool, config, out)
        return json.loads(open(config["output"]).read())

    def example(name, **changes):
        return dict(json.loads((repo / "examples/quickstart" / name).read_text()), **changes)

    first = run("identify-vehs", example("identify.json", output=str(out / "model.json")))
    assert first["data"]["input"]["in_drift_library"] and "u" in first["drift"]
    d = run("diagnose-vehs", example("diagnose.json", model=str(out / "model.json"),
                                     output=str(out / "diagnosis.json"), report=str(out / "report")))
    assert d["verdict"] == "inadequate" and d["recommended"] == ["coulomb_friction"]
    refit = json.loads((out / "report/refit.json").read_text())
    assert refit["effects"] == ["coulomb_friction"] and refit["units"] == UNITS
    model = run("identify-vehs", refit)
    assert_near_truth(model)
    assert model["drift"] == python_run["refit"].to_dict()["drift"]
    again = run("diagnose-vehs", example("diagnose.json", model=str(out / "report/refit_model.json"),
                                         output=str(out / "diagnosis2.json"), report=str(out / "report2")))
    assert again["verdict"] == "adequate"
    config = example("power.json", model=str(out / "report/refit_model.json"), output=str(out / "power.json"))
    config["statistics"] = dict(config["statistics"], output=config.pop("output"))
    cli("simulate-vehs", config, out)
    watts = json.loads((out / "power.json").read_text())["mean_power"]
    quoted = float(re.search(r"mean power ([0-9.e+-]+) W", (repo / "README.md").read_text()).group(1))
    assert abs(watts["watts"] - quoted) < 0.1 * watts["stderr"]
    assert abs(watts["watts"] - python_run["power"]["watts"]) < watts["stderr"]
