"""A fit whose diffusion selection keeps no term is refused, never returned (identify-vehs does
not write it either): a Duffing of sd 0.4 sampled at 1 kHz and printed with one decimal, whose
rounding repeats over hundreds of samples, was returned with an empty diffusion."""
import numpy as np
import pytest

import vehs


def test_an_empty_diffusion_is_refused():
    m = vehs.Model(drift={"x": -1.0, "x^3": -1.0, "y": -0.1}, diffusion={"1": 0.09})
    rec = vehs.simulate(m, trajectories=4, duration=19.999, dt=0.001, substeps=10, seed=4)
    x = np.array([[float(f"{v:.1f}") for v in row] for row in np.asarray(rec.x, dtype=float)])
    with pytest.raises(vehs.Error, match="no diffusion term") as e:
        vehs.identify(x, dt=0.001)
    assert "\n" not in str(e.value)
