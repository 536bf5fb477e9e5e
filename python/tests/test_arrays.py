"""NumPy arrays out of the library without copies (checked by buffer address), and in: Records
and C-contiguous float64 arrays are read in place (the library's Dataset views the array), other
arrays are copied once and give the same model."""
import gc

import numpy as np
import pytest

import vehs
import vehs.compute

MODEL = vehs.Model.paper(0.1, {1: -1.0, 3: 1.0}, 0.02, 0.01)


def address(a):
    return a.__array_interface__["data"][0]


def coefficients(model):
    """What a fit estimated (the model's dict less its report sections, which hold timings)."""
    d = model.to_dict()
    return {k: d[k] for k in ("drift", "diffusion", "stderr")}


def test_simulated_records_are_views_of_the_library_memory():
    r = vehs.simulate(MODEL, trajectories=3, duration=10, dt=0.01, seed=5)
    assert r.x.shape == (3, 1000) and r.y.shape == (3, 1000)
    assert address(r.x) == r._core.address("x")
    assert address(r.y) == r._core.address("y")
    x = r.x
    del r  # the view keeps the library's records alive
    assert np.isfinite(x).all() and x.base is not None


def test_contiguous_float64_arrays_are_read_in_place():
    rng = np.random.default_rng(1)
    x, u = rng.standard_normal((2, 500)), rng.standard_normal((2, 500))
    r = vehs.as_records(x, dt=0.01, u=u)
    for name, a in (("x", x), ("u", u)):
        assert r._core.is_view(name) and r._core.address(name) == a.ctypes.data  # the library sees a's memory
        assert address(getattr(r, name)) == a.ctypes.data and not getattr(r, name).flags.writeable
    one = rng.standard_normal(300)  # 1-D: one record
    assert vehs.as_records(one, dt=0.01)._core.address("x") == one.ctypes.data
    assert vehs.as_records(r) is r  # a Records goes in as it is


def test_a_viewed_array_is_held_while_the_records_live():
    x = np.random.default_rng(2).standard_normal((3, 400))
    kept = x.copy()
    r = vehs.as_records(x, dt=0.01)
    with pytest.raises(ValueError):
        x.resize((6, 400))  # NumPy refuses: the Records references it
    del x
    gc.collect()
    np.testing.assert_array_equal(r.x, kept)  # still alive, unchanged


def test_identify_reads_a_contiguous_array_in_place(monkeypatch):
    x = vehs.simulate(MODEL, trajectories=2, duration=50, dt=0.01, seed=3).x.copy()
    seen = []
    original = vehs.compute._vehs.identify

    def spy(core, options, progress):  # the pointer the binding works on
        seen.append((core.is_view("x"), core.address("x")))
        return original(core, options, progress)

    monkeypatch.setattr(vehs.compute._vehs, "identify", spy)
    vehs.identify(x, dt=0.01)
    assert seen == [(True, x.ctypes.data)]
    vehs.identify(x[:, ::2], dt=0.02)  # strided: converted once, then read in place
    assert seen[1][0] and seen[1][1] != x.ctypes.data


def test_strided_fortran_and_float32_arrays_are_copied_and_give_the_same_model():
    x = vehs.simulate(MODEL, trajectories=3, duration=100, dt=0.01, seed=4).x.copy()
    options = {"drift_library": ["x", "x^3", "y"], "diffusion_library": ["1"], "sparsity": "none"}

    def fit(a, dt=0.01):
        return coefficients(vehs.identify(a, dt=dt, **options)[0])

    wide = np.zeros((3, 2 * x.shape[1]))
    wide[:, ::2] = x
    assert fit(wide[:, ::2]) == fit(x)  # strided view of the same values
    assert fit(np.asfortranarray(x)) == fit(x)
    x32 = x.astype(np.float32)
    r = vehs.as_records(x32, dt=0.01)
    assert r._core.is_view("x") and r._core.address("x") != x32.ctypes.data  # viewed after one conversion
    assert fit(x32) == fit(x32.astype(np.float64))
    assert fit([row for row in x]) == fit(x)  # a list of records: concatenated once


def test_detrended_fit_copies_and_leaves_the_array_alone():
    sim = vehs.simulate(MODEL, trajectories=2, duration=100, dt=0.01, seed=6)  # the library's own memory
    x = np.array(sim.x)  # the same values in a contiguous float64 array (viewed)
    kept = x.copy()
    options = {"drift_library": ["x", "x^3", "y"], "diffusion_library": ["1"], "sparsity": "none", "detrend": "mean"}
    owned = coefficients(vehs.identify(sim, **options)[0])
    viewed = coefficients(vehs.identify(x, dt=0.01, **options)[0])
    assert viewed == owned  # bitwise: the same detrending of the same values
    np.testing.assert_array_equal(x, kept)  # the caller's array is not detrended in place
    # DC offsets are removed: the same model to rounding (the means differ in the last bits)
    shifted = coefficients(vehs.identify(x + np.array([[0.3], [-0.2]]), dt=0.01, **options)[0])
    for term, c in owned["drift"].items():
        assert shifted["drift"][term] == pytest.approx(c, rel=1e-8, abs=1e-12), term
    assert coefficients(vehs.identify(x + 0.3, dt=0.01, **dict(options, detrend="none"))[0])["drift"] != owned["drift"]


def test_diagnose_reads_a_viewed_array_as_it_reads_the_library_records():
    sim = vehs.simulate(MODEL, trajectories=4, duration=100, dt=0.01, seed=8)
    fitted, _ = vehs.identify(sim, drift_library=["x", "x^3", "y"], diffusion_library=["1"], sparsity="none")
    x = np.array(sim.x)
    assert vehs.as_records(x, dt=0.01)._core.is_view("x")
    a = vehs.diagnose(fitted, sim, replicates=2, seed=1)
    b = vehs.diagnose(fitted, x, dt=0.01, replicates=2, seed=1)
    assert (b.verdict, b.score, b.suspects) == (a.verdict, a.score, a.suspects)
