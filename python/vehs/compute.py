"""The library's computations: simulate, monte_carlo, identify, stationary, sweep, diagnose.

Each takes the keys of its tool's config as keyword options; the GIL is released while the
library works, ``progress(task, done, total, finished, seconds)`` is called as it goes, and
Ctrl-C stops a simulation cleanly (KeyboardInterrupt).
"""
import json
from dataclasses import dataclass, field

import numpy as np

from . import _vehs
from ._vehs import Error
from .model import Model
from .options import options_json
from .records import Records, as_records


def _core(model):
    if not isinstance(model, Model):
        raise TypeError(f"expected a vehs.Model, got {type(model).__name__}")
    return model._core


def _drive(u):
    """A recorded drive as the library takes it: a list of 1-D float64 arrays (one shared by all
    trajectories, or one per trajectory), from a 1-D array, a 2-D array (one row per trajectory)
    or a list of 1-D arrays."""
    if u is None:
        return None
    if isinstance(u, (list, tuple)) and u and np.ndim(u[0]) == 1:
        rows = list(u)
    else:
        a = np.asarray(u, dtype=np.float64)
        if a.ndim not in (1, 2):
            raise _vehs.Error(f"drive: must be 1-D (shared by all trajectories) or 2-D (one row per trajectory), got {a.ndim}-D")
        rows = [a] if a.ndim == 1 else list(a)
    return [np.ascontiguousarray(r, dtype=np.float64) for r in rows]


def simulate(model, progress=None, drive=None, statistics=None, **options):
    """Records of the model (simulate-vehs's keys: trajectories, duration, dt, substeps, scheme,
    seed, x0, y0, burn_in, sensor_noise, record_velocity, first_record, record_phases, ...). The
    arrays of the returned Records are the simulator's own memory (no copy).

    ``drive``: the recorded drive u for a model with a 'u' term, sampled at dt — one series (1-D)
    shared by all trajectories, or one per trajectory (2-D, or a list); applied as
    simulate-vehs applies its drive file (held per step, or interpolated as the model was fitted).
    ``statistics`` ({} for the defaults; discard, grid, batches): the Monte Carlo statistics of
    the same run as well, in ``records.statistics`` (as :func:`monte_carlo` returns them)."""
    if statistics is not None:
        options["statistics"] = statistics
    core, stats = _vehs.simulate(_core(model), options_json("vehs.simulate", options), progress, _drive(drive))
    records = Records(core)
    records.statistics = json.loads(stats) if stats else None
    return records


def monte_carlo(model, progress=None, statistics=None, drive=None, **options):
    """Monte Carlo statistics while simulating (no records kept): simulate-vehs's keys with
    ``statistics`` ({} for the defaults; discard, grid, batches) and ``drive`` as for
    :func:`simulate`. Returns simulate-vehs's statistics JSON as a dict plus ``record_means``
    (each record's mean of every moment)."""
    options["statistics"] = {} if statistics is None else statistics
    text = _vehs.monte_carlo(_core(model), options_json("vehs.monte_carlo", options), progress, _drive(drive))
    return json.loads(text)


class FitOptions(_vehs.FitOptions):
    """The fit's typed options (vehs::FitOptions): identify-vehs's keys (estimator, drift_library,
    diffusion_library, effects, sparsity, criterion, likelihood, glitches, detrend, ...) read and
    checked once, with the CLI's messages. The common ones are properties to read and set:
    ``estimator``, ``likelihood_use`` ('auto', 'always', 'never'), ``likelihood_starts``,
    ``drift_library``, ``diffusion_library`` (term names), ``effects`` (read only), ``glitches``
    and ``flat_stretches`` ('error', 'drop', 'keep')."""

    def __init__(self, **options):
        super().__init__(options_json("vehs.identify", options))


