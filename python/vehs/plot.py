"""matplotlib figures for notebooks: potential, drift and diffusion with bands and binned
estimates from the records, the stationary density with its marginals, the suspects table, and
mean power in W with error bars (or against a swept parameter). Each function draws into ``ax`` (or a new figure) and
returns the axes.

Ranges. The x axis of potential, drift and diffusion is ``x`` when given; else the records' range
(smallest to largest sample of every record, widened by 5 % on each side); else, without records,
the model's: where its stationary density stays within e^-9 (about 1e-4) of its peak, by the rule
of fpk-stationary's automatic grid (fpk::automatic_domain with log_density_drop 9, which spans the
wells and the noise around them). A model that has no stationary density (a drive ``u``, a
dynamic effect) needs records or ``x``.

Labels. Every axis names its quantity; with units — ``units`` given, else the model's ``units``
section, else the records' (``vehs.read(..., units=...)``) — the unit follows in brackets, written
by the library's rule of the parameter tables (vehs/io/parameter_units.hpp): "displacement x [mm]",
"drift b2(x, 0) [mm/s^2]", "diffusion a22(x, 0) [mm^2/s^3]"."""
import json

import numpy as np

from . import _vehs
from .records import Records

_PLOT_LOG_DENSITY_DROP = 9.0  # e-folds below the density's peak at the edge of the model's range


def _units_of(model=None, records=None, units=None):
    """The units block of the labels: ``units``, else the model's, else the records'; None without."""
    if units:
        return units
    if model is not None:
        u = model.to_dict().get("units")
        if u:
            return u
    return getattr(records, "units", None) or None


def _label(quantity, units, length=0, time=0, input=0):
    """'quantity [unit]' in the units' names (the library's unit_text), or the quantity alone."""
    if not units:
        return quantity
    return f"{quantity} [{_vehs.unit_text(length, time, input, json.dumps(units))}]"


def _x_range(model, records, x, n=401):
    """The x values of a curve: ``x``, else the records' range, else the model's stationary region
    (the module's docstring states the rule)."""
    if x is not None:
        return np.asarray(x, dtype=float)
    if isinstance(records, Records):
        data = np.asarray(records.x).ravel()
        lo, hi = float(np.nanmin(data)), float(np.nanmax(data))
        pad = 0.05 * (hi - lo) if hi > lo else max(abs(lo), 1.0) * 0.05
        return np.linspace(lo - pad, hi + pad, n)
    try:
        lo, hi, _, _ = _vehs.stationary_region(model._core, _PLOT_LOG_DENSITY_DROP)
    except _vehs.Error as e:
        raise _vehs.Error(f"vehs.plot: give records or x: the model has no stationary region ({e})") from None
    return np.linspace(lo, hi, n)


def _axes(ax, **subplots):
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    return plt.subplots(**subplots)[1]


def _coefficient_band(model, x, kind):
    """Value and 2-standard-error band of the x-part (y = 0) of b2 or a22 on x. The band adds the
    terms' standard errors in quadrature (the model file holds no covariances)."""
    d = model.to_dict()
    terms = d.get(kind, {})
    se = d.get("stderr", {}).get(kind, {})
    value = np.array([model.b2(v, 0.0) if kind == "drift" else model.a22(v, 0.0) for v in x])
    var = np.zeros_like(x)
    for term, s in se.items():
        if term not in terms or not np.isfinite(s):
            continue
        unit = _unit_model(kind, term)
        if unit is None:
            continue
        phi = np.array([unit(v) for v in x])
        var += (s * phi) ** 2
    return value, 2.0 * np.sqrt(var)


def _unit_model(kind, term):
    """phi(x) at y = 0 of a term ("1", "x^3", ...); None for terms that vanish or need y."""
    if term == "1":
        return lambda v: 1.0
    if term == "x":
        return lambda v: v
    if term.startswith("x^") and term[2:].isdigit():
        p = int(term[2:])
        return lambda v: v ** p
    return None


def _model_curve(model, records, x, kind, ax, label):
    """Draws b2(x, 0) or a22(x, 0) with its 2-SE band; returns the axes and the x values."""
    ax = _axes(ax)
    x = _x_range(model, records, x)
    value, band = _coefficient_band(model, x, kind)
    ax.plot(x, value, label=label)
    ax.fill_between(x, value - band, value + band, alpha=0.3, label="2 SE")
    return ax, x


