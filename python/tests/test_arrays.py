"""NumPy arrays out of the library without copies (checked by buffer address), and in: Records
are read in place, plain arrays are copied once."""
import numpy as np

import vehs

MODEL = vehs.Model.paper(0.1, {1: -1.0, 3: 1.0}, 0.02, 0.01)


def address(a):
    return a.__array_interface__["data"][0]


def test_simulated_records_are_views_of_the_library_memory():
    r = vehs.simulate(MODEL, trajectories=3, duration=10, dt=0.01, seed=5)
    assert r.x.shape == (3, 1000) and r.y.shape == (3, 1000)
    assert address(r.x) == r._core.address("x")
    assert address(r.y) == r._core.address("y")
    x = r.x
    del r  # the view keeps the library's records alive
    assert np.isfinite(x).all() and x.base is not None


def test_records_from_arrays_copy_once_then_identify_reads_them_in_place():
    rng = np.random.default_rng(1)
    x = rng.standard_normal((2, 500))
    r = vehs.as_records(x, dt=0.01)
    assert address(r.x) == r._core.address("x") and address(r.x) != address(x)
    np.testing.assert_array_equal(r.x, x)
    assert vehs.as_records(r) is r  # a Records goes in as it is


def test_stationary_density_is_a_view():
    s = vehs.stationary(MODEL, grid={"x": 100, "y": 100})
    assert s.density.shape == (100, 100)
    assert address(s.density) == s._core.address()
    assert abs(s.density.sum() * (s.x[1] - s.x[0]) * (s.y[1] - s.y[0]) - 1.0) < 1e-9