def identify(x, dt=None, u=None, progress=None, options=None, **keys):
    """Drift and diffusion from displacement records: ``(Model, report)``.

    ``x``: Records (used in place), a 2-D array (records × samples), a 1-D array or a list of
    1-D arrays: a C-contiguous float64 array is read in place (no copy; see :func:`as_records`),
    others are copied once. ``detrend="mean"`` necessarily works on a copy of the records (the
    caller's array is never modified). ``options``: a :class:`FitOptions`, or identify-vehs's keys
    as keyword arguments (estimator, drift_library, diffusion_library, effects, sparsity,
    criterion, ...). The fit is identify-vehs's (vehs::fit): the same records give the same model,
    bitwise. The model carries the report sections, so ``model.save(path)`` writes what
    identify-vehs writes (without its data/provenance). Records read by :func:`vehs.read` with
    ``units`` (given or from the measurement file) give the model those units unless ``units`` is
    given here."""
    if options is None:
        if isinstance(x, Records) and x.units and "units" not in keys:
            keys["units"] = x.units
        options = FitOptions(**keys)
    elif keys:
        raise TypeError("vehs.identify: give options=FitOptions(...) or keyword options, not both")
    elif not isinstance(options, _vehs.FitOptions):
        raise TypeError("vehs.identify: options must be a vehs.FitOptions")
    records = as_records(x, dt, u)
    core, report = _vehs.identify(records._core, options, progress)
    return Model(_core=core), json.loads(report)


def identify_study(study, progress=None, **options):
    """identify-vehs's consistency study (the seed paper's Table 4): simulate the truth on a grid
    of dt x samples, identify every repeat, tabulate mean (sd) and the coverage of the 95 %
    intervals. ``study`` is the config's study object (truth: a Model, a dict or a model file;
    dt, samples, repeats, records, scheme, substeps, x0, seed, sensor_noise, burn_in); options are
    the moment estimator's keys. Returns the study's JSON as a dict, with ``table`` the Table 4
    text identify-vehs prints."""
    study = dict(study)
    if isinstance(study.get("truth"), Model):
        study["truth"] = study["truth"].to_dict()
    elif study.get("truth") is not None and not isinstance(study["truth"], dict):
        study["truth"] = str(study["truth"])
    options["study"] = study
    return json.loads(_vehs.identify_study(options_json("vehs.identify_study", options), progress))


@dataclass
class Stationary:
    """A stationary density p(x, y) on cell centres x, y (density[i, j] at x[i], y[j])."""

    density: np.ndarray
    x: np.ndarray
    y: np.ndarray
    marginal_x: np.ndarray
    marginal_y: np.ndarray
    moments: dict
    summary: dict = field(repr=False)
    power: dict = None  # fpk-stationary's mean_power: watts (null without harvester constants or SI units), how
    units: dict = None  # the model's units section (vehs.plot.density labels its axes with it)
    _core: object = field(repr=False, default=None)


def _centres(axis):
    lo, hi, n = axis
    return lo + (np.arange(n) + 0.5) * (hi - lo) / n


def stationary(model, grid=None, progress=None, **options):
    """The stationary Fokker-Planck density of the model (fpk-stationary's keys: grid, scheme,
    solver, ordering, boundary_mass_tolerance, auto_domain_efolds, harvester, ...). The density array
    is the solver's own memory (no copy). ``power``: the mean power in W with ``harvester`` (or the
    model file's) constants and SI units. A driven model (a 'u' term) has no stationary density:
    use :func:`vehs.power` with its records."""
    if grid is not None:
        options["grid"] = grid
    core = _vehs.stationary(_core(model), options_json("vehs.stationary", options), progress)
    summary = json.loads(core.summary())
    g = summary["grid"]
    x, y = _centres(g["x"]), _centres(g["y"])
    return Stationary(density=core.density.reshape(x.size, y.size), x=x, y=y, marginal_x=core.marginal_x,
                      marginal_y=core.marginal_y, moments={k: v for k, v in summary.items() if k.startswith("E[")}, summary=summary,
                      power=summary.get("mean_power"), units=model.to_dict().get("units"),
                      _core=core)


