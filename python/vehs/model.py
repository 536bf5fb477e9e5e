"""vehs.Model: a model of dX = Y dt, dY = b2 dt + sqrt(a22) dB plus named effects."""
import collections
import json
import os
import tempfile

from . import _vehs


def _effect_list(effects):
    """[(name, params)] from {name: params}, [name, ...] or [(name, params), ...]."""
    if isinstance(effects, dict):
        return [(name, dict(params or {})) for name, params in effects.items()]
    return [(e, {}) if isinstance(e, str) else (e[0], dict(e[1])) for e in (effects or [])]


Parameter = collections.namedtuple("Parameter", "name value stderr unit")
Parameter.__doc__ = """One row of the parameter table: physical name (beta, k3, 2D, coulomb_friction.mu, ...), value,
standard error (nan when the model file has none) and unit."""


class Model:
    """A vehs model with the sections of its file (identify's report travels with it).

    Build one from terms and physical parameters (the C++ ModelBuilder)::

        Model(drift={"x": -1.0, "x^3": 1.0}, parameters={"beta": 0.1},
              diffusion={"1": 0.02, "x^2": 0.01}, effects={"coulomb_friction": {"mu": 0.05}})

    or from a model file / dict (``Model.load``, ``Model.from_dict``); ``to_dict`` and ``save`` give
    the model file format back.
    """

    def __init__(self, drift=None, diffusion=None, parameters=None, effects=None, *, where="model", _core=None):
        if _core is None:
            _core = _vehs.Model.build(list((drift or {}).items()), list((diffusion or {}).items()),
                                      list((parameters or {}).items()), _effect_list(effects), where)
        self._core = _core

    @classmethod
    def from_dict(cls, d, where="model"):
        return cls(_core=_vehs.Model.from_json(json.dumps(d), where))

    @classmethod
    def load(cls, path):
        with open(path, "r", encoding="utf-8") as f:
            text = f.read()
        try:
            return cls(_core=_vehs.Model.from_json(text, str(path)))
        except json.JSONDecodeError as e:  # pragma: no cover - from_json parses itself
            raise _vehs.Error(f"{path}: {e}") from None

    @classmethod
    def paper(cls, beta, k, two_D, two_Q=0.0):
        """The paper's harvester: b2 = -beta y - sum k_i x^i, a22 = 2D + 2Q x^2 (k: {power: k_i})."""
        drift = {("x" if p == 1 else f"x^{p}"): -c for p, c in sorted(k.items())}
        drift["y"] = -beta
        return cls(drift=drift, diffusion={"1": two_D, "x^2": two_Q})

    def to_dict(self):
        return json.loads(self._core.to_json())

    def save(self, path):
        """Writes the model file atomically."""
        d = os.path.dirname(os.path.abspath(path))
        fd, tmp = tempfile.mkstemp(dir=d, prefix=".vehs-model-")
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            json.dump(self.to_dict(), f, indent=2)
            f.write("\n")
        os.replace(tmp, path)

    @property
    def drift(self):
        return self.to_dict().get("drift", {})

    @property
    def diffusion(self):
        return self.to_dict().get("diffusion", {})

    @property
    def stderr(self):
        return self.to_dict().get("stderr", {})

    def parameters(self):
        """The parameter table of identify-vehs, diagnose-vehs and vehs-compare as a list of
        :class:`Parameter` (name, value, stderr or nan, unit) in the library's order: beta, k_i, ...,
        2D, 2Q, effects. The unit is the parameter's dimension in the names of the model's ``units``
        section (``{"length": "mm", "time": "s"}`` gives "1/(mm^2 s^2)" for k3); a name the section
        lacks is written as the quantity ("1/time"). The rule is the library's
        (vehs/io/parameter_units.hpp), the one the command-line tools print."""
        return [Parameter(*row) for row in self._core.parameters()]

    def __getitem__(self, name):
        return self._core.get(name)

    def with_parameter(self, name, value):
        """A copy with one physical parameter (beta, k3, 2D, mu, drift[x^2*y], ...) changed."""
        core = self._core.__copy__()
        core.set(name, float(value))
        return Model(_core=core)

    def b2(self, x, y, u=0.0):
        return self._core.b2(float(x), float(y), float(u))

    def a22(self, x, y):
        return self._core.a22(float(x), float(y))

    def __repr__(self):
        terms = ", ".join(f"{n}={v:.6g}" for n, v, _, _ in self.parameters())
        return f"vehs.Model({terms})"