def _kinematics(records, model):
    """x, velocity and acceleration of every record, by the differences the model was fitted
    with: forward ((x[i+1] - x[i]) / dt, ...) for the forward and paper estimators (data from a
    scheme at the recorded step), else central (ULI: a sensor sampling a continuous process).
    Also the factor c with a22 = c dt E[(a - b2)^2 | x] (1 forward, 3/2 central)."""
    used = (model.to_dict().get("estimator") or {}).get("used", "uli")
    forward = used in ("forward", "paper")
    xs, vs, accs = [], [], []
    x = records.x if records.x.ndim == 2 else [records.x]
    dt = records.dt
    for r in x:
        if forward:
            v = np.diff(r) / dt
            xs.append(r[:-2])
            vs.append(v[:-1])
            accs.append(np.diff(v) / dt)
        else:
            xs.append(r[1:-1])
            vs.append((r[2:] - r[:-2]) / (2 * dt))
            accs.append((r[2:] - 2 * r[1:-1] + r[:-2]) / dt ** 2)
    return np.concatenate(xs), np.concatenate(vs), np.concatenate(accs), 1.0 if forward else 1.5


def _binned(x, values, edges):
    idx = np.digitize(x, edges) - 1
    centres, means, errors = [], [], []
    for b in range(len(edges) - 1):
        v = values[idx == b]
        if v.size >= 30:
            centres.append(0.5 * (edges[b] + edges[b + 1]))
            means.append(v.mean())
            errors.append(v.std(ddof=1) / np.sqrt(v.size))
    return np.array(centres), np.array(means), np.array(errors)


def potential(model, x=None, ax=None, records=None, units=None, **plot):
    """U(x) = -integral of b2(x, 0) from 0 (the restoring force's potential, per unit mass:
    length^2/time^2), over ``x`` or the range of ``records`` or of the model (module docstring)."""
    ax = _axes(ax)
    x = _x_range(model, records, x)
    f = np.array([model.b2(v, 0.0) for v in x])
    u = -np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(x))])
    u -= u[np.argmin(np.abs(x))]
    ax.plot(x, u, **plot)
    units = _units_of(model, records, units)
    ax.set_xlabel(_label("displacement x", units, length=1))
    ax.set_ylabel(_label("potential U(x)", units, length=2, time=-2))
    return ax


def drift(model, records=None, x=None, bins=40, ax=None, label="model", units=None):
    """b2(x, 0) with a 2-SE band, and binned E[acceleration | x] from the records (which equals
    the restoring force b2(x, 0) in stationarity for drifts linear in y). x spans ``x``, else the
    records, else the model's stationary region (module docstring)."""
    ax, x = _model_curve(model, records, x, "drift", ax, label)
    if isinstance(records, Records):
        xi, _, acc, _ = _kinematics(records, model)
        c, m, e = _binned(xi, acc, np.linspace(x.min(), x.max(), bins + 1))
        ax.errorbar(c, m, yerr=2 * e, fmt=".", label="binned data")
    units = _units_of(model, records, units)
    ax.set_xlabel(_label("displacement x", units, length=1))
    ax.set_ylabel(_label("drift b2(x, 0)", units, length=1, time=-2))
    ax.legend()
    return ax


