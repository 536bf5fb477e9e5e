"""Mean harvested power with a standard error for any model, driven or not: a Monte Carlo run of
the model under the recorded input (simulate-vehs's ``statistics`` with the records' u as the
drive, record by record), as simulate-vehs computes it."""
import json

import numpy as np

from . import _vehs
from .compute import monte_carlo
from .records import Records, as_records


def power(model, records=None, harvester=None, seed=1, substeps=10, parameters=True, progress=None, **options):
    """Mean power of ``model`` with its standard error: simulate-vehs's ``mean_power`` section
    (watts and stderr in W with ``harvester`` constants and SI units in the model, else null;
    E[Y^2] and its stderr always; monte_carlo_stderr, parameter_stderr, error_method).

    ``records`` (a Records with u, e.g. from :func:`vehs.read`): one trajectory per record,
    driven by the record's u (applied as the model was fitted: held or interpolated), started at
    the record's first x with y = 0, as long as the shortest record. Without records, give
    simulate-vehs's keys (trajectories, duration, dt, drive, ...). ``parameters``: add the
    fitted parameters' errors (delta method over the model's covariance). Other keywords are
    simulate-vehs's keys (scheme, discard, ...); ``statistics`` keys go in ``statistics``."""
    statistics = dict(options.pop("statistics", {}))
    statistics["parameters"] = bool(parameters)
    drive = options.pop("drive", None)
    if records is not None:
        r = records if isinstance(records, Records) else as_records(records)
        if r._core.u.size == 0:
            raise _vehs.Error("vehs.power: the records have no input column u (give simulate-vehs's keys instead)")
        n = min(r.sizes)
        starts = np.concatenate([[0], np.cumsum(r.sizes)[:-1]])
        x, u = np.asarray(r._core.x), np.asarray(r._core.u)
        drive = [u[s:s + n] for s in starts]
        options.update(trajectories=len(starts), duration=n * r.dt, dt=r.dt, x0=[float(x[s]) for s in starts], y0=0.0)
    options.setdefault("seed", seed)
    options.setdefault("substeps", substeps)
    if harvester is not None:
        options["harvester"] = harvester
    stats = monte_carlo(model, progress=progress, statistics=statistics, drive=drive, **options)
    out = dict(stats["mean_power"])
    out["records"], out["samples_per_record"] = stats["records"], stats["samples_per_record"]
    return out


def watts(eyy, units, harvester):
    """The mean power in W of a stationary E[Y^2] (fpk-stationary's formula; None without
    harvester constants or SI units)."""
    return json.loads(_vehs.mean_power(float(eyy), json.dumps(units or {}), json.dumps(harvester or {})))["watts"]
