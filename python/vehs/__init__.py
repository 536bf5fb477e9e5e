"""vehs from Python: stochastic vibration energy harvesters — simulate, identify, solve, diagnose.

The library's own types and functions (a nanobind extension, ``vehs._vehs``), not a wrapper
around the executables. Keyword options are the keys of the matching tool's JSON config
(``simulate-vehs --help`` and friends), checked by the same code, so errors are the CLI's one-line
messages (raised as :class:`vehs.Error`, a ``ValueError``).
"""
from ._vehs import Error, __version__, max_threads, set_threads
from .model import Model, Parameter
from .records import Records, as_records, read
from .compute import FitOptions, diagnose, identify, identify_study, monte_carlo, simulate, stationary, sweep, Diagnosis, Stationary
from .progress import tqdm_progress
from .power import power

__all__ = [
    "Error", "FitOptions", "Model", "Parameter", "Records", "as_records", "read", "simulate", "monte_carlo", "identify", "identify_study", "stationary",
    "sweep", "power", "diagnose", "Diagnosis", "Stationary", "set_threads", "max_threads", "tqdm_progress",
]
