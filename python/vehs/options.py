"""Keyword options to the JSON object the tools' config parsers read."""
import json
import math

import numpy as np

from ._vehs import Error


def _plain(value):
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return [_plain(v) for v in value.tolist()]
    if isinstance(value, np.generic):
        return value.item()
    return value


def _check_finite(where, key, value):
    if isinstance(value, float) and not math.isfinite(value):
        raise Error(f"{where}: '{key}' must be a finite number (got {value})")
    if isinstance(value, dict):
        for k, v in value.items():
            _check_finite(where, f"{key}.{k}", v)
    elif isinstance(value, list):
        for v in value:
            _check_finite(where, key, v)


def options_json(where, options):
    """The options as JSON text; a non-finite number is an error naming its key."""
    plain = {k: _plain(v) for k, v in options.items() if v is not None}
    for k, v in plain.items():
        _check_finite(where, k, v)
    return json.dumps(plain)