def sweep(model, sweep, grid=None, progress=None, **options):
    """fpk-stationary's parameter sweep on this machine (both cores): ``sweep`` is
    {name: [min, max, n] or {"values": [...]}} for one or two parameters. Returns the sweep
    section fpk-stationary writes: parameters, grid, points (E[X^2], E[Y^2], ... per point)."""
    options["sweep"] = sweep
    if grid is not None:
        options["grid"] = grid
    return json.loads(_vehs.sweep(_core(model), options_json("vehs.sweep", options), 0, 0, progress))


@dataclass
class Diagnosis:
    """What :func:`diagnose` found: ``verdict``, ``score``, ``suspects`` (what it recommends
    first, see :func:`ranked_suspects`), the HTML ``report`` path and the whole ``result`` (the
    diagnosis file diagnose-vehs writes)."""

    verdict: str
    score: float
    suspects: list
    report: str
    result: dict = field(repr=False)
    units: dict = field(repr=False, default=None)  # the diagnosed model's units, kept by refit

    def refit(self, x, dt=None, u=None, progress=None, **keys):
        """The refit this diagnosis recommends (identify-vehs --refit): :func:`identify` on the
        records with ``result["refit_config"]`` (the model's terms and effects plus the named
        ones) and the diagnosed model's units; keyword options given here win. Raises
        :class:`vehs.Error` when the diagnosis recommends no refit."""
        config = self.result.get("refit_config")
        if not config:
            raise Error(f"vehs.Diagnosis.refit: the diagnosis ({self.verdict}) recommends no refit "
                        f"(its refit_config is null)")
        options = dict(config)
        if self.units and "units" not in keys and not getattr(x, "units", None):
            options["units"] = self.units
        options.update(keys)
        return identify(x, dt, u, progress, **options)


def diagnose(model, x, dt=None, u=None, report=None, label="model", progress=None, **options):
    """Is the model adequate for the records? diagnose-vehs's keys (alpha, twins, suspects, ...).
    ``report``: a folder for the HTML report and its history.json (as diagnose-vehs writes them),
    or None. Returns verdict, score, ranked suspects, report path and the whole result."""
    records = as_records(x, dt, u)
    text, html = _vehs.diagnose(_core(model), records._core, options_json("vehs.diagnose", options),
                                "" if report is None else str(report), label, progress)
    result = json.loads(text)
    return Diagnosis(verdict=result["verdict"], score=result["score"], suspects=ranked_suspects(result),
                     report=html or None, result=result, units=model.to_dict().get("units"))


_STATUS_ORDER = {"recommended": 0, "significant": 1, "not significant": 2, "set aside": 3}


def ranked_suspects(result):
    """Every suspect of a diagnosis once, what it recommends first: the recommended effects (in its
    order), then the significant ones (score tests by z, then held-out evidence), then the rest, and
    last the held-out suspects of a split that was set aside ("not a test on these data"). Each entry
    is the diagnosis file's entry with ``source`` ("score test" or "held-out") and ``status``."""
    recommended = list(result.get("recommended") or [])
    set_aside = bool(result.get("suspects_heldout", {}).get("set_aside"))
    entries = []
    for e in result.get("score_suspects") or []:
        entries.append(dict(e, source="score test"))
    for e in result.get("suspects") or []:
        entries.append(dict(e, source="held-out"))
    for e in entries:
        if e["effect"] in recommended:
            e["status"] = "recommended"
        elif e["source"] == "held-out" and set_aside:
            e["status"] = "set aside"
        else:
            e["status"] = "significant" if e.get("significant") else "not significant"

    def key(e):
        rank = recommended.index(e["effect"]) if e["status"] == "recommended" else 0
        z = e.get("z")
        return (_STATUS_ORDER[e["status"]], rank, e["source"] != "score test", -(z if isinstance(z, (int, float)) else 0.0))

    out, seen = [], set()
    for e in sorted(entries, key=key):
        if e["effect"] not in seen:
            seen.add(e["effect"])
            out.append(e)
    return out
