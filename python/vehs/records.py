"""Records: displacement records in memory, shared with the library without copies."""
import json

import numpy as np

from . import _vehs


class Records:
    """Records of x (and the true velocity y from a simulation, the drive u when present).

    The arrays are NumPy views of the records' memory (no copy): the library's own for simulated
    records, else the array the Records was made from (read-only then). ``x`` is 2-D (records ×
    samples) when every record has the same length, else 1-D (all records concatenated; ``sizes``
    tells where each ends).
    """

    def __init__(self, core):
        self._core = core
        self.statistics = None  # vehs.simulate(..., statistics=...): the Monte Carlo statistics of the run
        self.units = None  # vehs.read(..., units=...): the data's units block (vehs.plot labels axes with it)

    def _shaped(self, flat):
        sizes = self.sizes
        if flat.size and len(set(sizes)) == 1:
            return flat.reshape(len(sizes), sizes[0])
        return flat

    @property
    def x(self):
        return self._shaped(self._core.x)

    @property
    def y(self):
        return self._shaped(self._core.y)

    @property
    def u(self):
        return self._shaped(self._core.u)

    @property
    def sizes(self):
        return list(self._core.sizes)

    @property
    def ids(self):
        return list(self._core.ids)

    @property
    def dt(self):
        return self._core.dt

    @property
    def t(self):
        """Sample times of one record (t = 0, dt, ...) when every record has the same length."""
        return np.arange(self.sizes[0]) * self.dt

    def __len__(self):
        return len(self.sizes)

    def __repr__(self):
        return f"vehs.Records({len(self)} records, {sum(self.sizes)} samples, dt={self.dt:g})"


def read(data=None, **options):
    """Records from measurement files (CSV, .npy, .mat), read and checked as identify-vehs and
    diagnose-vehs read them: the same readers and data checks, the same one-line errors (raised as
    :class:`vehs.Error`). ``data``: a path or a list of paths. Options are the tools' measurement
    keys: ``columns``, ``dt``, ``mat_variable``, ``sampling``, ``detrend``, ``glitches``,
    ``flat_stretches``; ``u=True`` requires the drive column in every file (it is read whenever a
    file has it). identify and diagnose take the Records as checked here. A path may be a glob
    pattern (``"rig/run_*.csv"``: the matching files in byte order, as in the tools' configs).
    ``measurement="rig.json"``: a measurement file holding any of these keys and ``data`` (the
    tools' ``measurement`` key); what the call gives itself wins. ``units``
    (``{"length": "mm", "time": "s"}``, given or from the measurement file) is checked as the tools
    check it and kept as ``Records.units`` for vehs.plot's labels."""
    from .options import options_json
    if data is not None:
        options["data"] = [str(p) for p in data] if isinstance(data, (list, tuple)) else [str(data)]
    core, units = _vehs.read(options_json("vehs.read", options))
    records = Records(core)
    records.units = json.loads(units) or None
    return records


def as_records(x, dt=None, u=None, source="x"):
    """Records from a Records (as is), a 2-D array (one record per row), a 1-D array (one record)
    or a list of 1-D arrays (records of any lengths).

    A C-contiguous float64 array is not copied: the library reads its memory in place, and the
    Records holds the array (it cannot be freed or resized meanwhile; writing into it while a call
    reads it, e.g. from another thread, is undefined, as NumPy's own rules say). Other arrays (other
    dtypes, strided views, Fortran order) and lists of records are converted to one contiguous
    float64 array first (one copy)."""
    if isinstance(x, Records):
        if u is not None:
            raise _vehs.Error(f"{source}: u comes with the Records")
        return x
    if dt is None:
        raise _vehs.Error(f"{source}: give dt (the sampling interval) with an array")
    if isinstance(x, (list, tuple)) and x and np.ndim(x[0]) == 1:
        parts = [np.asarray(r, dtype=np.float64) for r in x]
        sizes = [p.size for p in parts]
        flat = np.concatenate(parts)
        uflat = None if u is None else np.concatenate([np.asarray(r, dtype=np.float64) for r in u])
    else:
        a = np.asarray(x, dtype=np.float64)
        if a.ndim == 1:
            a = a[None, :]
        if a.ndim != 2:
            raise _vehs.Error(f"{source}: must be 1-D (one record) or 2-D (records x samples), got {a.ndim}-D")
        sizes = [a.shape[1]] * a.shape[0]
        flat = np.ascontiguousarray(a).reshape(-1)
        uflat = None if u is None else np.ascontiguousarray(np.asarray(u, dtype=np.float64)).reshape(-1)
    return Records(_vehs.Records.from_arrays(flat, sizes, float(dt), uflat, source))
