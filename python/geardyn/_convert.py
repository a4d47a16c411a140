"""Conversions of Python arguments to the payload of the Rust half (``_geardyn``): where a
configuration comes from, counts, pairs, triples, value lists; and of its column tables back
(names as numpy unicode arrays). The type errors are raised here; everything else is checked by
the library."""

from __future__ import annotations

import json
import os
from collections.abc import Mapping

import numpy as np

from . import _geardyn

def _assignment(name, value):
    """``NAME=VALUE`` as the CLI's ``--set`` takes it (floats in shortest round-trip form)."""
    if not isinstance(name, str):
        raise TypeError(f"parameter names are strings, not {type(name).__name__}")
    if isinstance(value, str):
        return f"{name}={value.strip()}"
    if isinstance(value, (bool, np.bool_)):
        raise TypeError(f"parameter {name}: a number, not a bool")
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"parameter {name}: a number, not {type(value).__name__}") from None
    return f"{name}={number!r}"


def _source(preset, config, set_, params):
    # contact="linear" (LAW[:EXPONENT[:RESTITUTION]]) is the CLI's --contact, not a number
    params = dict(params)
    contact = params.pop("contact", None)
    if contact is not None and not isinstance(contact, str):
        raise TypeError("contact: a law as the CLI's --contact takes it, e.g. 'linear' or 'power:1.5'")
    sets = []
    if set_ is not None:
        if not isinstance(set_, Mapping):
            raise TypeError("set: a dict {name: value}, e.g. set={'pair.mu': 0.1}")
        sets += [_assignment(k, v) for k, v in set_.items()]
    sets += [_assignment(k, v) for k, v in params.items()]
    path = text = None
    if config is not None:
        if isinstance(config, Mapping):
            try:
                text = json.dumps(config, allow_nan=False)
            except RecursionError:
                raise ValueError("malformed config dict: nested too deeply (a configuration has tables two levels deep, as geardyn.config() returns)") from None
            except (TypeError, ValueError) as e:
                raise ValueError(f"malformed config dict: {e}") from None
        elif isinstance(config, (str, os.PathLike)):
            path = os.fspath(config)
        else:
            raise TypeError("config: a path to a TOML file or a dict from geardyn.config()")
    if preset is not None and not isinstance(preset, str):
        raise TypeError("preset: a preset name (see geardyn.presets())")
    return {
        "preset": preset,
        "config_path": path,
        "config_json": text,
        "sets": sets,
        "contact": contact,
    }


def _opt_float(name, v):
    if v is None:
        return None
    if isinstance(v, (bool, np.bool_)):
        raise TypeError(f"{name}: a number, not a bool")
    try:
        return float(v)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: a number, not {type(v).__name__}") from None


# the keyword defaults below, read from the library's requests (the CLI shows the same ones)
_D = _geardyn.defaults()

_COUNT_MAX = 2**62  # far above every count the library takes (each has its own, lower limit)


def _count(name, v, lo=0):
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)):
        raise TypeError(f"{name}: an integer, not {type(v).__name__}")
    if v < lo:
        raise ValueError(f"bad {name} {v}: allowed >= {lo}")
    if v > _COUNT_MAX:
        raise ValueError(f"bad {name} {v:.3g}: far too large (every count is at most {_COUNT_MAX:.3g})")
    return int(v)


def _sim(periods, transient, integrator, steps_per_cycle):
    if integrator is not None and not isinstance(integrator, str):
        raise TypeError("integrator: 'dopri' or 'rk4'")
    return {
        "periods": _opt_float("periods", periods),
        "transient": _opt_float("transient", transient),
        "integrator": integrator,
        "steps_per_cycle": _opt_float("steps_per_cycle", steps_per_cycle),
    }


def _ident(capture_tol, early_stop, ident_rtol):
    return {
        "capture_tol": float(capture_tol),
        "early_stop": bool(early_stop),
        "ident_rtol": float(ident_rtol),
    }


def _pair(name, p):
    if p is None:
        return None
    try:
        lo, hi = p
    except (TypeError, ValueError):
        raise TypeError(f"{name}: a pair (min, max)") from None
    return (float(lo), float(hi))


def _triple(name, t):
    if t is None:
        return None
    try:
        lo, hi, n = t
    except (TypeError, ValueError):
        raise TypeError(f"{name}: a triple (min, max, count)") from None
    return (float(lo), float(hi), _count(f"{name} count", n))


def _values(values, range_, default):
    """Explicit values, or (start, stop, count) through the library's linspace (``--range``)."""
    if values is None and range_ is None:
        range_ = default
    vals = None
    if values is not None:
        vals = np.asarray(values, dtype=np.float64).ravel().tolist()
    return vals, _triple("range", range_)


def _strings(a):
    return np.asarray(a, dtype=str) if len(a) else np.zeros(0, dtype="<U1")


def _table(d):
    """A column table: lists of strings become numpy unicode arrays."""
    return {k: (_strings(v) if isinstance(v, list) else v) for k, v in d.items()}


def _signal_array(name, a):
    try:
        x = np.asarray(a, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: an array of numbers") from None
    if x.ndim != 1:
        raise ValueError(f"bad {name}: a one-dimensional array is needed, not shape {x.shape}")
    return x.tolist()


def _axis(name, a):
    """``(param, start, stop, count)`` or ``(param, values)``."""
    if not isinstance(a, (tuple, list)) or len(a) not in (2, 4) or not isinstance(a[0], str):
        raise TypeError(f"{name}: (param, start, stop, count) or (param, values)")
    if len(a) == 4:
        return a[0], None, _triple(name, a[1:])
    return a[0], np.asarray(a[1], dtype=np.float64).ravel().tolist(), None


