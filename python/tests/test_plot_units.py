"""vehs.plot's ranges come from the data or the model (not a fixed interval) and its axes name the
quantity with its unit (issue 35, item 7): a harvester with wells at +-2 mm is drawn whole."""
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import vehs  # noqa: E402
import vehs.plot  # noqa: E402

MM_S = {"length": "mm", "time": "s"}


def wells_at_2mm(units=MM_S):
    """b2 = x - x^3/4 - 0.5 y: wells at x = +-2 (mm), a22 = 0.5 mm^2/s^3."""
    d = {"drift": {"x": 1.0, "x^3": -0.25, "y": -0.5}, "diffusion": {"1": 0.5},
         "stderr": {"drift": {"x": 0.01, "x^3": 0.002, "y": 0.01}, "diffusion": {"1": 0.005}}}
    if units:
        d["units"] = units
    return vehs.Model.from_dict(d)


def x_span(ax):
    x = np.concatenate([np.asarray(line.get_xdata(), dtype=float) for line in ax.lines])
    return x.min(), x.max()


@pytest.mark.parametrize("draw", [vehs.plot.potential, vehs.plot.drift, vehs.plot.diffusion])
def test_model_range_holds_both_wells(draw):
    # without records the range is the model's stationary region: both wells at +-2 and the
    # barrier between them (the old fixed +-1.6 missed the wells)
    ax = draw(wells_at_2mm())
    lo, hi = x_span(ax)
    assert lo < -2.2 and hi > 2.2
    assert lo > -20 and hi < 20  # the region of the density, not the solver's e^-25 domain
    plt.close("all")


def test_records_range_is_the_data(tmp_path):
    model = wells_at_2mm()
    records = vehs.simulate(model, trajectories=2, duration=200, dt=0.01, substeps=5, seed=5)
    data = np.asarray(records.x)
    ax = vehs.plot.drift(model, records)
    lo, hi = x_span(ax)
    span = data.max() - data.min()
    assert lo == pytest.approx(data.min() - 0.05 * span)
    assert hi == pytest.approx(data.max() + 0.05 * span)
    plt.close("all")


def test_labels_carry_the_models_units():
    model = wells_at_2mm()
    ax = vehs.plot.potential(model)
    assert ax.get_xlabel() == "displacement x [mm]"
    assert ax.get_ylabel() == "potential U(x) [mm^2/s^2]"
    ax = vehs.plot.drift(model)
    assert ax.get_ylabel() == "drift b2(x, 0) [mm/s^2]"
    ax = vehs.plot.diffusion(model)
    assert ax.get_ylabel() == "diffusion a22(x, 0) [mm^2/s^3]"
    main, top, side = vehs.plot.density(vehs.stationary(model, grid={"x": 60, "y": 60}))
    assert main.get_xlabel() == "displacement x [mm]"
    assert main.get_ylabel() == "velocity y [mm/s]"
    assert top.get_ylabel() == "p(x) [1/mm]"
    assert side.get_xlabel() == "p(y) [s/mm]"
    plt.close("all")


def test_labels_from_the_records_units(tmp_path):
    # a model without units (fitted without the key) drawn over records read with units
    model = wells_at_2mm(units=None)
    sim = vehs.simulate(model, trajectories=1, duration=50, dt=0.01, seed=2)
    path = tmp_path / "rig.csv"
    x = np.asarray(sim.x).ravel()
    np.savetxt(path, np.column_stack([np.arange(x.size) * 0.01, x]), delimiter=",", header="t,x", comments="")
    records = vehs.read(path, units=MM_S)
    assert records.units == MM_S
    ax = vehs.plot.drift(model, records)
    assert ax.get_xlabel() == "displacement x [mm]"
    assert ax.get_ylabel() == "drift b2(x, 0) [mm/s^2]"
    # without any units the axes still name their quantity
    ax = vehs.plot.drift(model)
    assert ax.get_xlabel() == "displacement x"
    assert ax.get_ylabel() == "drift b2(x, 0)"
    plt.close("all")


def test_sweep_axis_carries_the_parameter_unit():
    model = wells_at_2mm()
    sw = vehs.sweep(model, {"2D": [0.3, 0.6, 2]}, grid={"x": 60, "y": 60})
    ax = vehs.plot.power(sw, units=MM_S)
    assert ax.get_xlabel() == "2D [mm^2/s^3]"
    assert ax.get_ylabel() == "E[Y^2] [mm^2/s^2]"
    plt.close("all")


def test_driven_model_without_records_asks_for_them():
    d = json.loads(json.dumps(wells_at_2mm().to_dict()))
    d["drift"]["u"] = 1.0
    with pytest.raises(vehs.Error, match="give records or x"):
        vehs.plot.potential(vehs.Model.from_dict(d))


def test_read_checks_units_as_the_tools_do(tmp_path):
    path = tmp_path / "rig.csv"
    np.savetxt(path, np.column_stack([np.arange(200) * 0.01, np.sin(np.arange(200) * 0.1)]), delimiter=",",
               header="t,x", comments="")
    assert vehs.read(path).units is None
    with pytest.raises(vehs.Error, match=r"units.*lenght"):
        vehs.read(path, units={"lenght": "mm"})
