"""Progress callbacks: the library reports (task, done, total, finished, seconds)."""


def tqdm_progress(**tqdm_options):
    """A progress callback drawing one tqdm bar per task (tqdm.auto: a widget in notebooks).
    tqdm comes with the package's ``progress`` extra: ``pip install vehs[progress]``."""
    try:
        from tqdm.auto import tqdm
    except ImportError as e:
        raise ImportError("vehs.tqdm_progress needs tqdm: pip install 'vehs[progress]' (or pip install tqdm)") from e

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
