"""vehs.tqdm_progress draws tqdm bars (tqdm is the package's `progress` extra)."""
import io

import vehs


def test_tqdm_progress_draws_a_bar_per_task():
    out = io.StringIO()
    callback = vehs.tqdm_progress(file=out)
    vehs.simulate(vehs.Model.paper(0.1, {1: -1.0, 3: 1.0}, 0.02), trajectories=4, duration=20, dt=0.01,
                  seed=3, progress=callback)
    text = out.getvalue()
    assert "100%" in text, text
