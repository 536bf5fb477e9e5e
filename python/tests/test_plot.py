"""The matplotlib helpers draw (Agg) from real library results."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import vehs  # noqa: E402
import vehs.plot  # noqa: E402


def test_figures_render(tmp_path):
    model = vehs.Model.paper(0.1, {1: -1.0, 3: 1.0}, 0.02, 0.01)
    records = vehs.simulate(model, trajectories=4, duration=200, dt=0.01, substeps=5, seed=3)
    fitted, _ = vehs.identify(records)
    fig, axes = plt.subplots(1, 3, figsize=(12, 3))
    vehs.plot.potential(fitted, ax=axes[0])
    vehs.plot.drift(fitted, records, ax=axes[1])
    vehs.plot.diffusion(fitted, records, ax=axes[2])
    fig.savefig(tmp_path / "model.png")
    s = vehs.stationary(fitted, grid={"x": 100, "y": 100})
    main, _, _ = vehs.plot.density(s)
    main.figure.savefig(tmp_path / "density.png")
    sw = vehs.sweep(model, {"2D": [0.01, 0.03, 3]}, grid={"x": 100, "y": 100})
    vehs.plot.power(sw).figure.savefig(tmp_path / "power.png")
    d = vehs.diagnose(fitted, records, replicates=2)
    vehs.plot.suspects(d).figure.savefig(tmp_path / "suspects.png")
    for name in ("model", "density", "power", "suspects"):
        assert (tmp_path / f"{name}.png").stat().st_size > 1000
    plt.close("all")
