"""vehs.Model.parameters(): the CLI's parameter table — physical names, values, standard errors
and units by the library's one rule — the same rows vehs-compare writes for the same model file."""
import csv
import json
import math

import vehs

MODEL = {"drift": {"x": 1.0, "x^3": -0.25, "y": -0.1, "sign(y)": -0.05, "u": 2.0},
         "diffusion": {"1": 0.1, "x^2": 0.02},
         "stderr": {"drift": {"x": 0.01, "x^3": 0.002, "y": 0.003, "sign(y)": 0.004, "u": 0.05},
                    "diffusion": {"1": 0.001, "x^2": 0.0005}},
         "units": {"length": "mm", "time": "s", "input": "V"}}


def test_rows_have_physical_names_and_units():
    rows = {p.name: p for p in vehs.Model.from_dict(MODEL).parameters()}
    assert rows["beta"] == ("beta", 0.1, 0.003, "1/s")
    assert rows["k3"].unit == "1/(mm^2 s^2)"
    assert rows["coulomb_friction.mu"].value == 0.05
    assert rows["coulomb_friction.mu"].unit == "mm/s^2"
    assert rows["drift[u]"].unit == "mm/(V s^2)"
    assert rows["2D"].unit == "mm^2/s^3"
    assert rows["2Q"].unit == "1/s^3"


def test_without_units_the_dimension_is_named():
    d = dict(MODEL)
    del d["units"]
    rows = {p.name: p for p in vehs.Model.from_dict(d).parameters()}
    assert rows["beta"].unit == "1/time"
    assert rows["coulomb_friction.mu"].unit == "length/time^2"


def test_same_rows_as_the_cli(cli, tmp_path):
    path = tmp_path / "model.json"
    path.write_text(json.dumps(MODEL))
    cli("vehs-compare", {"learned": str(path), "output": str(tmp_path / "table.csv")}, tmp_path)
    with open(tmp_path / "table.csv", newline="") as f:
        table = [(r["parameter"], float(r["learned"]), float(r["stderr"]) if r["stderr"] else math.nan, r["unit"])
                 for r in csv.DictReader(f)]
    rows = vehs.Model.load(path).parameters()
    assert [r.name for r in rows] == [t[0] for t in table]
    assert [r.unit for r in rows] == [t[3] for t in table]
    for r, t in zip(rows, table):
        assert math.isclose(r.value, t[1], rel_tol=1e-9)
        assert math.isclose(r.stderr, t[2], rel_tol=1e-9)
