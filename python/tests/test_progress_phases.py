"""Progress that tracks the real work (issue 35, "silent minutes"): the callback of a driven
identify (the likelihood's phases) and of a diagnose reports through to the end of the call, no
stretch is silent, and within a task the total never changes and the count never falls; tqdm is
the ``progress`` extra and its absence says how to install it."""
import builtins
import sys
import threading
import time

import numpy as np
import pytest

import vehs

# a driven linear oscillator sampled coarsely (omega dt 0.5): the likelihood refines the moment fit
MODEL_U = vehs.Model(drift={"x": -1.0, "y": -0.2, "u": 0.5}, diffusion={"1": 0.02})


def driven_records(n=12000, seed=11):
    rng = np.random.default_rng(seed)
    u = np.zeros(n)
    for i in range(1, n):
        u[i] = 0.5 * u[i - 1] + rng.uniform(-1.0, 1.0)
    return vehs.simulate(MODEL_U, drive=u, trajectories=1, duration=n * 0.5, dt=0.5, substeps=40,
                         scheme="taylor15", sensor_noise=0.01, seed=seed)


class Recorder:
    def __init__(self):
        self.t0 = time.monotonic()
        self.events = []
        self.lock = threading.Lock()

    def __call__(self, task, done, total, finished, seconds):
        with self.lock:
            self.events.append((task, done, total, finished, time.monotonic() - self.t0))


def problems(events, wall, max_gap):
    """What breaks the progress contract (include/vehs/core/progress.hpp), as text."""
    why = []
    if not events:
        return [f"no events in a {wall:.1f} s call"]
    if wall - events[-1][4] > 0.05 * wall:
        why.append(f"last event {wall - events[-1][4]:.1f} s before the end of a {wall:.1f} s call")
    previous, previous_task, last = 0.0, "(start)", {}
    for task, done, total, finished, at in events:
        if at - previous > max_gap:
            why.append(f"silent {at - previous:.1f} s between {previous_task} and {task} at {at:.1f} s")
        if task in last:
            d, t, f = last[task]
            if f:
                why.append(f"{task} reported after it finished")
            if total < t or done < d:
                why.append(f"{task}: total {t} -> {total}, done {d} -> {done}")
        last[task] = (done, total, finished)
        previous, previous_task = at, task
    return why


def test_identify_reports_the_likelihood_phases_through_to_the_end():
    records = driven_records()
    rec = Recorder()
    model, report = vehs.identify(records, progress=rec)
    wall = time.monotonic() - rec.t0
    assert report["likelihood"]["used"]
    tasks = list(dict.fromkeys(e[0] for e in rec.events))
    assert "likelihood fit" in tasks, tasks
    assert problems(rec.events, wall, 2.0) == [], (wall, tasks)


def test_diagnose_reports_every_stage_through_to_the_end():
    records = driven_records(4000, 12)
    wrong = vehs.Model(drift={"x": -1.0, "y": -0.2}, diffusion={"1": 0.05})  # misses the input
    rec = Recorder()
    d = vehs.diagnose(wrong, records, progress=rec, replicates=2, parameter_uncertainty="off")
    wall = time.monotonic() - rec.t0
    tasks = list(dict.fromkeys(e[0] for e in rec.events))
    assert d.verdict == "inadequate"
    for stage in ("diagnose", "score tests"):
        assert stage in tasks, tasks
    assert problems(rec.events, wall, 2.0) == [], (wall, tasks)


def test_tqdm_progress_without_tqdm_says_how_to_install(monkeypatch):
    real_import = builtins.__import__

    def no_tqdm(name, *args, **kwargs):
        if name == "tqdm" or name.startswith("tqdm."):
            raise ModuleNotFoundError("No module named 'tqdm'")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_tqdm)
    for mod in [m for m in sys.modules if m == "tqdm" or m.startswith("tqdm.")]:
        monkeypatch.delitem(sys.modules, mod)
    with pytest.raises(ImportError, match=r"pip install 'vehs\[progress\]'"):
        vehs.tqdm_progress()


def test_tqdm_progress_shows_a_phase_of_unknown_length():
    import io
    out = io.StringIO()
    callback = vehs.tqdm_progress(file=out)
    callback("likelihood fit", 0, 0, False, 0.5)
    callback("likelihood fit", 3, 0, False, 1.5)
    callback("likelihood fit", 4, 0, True, 2.0)
    assert "likelihood fit" in out.getvalue() and "4it" in out.getvalue(), out.getvalue()
