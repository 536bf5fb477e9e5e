"""vehs.Model: built from terms and parameters, from and to the model file format."""
import json

import pytest

import vehs


def test_builder_matches_paper_and_file_format(tmp_path, repo):
    truth = vehs.Model.load(repo / "data/paper/truth.json")
    built = vehs.Model.paper(0.1, {1: 1.0, 3: -7.7, 5: 16.3, 7: -12.5, 9: 3.1}, 0.02, 0.01)
    assert built.drift == truth.drift and built.diffusion == truth.diffusion
    path = tmp_path / "m.json"
    truth.save(path)
    again = vehs.Model.load(path)
    assert again.to_dict() == truth.to_dict()
    assert json.loads(path.read_text())["provenance"] == truth.to_dict()["provenance"]  # sections kept


def test_parameters_by_physical_name():
    m = vehs.Model(drift={"x": -1.0, "x^3": 1.0}, parameters={"beta": 0.1}, diffusion={"1": 0.02},
                   effects={"coulomb_friction": {"mu": 0.05}})
    assert m["beta"] == 0.1 and m["k3"] == -1.0 and m["2D"] == 0.02
    assert m["drift[sign(y)]"] == -0.05  # a term-like effect is its terms
    m2 = m.with_parameter("2D", 0.03)
    assert m2["2D"] == 0.03 and m["2D"] == 0.02
    assert m.b2(0.5, 0.2) == pytest.approx(-0.5 + 0.125 - 0.1 * 0.2 - 0.05)


def test_bad_models_raise_one_line_errors():
    with pytest.raises(vehs.Error, match=r"^model: .*x\^q") as e:
        vehs.Model(drift={"x^q": 1.0}, diffusion={"1": 0.02})
    assert "\n" not in str(e.value)
    with pytest.raises(vehs.Error, match="coulomb"):
        vehs.Model(drift={"x": -1.0}, diffusion={"1": 0.02}, effects={"coulomb_friction": {"mu": -1.0}})
    with pytest.raises(vehs.Error, match="nope"):
        vehs.Model.from_dict({"drift": {"x": -1.0}, "diffusion": {"1": 0.02}}).with_parameter("nope", 1.0)
