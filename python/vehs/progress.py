"""Progress callbacks: the library reports (task, done, total, finished, seconds)."""


def tqdm_progress(**tqdm_options):
    """A progress callback drawing one tqdm bar per task (tqdm.auto: a widget in notebooks)."""
    from tqdm.auto import tqdm

    bars = {}

    def callback(task, done, total, finished, seconds):
        bar = bars.get(task)
        if bar is None:
            bar = bars[task] = tqdm(total=total, desc=task, **tqdm_options)
        bar.update(done - bar.n)
        if finished:
            bar.close()
            del bars[task]

    return callback
