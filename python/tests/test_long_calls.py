"""Long calls: Ctrl-C (SIGINT -> KeyboardInterrupt) stops a simulation cleanly (every thread stops
at its next chunk, the library works normally afterwards); the GIL is released while the library
works; progress reaches a Python callback, whose exceptions propagate."""
import os
import signal
import threading
import time

import pytest

import vehs

MODEL = vehs.Model.paper(0.1, {1: -1.0, 3: 1.0}, 0.02, 0.01)


def test_keyboard_interrupt_stops_a_long_simulate():
    # 8 records x 10^7 samples x 20 substeps: about a minute of work (640 MB of records)
    # The stop is measured in this process's CPU time (every thread), not wall time: on a quiet
    # machine 0.27 CPU s / 0.55 s wall; beside 10 busy processes on 2 cores the same 0.28 CPU s
    # took 6.6 s wall, which failed a wall-clock bound of 5 s.
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    start = time.process_time()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        vehs.simulate(MODEL, trajectories=8, duration=1e5, dt=0.01, substeps=20, record_velocity=False)
    cpu = time.process_time() - start
    timer.join()
    assert cpu < 5.0, cpu
    r = vehs.simulate(MODEL, trajectories=2, duration=1, dt=0.01)  # still usable
    assert r.x.shape == (2, 100)


def test_progress_callback_sees_the_work_and_its_exceptions_propagate():
    events = []
    vehs.simulate(MODEL, trajectories=4, duration=100, dt=0.01, progress=lambda *e: events.append(e))
    assert events and events[-1][0] == "simulate" and events[-1][3] is True
    # the simulator counts the steps between samples (4 x 9999) against a total of samples (4 x 10^4)
    assert events[-1][2] == 4 * 10000 and events[-1][1] == 4 * 9999

    def boom(*event):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        vehs.simulate(MODEL, trajectories=4, duration=1000, dt=0.01, progress=boom)


def test_the_gil_is_released_while_the_library_works():
    spins = [0]
    marks = []  # the main thread's spin count at each progress event (inside the library's call)
    worker = threading.Thread(target=vehs.simulate, args=(MODEL,),
                              kwargs=dict(trajectories=8, duration=1e3, dt=0.01, substeps=10, record_velocity=False,
                                          progress=lambda *event: marks.append(spins[0])))
    worker.start()
    while worker.is_alive():
        spins[0] += 1  # runs only while the simulating thread does not hold the GIL
    worker.join()
    assert len(marks) >= 2 and marks[-1] - marks[0] > 1000, marks[:3] + marks[-3:]