def diffusion(model, records=None, x=None, bins=40, ax=None, label="model", units=None):
    """a22(x, 0) with a 2-SE band, and the binned estimate c dt E[(a - b2(x, v))^2 | x] from the
    records (c = 1 with forward differences, 3/2 with ULI's central ones: see _kinematics). x spans
    ``x``, else the records, else the model's stationary region (module docstring)."""
    ax, x = _model_curve(model, records, x, "diffusion", ax, label)
    if isinstance(records, Records):
        xi, vi, acc, factor = _kinematics(records, model)
        stride = max(1, xi.size // 200000)  # b2 is evaluated per sample in Python: subsample
        xi, vi, acc = xi[::stride], vi[::stride], acc[::stride]
        resid = acc - np.array([model.b2(a, b) for a, b in zip(xi, vi)])
        c, m, e = _binned(xi, factor * records.dt * resid ** 2, np.linspace(x.min(), x.max(), bins + 1))
        ax.errorbar(c, m, yerr=2 * e, fmt=".", label="binned data")
    units = _units_of(model, records, units)
    ax.set_xlabel(_label("displacement x", units, length=1))
    ax.set_ylabel(_label("diffusion a22(x, 0)", units, length=2, time=-3))
    ax.legend()
    return ax


def density(stationary, fig=None, units=None, model=None):
    """p(x, y) as a map with the marginals p(x) and p(y) beside it, over the solver's grid (the
    region where the density lives); returns the three axes. Labels carry ``units`` (else the
    ``model``'s units section, else those of the model vehs.stationary solved)."""
    import matplotlib.pyplot as plt

    fig = fig or plt.figure(figsize=(7, 6))
    grid = fig.add_gridspec(2, 2, width_ratios=(4, 1), height_ratios=(1, 4), wspace=0.05, hspace=0.05)
    main = fig.add_subplot(grid[1, 0])
    top = fig.add_subplot(grid[0, 0], sharex=main)
    side = fig.add_subplot(grid[1, 1], sharey=main)
    s = stationary
    main.pcolormesh(s.x, s.y, s.density.T, shading="nearest")
    units = _units_of(model, None, units) or getattr(s, "units", None)
    main.set_xlabel(_label("displacement x", units, length=1))
    main.set_ylabel(_label("velocity y", units, length=1, time=-1))
    top.plot(s.x, s.marginal_x)
    top.set_ylabel(_label("p(x)", units, length=-1))
    side.plot(s.marginal_y, s.y)
    side.set_xlabel(_label("p(y)", units, length=-1, time=1))
    top.tick_params(labelbottom=False)
    side.tick_params(labelleft=False)
    return main, top, side


def suspects(diagnosis, ax=None):
    """The suspects (missing effects) as a table, what the diagnosis recommends first and suspects
    of a set-aside split last (Diagnosis.suspects)."""
    ax = _axes(ax, figsize=(7, 0.4 * (len(diagnosis.suspects) + 2)))
    rows = []
    for s in diagnosis.suspects:
        params = ", ".join(f"{k} = {v:.3g}" for k, v in list((s.get("params") or {}).items())[:3])
        z = s.get("z")
        rows.append([s["effect"], s["source"], f"{float(z):.1f}" if isinstance(z, (int, float)) else "",
                     s["status"], params])
    ax.axis("off")
    ax.set_title(f"verdict: {diagnosis.verdict}, score {diagnosis.score:.3g}")
    if rows:
        table = ax.table(cellText=rows, colLabels=["suspect", "evidence", "z", "status", "fitted"],
                         loc="center")
        table.auto_set_font_size(False)
        table.set_fontsize(8)
        table.auto_set_column_width(col=list(range(5)))
    return ax


def power(data, ax=None, units=None, harvester=None, moment="E[Y^2]"):
    """Mean power in W with error bars (±2 standard errors): ``data`` is one :func:`vehs.power`
    result, a list of them, or a dict {label: result}. A sweep (vehs.sweep) is drawn against its
    first parameter (one line per value of the second), in W when ``units`` and ``harvester``
    give the constants (vehs.power.watts), else as ``moment`` (to which the power is proportional)."""
    ax = _axes(ax)
    if isinstance(data, dict) and "points" in data:
        return _sweep_power(data, ax, units, harvester, moment)
    if isinstance(data, dict) and "E[Y^2]" in data:
        data = [data]
    items = list(data.items()) if isinstance(data, dict) else [(str(i + 1), d) for i, d in enumerate(data)]
    in_watts = all(d.get("watts") is not None for _, d in items)
    value, err = ("watts", "stderr") if in_watts else ("E[Y^2]", "E[Y^2]_stderr")
    pos = np.arange(len(items))
    ax.errorbar(pos, [d[value] for _, d in items], yerr=[2 * d[err] for _, d in items], fmt="o", capsize=4)
    ax.set_xticks(pos)
    ax.set_xticklabels([k for k, _ in items])
    ax.set_ylabel("mean power [W] (±2 SE)" if in_watts else
                  _label("E[Y^2]", units, length=2, time=-2) + " (±2 SE; power ∝ E[Y^2])")
    return ax


def _moment_label(moment, units):
    """E[X^2] [mm^2], E[Y^2] [mm^2/s^2], E[XY] [mm^2/s] with units."""
    time = {"E[X^2]": 0, "E[Y^2]": -2, "E[XY]": -1}.get(moment)
    return moment if time is None else _label(moment, units, length=2, time=time)


def _sweep_power(sweep, ax, units, harvester, moment):
    from .power import watts

    names = [p["name"] for p in sweep["parameters"]]
    pts = [p for p in sweep["points"] if "error" not in p]
    in_watts = moment == "E[Y^2]" and watts(1.0, units, harvester) is not None
    scale = watts(1.0, units, harvester) if in_watts else 1.0
    if len(names) == 1:
        ax.plot([p[names[0]] for p in pts], [scale * p[moment] for p in pts], "o-")
    else:
        for v in sweep["parameters"][1]["values"]:
            sel = [p for p in pts if p[names[1]] == v]
            ax.plot([p[names[0]] for p in sel], [scale * p[moment] for p in sel], "o-", label=f"{names[1]} = {v:g}")
        ax.legend()
    ax.set_xlabel(f"{names[0]} [{_vehs.parameter_unit(names[0], json.dumps(units))}]" if units else names[0])
    ax.set_ylabel("mean power [W]" if in_watts else _moment_label(moment, units))
    return ax
