"""Progress callbacks: the library reports (task, done, total, finished, seconds).

Every long phase is a task of its own ("identify", "likelihood starts", "likelihood fit",
"diagnose", "score tests", "confirmation refits", ...). ``total`` 0 means a phase whose length is
not known in advance: ``done`` counts its steps so far. While a task runs an event comes at least
every half second; ``finished`` is set on the last event of each task."""


def tqdm_progress(**tqdm_options):
    """A progress callback drawing one tqdm bar per task (tqdm.auto: a widget in notebooks); a task
    of unknown length shows its steps and elapsed time. tqdm comes with the package's ``progress``
    extra: ``pip install 'vehs[progress]'``."""
    try:
        from tqdm.auto import tqdm
    except ImportError as e:
        raise ImportError("vehs.tqdm_progress needs tqdm: pip install 'vehs[progress]' (or pip install tqdm)") from e

    bars = {}

    def callback(task, done, total, finished, seconds):
        bar = bars.get(task)
        if bar is None:
            bar = bars[task] = tqdm(total=total if total > 0 else None, desc=task, **tqdm_options)
        bar.update(done - bar.n)
        if finished:
            bar.close()
            del bars[task]

    return callback
