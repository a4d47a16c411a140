"""geardyn: nonlinear dynamics of spur gear pairs, from Python.

The same library as the ``geardyn`` command-line program (not a wrapper around it): every
analysis of the CLI is a function here, with the same parameter names, the same defaults and the
same numbers for the same inputs. Results are objects holding numpy arrays and plain dicts.

Where a configuration comes from (every function that runs a model)
--------------------------------------------------------------------
preset : str, optional
    Built-in preset (:func:`presets`): ``"classic"`` (default), ``"breakage"``, ``"internal"``.
config : str, os.PathLike or dict, optional
    A TOML configuration file (as ``geardyn show`` prints it), or the dict returned by
    :func:`config`. Excludes ``preset``.
set : dict, optional
    Overrides ``{name: value}`` applied in order, exactly as ``--set NAME=VALUE``; the way to
    give dotted names: ``set={"pair.mu": 0.1, "pair.operating.speed_rpm": 9000}``.
**params
    Overrides by keyword, applied after ``set``: model parameters (``omega``, ``F``, ``xi``,
    ``c``, ``D``, ``D_d``, ``D_s``, ``kappa``, ``R``, ...) and simulation settings (``x0``,
    ``v0``, ``tau0``, ``rtol``, ``atol``, ``steps_per_cycle``, ``transient_periods``,
    ``record_periods``, and the decision's horizon, work budget and follow resolution
    ``decision_periods``, ``decision_budget``, ``follow_steps``); see :func:`parameter_names` and docs/configuration.md.
contact : str, optional (keyword)
    The contact law of both flanks as the CLI's ``--contact`` takes it,
    ``LAW[:EXPONENT[:RESTITUTION]]``: ``"linear"``, ``"power:1.5"``,
    ``"lankarani_nikravesh:1.19:0.8"``; applied before the overrides.

Errors
------
``ValueError`` for bad parameters or settings, with the one-line message the CLI prints after
``error:``; ``OSError`` for files that cannot be read or written; ``RuntimeError`` when an
integration fails. Long calls release the GIL, run on the library's threads, print progress on
``sys.stderr`` only with ``progress=True``, and stop on Ctrl-C within about a second: the
``KeyboardInterrupt`` raised carries what was finished in its attribute ``partial`` — a
:class:`SweepResult` of the finished values (``bifurcation``, ``response``), a list of finished
values or cells (``continuation``, ``map2d``, as the CLI's checkpoint lines), columns ``cell``,
``kind``, ``attractor`` of the finished basin cells, or ``None`` (single runs).

Arrays
------
Floating-point columns are ``float64``, counts and indices ``int64``, flags ``bool``, names
numpy unicode arrays (``<U``); a column table is a dict of equally long 1-d arrays (pass it to
``pandas.DataFrame`` directly).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import warnings
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from . import _geardyn

__version__ = _geardyn.__version__

__all__ = [
    "presets",
    "parameter_names",
    "config",
    "derived",
    "simulate",
    "lyapunov",
    "bifurcation",
    "response",
    "basins",
    "continuation",
    "orbits",
    "signals",
    "indicators",
    "map2d",
    "stiffness",
    "report",
    "Result",
    "SimulationResult",
    "LyapunovResult",
    "SweepResult",
    "BasinsResult",
    "ContinuationResult",
    "OrbitsResult",
    "SignalsResult",
    "MapResult",
    "StiffnessResult",
]


# --------------------------------------------------------------------------- helpers


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


# --------------------------------------------------------------------------- results


class Result:
    """Base of the result objects: attributes, a short ``repr`` and :meth:`to_dict`."""

    _fields: tuple = ()

    def __init__(self, **kw):
        for k, v in kw.items():
            setattr(self, k, v)

    def to_dict(self):
        """The result's fields as a dict."""
        return {k: getattr(self, k) for k in self._fields}

    def to_dataframe(self, table=None):
        """A column table of the result as a ``pandas.DataFrame`` (pandas must be installed).

        ``table`` names the field (``"runs"``, ``"points"``, ``"impact_force"``, ``"cells"``,
        ...); by default the result's main table (``runs`` of a sweep). The columns are those of
        the CLI's CSV file of that table.
        """
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("to_dataframe needs pandas: pip install pandas") from None
        name = table or getattr(self, "_main_table", None)
        if name is None:
            raise ValueError(f"{type(self).__name__} has no main table: give table=")
        value = getattr(self, name, None)
        if not isinstance(value, dict) or not value:
            raise ValueError(f"{type(self).__name__}.{name} is not a column table")
        return pd.DataFrame(value)

    def __repr__(self):
        parts = []
        for k in self._fields:
            v = getattr(self, k)
            if isinstance(v, np.ndarray):
                parts.append(f"{k}=<{v.dtype} array {v.shape}>")
            elif isinstance(v, dict):
                parts.append(f"{k}=<dict: {', '.join(map(str, list(v)[:6]))}{', ...' if len(v) > 6 else ''}>")
            elif isinstance(v, list):
                parts.append(f"{k}=<list of {len(v)}>")
            else:
                parts.append(f"{k}={v!r}")
        return f"{type(self).__name__}({', '.join(parts)})"


class SimulationResult(Result):
    """Result of :func:`simulate` (the contents of the CLI's simulate folder).

    Attributes
    ----------
    strobe : ndarray, float64, shape (n, 3)
        Stroboscopic points, columns ``tau, x, v``: one row per recorded excitation period
        (strobe.csv).
    trajectory : dict of ndarray
        ``tau, x, v, mesh_force`` (float64) and ``state`` (int8: 1 drive, 0 separated, -1 back
        contact, -2 resting on the back stop), 128 samples per mesh cycle plus both sides of
        every event, over the last ``trajectory_periods`` recorded periods (trajectory.csv).
    events : dict of ndarray
        ``tau, cycle_position, kind, x, v_before, v_after, peak_force`` (events.csv); ``kind`` is a
        string array (``drive_enter``, ``drive_exit``, ``back_enter``, ``back_exit``, ``impact``,
        ``stick``, ``release``).
    sections : dict of ndarray
        ``section`` (``ds_up``, ``ds_down``, ``dd_up``, ``dd_down``), ``tau, x, v`` (sections.csv).
    description : str
        The decided motion in words (``period 1``, ``chaotic (TLE ...)``, ...). A diverged run
        (the CLI's error) is returned with a ``RuntimeWarning``.
    summary : dict
        What summary.json holds: ``period``, ``label``, ``motion``, ``counts``, ``healthy``,
        ``p_id``, force extrema, impacts, ``parameters`` (the integrated dimensionless values),
        contact durations, run lengths, ``method``, ``steps``, ``wall_time_s``.
    mesh_strobe : ndarray, float64, shape (m, 2)
        ``x, v`` at the end of every mesh cycle when an excitation period spans several (tooth
        breakage); empty otherwise.
    impact_force_per_period : ndarray, float64
        Largest impact force in each recorded excitation period.
    amplitudes : dict
        Means, RMS and peak-to-peak of ``x`` and the mesh force.
    final_state : tuple
        ``(tau, x, v)`` at the end.
    excitation_period : float
        The excitation period (dimensionless time).
    backlash_levels : tuple
        ``(D_d, D_s)``.
    config : dict
        The resolved configuration (config.toml).
    """

    _fields = (
        "strobe",
        "trajectory",
        "events",
        "sections",
        "summary",
        "description",
        "mesh_strobe",
        "impact_force_per_period",
        "amplitudes",
        "final_state",
        "excitation_period",
        "backlash_levels",
        "config",
    )


class LyapunovResult(Result):
    """Result of :func:`lyapunov`.

    Attributes
    ----------
    value : float
        Top Lyapunov exponent per unit dimensionless time: the variational (saltation) estimate,
        or the two-trajectory one when ``method="two-trajectory"``.
    stderr : float
        Its standard error (ten block means).
    method : str
        ``"variational"``, ``"two-trajectory"`` or ``"both"``.
    periods : int
        Excitation periods of the (last) run.
    converged : bool or None
        Whether the run-length doubling met its tolerance (None with a fixed ``periods``).
    tol : float or None
        The tolerance of the last round.
    rounds : dict of ndarray or None
        The doubling: ``periods`` (int64), ``tle``, ``half`` (the estimate at half the run),
        ``stderr``.
    history : ndarray, float64
        Running estimate after each excitation period of the run giving ``value``.
    annihilated : int
        Sticking intervals (perturbation contracted to zero) in that run.
    variational, two_trajectory : dict or None
        Each method's full result (``tle``, ``spread``, ``history``, ``time``, ``annihilated``).
    integrated : dict
        The integrated ``omega, F, xi, c, D_d, D_s``.
    config : dict
        The resolved configuration.
    """

    _fields = (
        "value",
        "stderr",
        "method",
        "periods",
        "converged",
        "tol",
        "rounds",
        "history",
        "annihilated",
        "variational",
        "two_trajectory",
        "integrated",
        "d0",
        "config",
    )


class SweepResult(Result):
    """Result of :func:`bifurcation` and :func:`response`.

    Attributes
    ----------
    points : dict of ndarray
        One entry per section point, the columns of the CLI's bifurcation.csv: the swept
        parameter under its own name (e.g. ``omega``, float64), ``branch`` (``none``, ``up``,
        ``down``), ``ic`` (int64), ``section``, ``x``, ``v`` (float64), ``label``.
    runs : dict of ndarray
        One entry per simulation, the columns of the CLI's runs.csv (and of the report's
        ``*_runs.csv``), in its order: the swept parameter under its own name, ``branch, ic, x0,
        v0, class`` (periodic, quasi-periodic, chaotic, unsettled, diverged, failed), ``label``
        (``n-p-q-r-s`` when periodic, else the class: no numbers), ``period, mesh_period``
        (int64; 0: none), ``healthy, back_contact`` (bool), ``impacts`` (int64), ``p_rate,
        q_rate, r_rate, s_rate`` (crossings per excitation period), ``p_id, max_force,
        min_force, max_impact_force, mean_x, rms_x, p2p_x, mean_force, rms_force, p2p_force,
        tle`` (NaN when not computed), ``decision_tle`` (the exponent the class was decided on),
        ``transient_used`` (int64), ``decided_by``, ``periods_integrated`` (int64), ``final_x,
        final_v``, ``reason`` (why a failed or diverged run has no verdict). The table is in
        docs/configuration.md ("Result tables").
    impact_force : dict of ndarray
        Largest impact force per recorded period per run (impact_force.csv): the swept
        parameter, ``branch, ic, period, impact_force``.
    jumps : list of dict
        (response only) jumps between up and down sweeps (jumps.json).
    param : str
        The swept parameter.
    values : ndarray, float64
        Its values.
    settings : dict
        The sweep settings as the library holds them.
    config : dict
        The resolved configuration.
    """

    _fields = ("points", "runs", "impact_force", "param", "values", "settings", "config")
    _main_table = "runs"


class BasinsResult(Result):
    """Result of :func:`basins`.

    Attributes
    ----------
    cells : ndarray, int64, shape (n_v, n_x)
        Attractor id of every initial state (rows: velocity, columns: displacement; as
        basins.npy): index into ``attractors``, -1 divergent, -2 failed.
    x, v : ndarray, float64
        Cell centres of the displacement (length n_x) and velocity (length n_v) axes.
    attractors : list of dict
        ``id``, ``label``, ``period``, ``healthy``, ``fraction`` (basin fraction), ``cells``,
        ``points`` (float64 array (k, 2) of stroboscopic points), ``bbox``, ``max_force``,
        ``p_id``. Ids are canonical: healthy first, then by period and position.
    diverged, failed, boundary_fraction : float
        Fractions of cells.
    captured_early : int
        Cells assigned early to a known attractor.
    """

    _fields = (
        "cells",
        "x",
        "v",
        "attractors",
        "diverged",
        "failed",
        "boundary_fraction",
        "captured_early",
        "periods",
        "phase",
        "settings",
        "config",
    )

    def to_xarray(self):
        """The grid as an ``xarray.DataArray`` ``attractor`` over dimensions ``v`` and ``x`` (the
        initial velocity and displacement at the cell centres); xarray must be installed. The
        attractors' labels are in its attribute ``labels`` (by id)."""
        xr = _xarray()
        return xr.DataArray(
            self.cells,
            dims=("v", "x"),
            coords={"v": self.v, "x": self.x},
            name="attractor",
            attrs={
                "labels": [a["label"] for a in self.attractors],
                "diverged": -1,
                "failed": -2,
                "phase": self.phase,
            },
        )


def _xarray():
    try:
        import xarray as xr
    except ImportError:
        raise ImportError("to_xarray needs xarray: pip install xarray") from None
    return xr


class ContinuationResult(Result):
    """Result of :func:`continuation`.

    Attributes
    ----------
    points : dict of ndarray
        One entry per attractor and value (continuation.csv): ``value``, ``branch`` (int64),
        ``label``, ``period`` (int64), ``healthy`` (bool), ``fraction``, ``max_force``, ``x``,
        ``v`` (first stroboscopic point).
    events : list of dict
        ``from``, ``to``, ``kind``, ``branches``, ``text`` between consecutive values.
    intervals : list of dict
        Parameter intervals with the same attractor set.
    lost : ndarray, float64, shape (n, 2)
        ``value, fraction`` of divergent or failed initial states.
    """

    _fields = ("points", "events", "intervals", "lost", "param", "values", "settings", "config")
    _main_table = "points"


class OrbitsResult(Result):
    """Result of :func:`orbits`.

    Attributes
    ----------
    branch : dict of ndarray
        One row per orbit (branch.csv): the continued parameter under its own name (absent for
        one orbit), ``branch`` (int64), ``x``, ``v`` (the orbit's point at the stroboscopic
        phase), ``period`` (int64), ``label``, ``stable`` (bool), the Floquet multipliers
        ``mu1_re, mu1_im, mu2_re, mu2_im`` (largest modulus first), ``max_force``, ``p_id``.
    bifurcations : dict of ndarray
        (bifurcations.csv) ``kind`` (``period-doubling``, ``fold``, ``torus``, ``grazing``), the
        parameter, ``branch``, ``x``, ``v``, ``period`` and the multipliers; empty for one orbit.
    ends : list of str
        Why each branch ended.
    """

    _fields = ("branch", "bifurcations", "ends", "config")
    _main_table = "branch"


class SignalsResult(Result):
    """Result of :func:`signals`.

    Attributes
    ----------
    signals : dict of ndarray
        One row per sample of each pair, healthy twin first (signals.csv): ``pair``
        (``healthy``, ``broken``), ``tau`` (dimensionless time; seconds: ``tau / omega_n``),
        ``dte_um`` (dynamic transmission error, µm), ``mesh_force_N`` (N),
        ``acceleration_m_s2`` (relative acceleration on the line of action, m/s²).
    spectrum : dict of ndarray
        Welch amplitude spectra (spectrum.csv): ``pair``, ``signal``, ``order`` (cycles per
        pinion revolution; the mesh order is ``z1``), ``amplitude`` (unit of the signal).
    indicators : dict of ndarray
        (indicators.csv) ``pair``, ``signal``, ``indicator``, ``value``.
    tsa : dict of ndarray
        Time-synchronous averages (tsa.csv): ``pair``, ``angle_deg`` and the three signals.
    lines : dict of ndarray
        Labelled integer orders of the TSA (lines.csv): ``pair``, ``signal``, ``order``,
        ``label`` (``mesh1``, ``mesh1-1``, ...), ``amplitude``.
    info : dict
        signals.json: the request, the scales, each pair's motion (label, class, impacts), whether
        both pairs are on the same attractor class (``comparable``), notes, the removed orders.
    """

    _fields = ("signals", "spectrum", "indicators", "tsa", "lines", "info", "config")
    _main_table = "indicators"


class MapResult(Result):
    """Result of :func:`map2d`.

    Attributes
    ----------
    values : ndarray, float64, shape (n_y, n_x)
        The metric on the grid (as map.npy; NaN where a cell failed).
    x, y : ndarray, float64
        The axes' values.
    cells : dict of ndarray
        Every cell, row-major with ``y`` rows, with the columns of the CLI's map.csv: the two
        parameters under their own names (``x_param``, ``y_param``), then ``label, period,
        healthy, max_force, min_force, p_id, impacts, tle, class``.
    """

    _fields = ("values", "metric", "x_param", "x", "y_param", "y", "cells", "settings", "config")
    _main_table = "cells"

    def to_xarray(self):
        """The map as an ``xarray.Dataset`` over two dimensions named after the swept parameters
        (``y_param`` by ``x_param``, as ``values``): one variable per numeric column of ``cells``
        (``max_force``, ``p_id``, ``period``, ...) and ``label`` and ``class`` as strings; xarray
        must be installed. The map's metric is ``attrs["metric"]``."""
        xr = _xarray()
        dims = (self.y_param, self.x_param)
        shape = (len(self.y), len(self.x))
        data = {
            k: (dims, np.asarray(v).reshape(shape))
            for k, v in self.cells.items()
            if k not in (self.x_param, self.y_param)
        }
        return xr.Dataset(
            data,
            coords={self.y_param: self.y, self.x_param: self.x},
            attrs={"metric": self.metric},
        )


class StiffnessResult(Result):
    """Result of :func:`stiffness`.

    Attributes
    ----------
    table : dict of ndarray
        The columns of stiffness.csv. With a physical pair: ``position_cycles``,
        ``k_pair1_N_per_m``, ``k_pair2_N_per_m``, ``k_mesh_N_per_m``, ``share1``, ``share2``,
        ``h_drive``, ``h_back``, ``half_backlash``, ``zone``, ``mu1``, ``mu2``, ``film1_um``,
        ``lambda1``, ``regime1``; without one: ``position_cycles``, ``k_dimensionless``,
        ``h_drive``, ``h_back``, ``half_backlash``.
    pair : dict or None
        ``eps``, ``eps_b``, ``k_av_n_per_m``, ``omega_n_rad_per_s``, ``cycles``,
        ``samples_per_cycle`` of the pair.
    """

    _fields = ("table", "pair", "config")
    _main_table = "table"


# --------------------------------------------------------------------------- functions


def presets():
    """The built-in presets.

    Returns
    -------
    dict
        ``{name: description}`` (``geardyn presets``).
    """
    return dict(_geardyn.presets())


def parameter_names():
    """Names accepted as keyword parameters and in ``set`` (besides ``pair.*`` fields).

    Returns
    -------
    list of str
    """
    return list(_geardyn.parameter_names())


def config(preset=None, config=None, *, set=None, as_toml=False, **params):
    """The resolved, validated configuration (what ``geardyn show`` prints as TOML).

    Parameters
    ----------
    preset, config, set, **params
        Where the configuration comes from (see the module documentation).
    as_toml : bool
        Return the TOML text instead (ready to save and pass back as ``config=path``, or to the
        CLI's ``--config``).

    Returns
    -------
    dict or str
        Tables ``model``, ``pair`` (if any), ``set`` (if any), ``simulation``; pass the dict back
        as ``config=`` to any function, or edit it first.

    Examples
    --------
    >>> cfg = geardyn.config(preset="classic", omega=1.3)
    >>> cfg["model"]["omega"]
    1.3
    """
    return _geardyn.config(_source(preset, config, set, params), bool(as_toml))


def derived(preset=None, config=None, *, set=None, **params):
    """Derived quantities of a configuration (the comment lines of ``geardyn show``).

    Returns
    -------
    dict
        ``parameters`` (the integrated dimensionless values and the overrides applied),
        ``excitation_period``, ``cycles_per_period``, ``mesh_cycle_time``, ``backlash_levels``
        ``(D_d, D_s)``, ``pair`` (contact ratios, ``k_av``, ``m_e``, ``omega_n``, ``b_c``, the
        physical operating point of the integrated values; None without a pair) and ``text``
        (the lines ``show`` prints).
    """
    return _geardyn.derived(_source(preset, config, set, params))


def simulate(
    preset=None,
    config=None,
    *,
    transient=None,
    periods=None,
    integrator=None,
    trajectory_periods=_D["simulate"]["trajectory_periods"],
    set=None,
    progress=False,
    out=None,
    **params,
):
    """Integrate the model and classify the motion (``geardyn simulate``).

    Parameters
    ----------
    preset, config, set, **params
        Where the configuration comes from (see the module documentation), e.g. ``omega=0.8``.
    transient : int, optional
        Excitation periods discarded first (default ``simulation.transient_periods``, 300).
    periods : int, optional
        Excitation periods recorded (default ``simulation.record_periods``, 100).
    integrator : {"dopri", "rk4"}, optional
        Default ``simulation.method``.
    trajectory_periods : int or None
        Recorded excitation periods (the last ones) kept in ``trajectory``; None keeps all.
    progress : bool
        Print the elapsed time on ``sys.stderr``.
    out : str or os.PathLike, optional
        Also write the folder the CLI writes there (config.toml, trajectory.csv, strobe.csv,
        events.csv, sections.csv, summary.json, the figures, run.json), with its rules: a new or
        empty folder or one geardyn made, locked while the run writes (another run's folder is
        refused at once, before any work).

    Returns
    -------
    SimulationResult
        ``strobe``, ``trajectory``, ``events``, ``sections``, ``summary`` (as summary.json), ...

    Examples
    --------
    >>> r = geardyn.simulate(preset="classic", omega=0.8)
    >>> r.summary["period"], r.strobe.shape
    (1, (100, 3))
    """
    if trajectory_periods is not None:
        trajectory_periods = _count("trajectory_periods", trajectory_periods)
    d = _geardyn.simulate(
        _source(preset, config, set, params),
        _opt_float("periods", periods),
        _opt_float("transient", transient),
        integrator,
        trajectory_periods,
        bool(progress),
        None if out is None else os.fspath(out),
    )
    d["events"] = _table(d["events"])
    d["sections"] = _table(d["sections"])
    if d["summary"]["motion"].get("class") == "diverged":
        # the CLI writes the files, then ends with this message as an error
        warnings.warn(d["description"], RuntimeWarning, stacklevel=2)
    return SimulationResult(**d)


def lyapunov(
    preset=None,
    config=None,
    *,
    method=_D["lyapunov"]["method"],
    periods=None,
    transient=None,
    integrator=None,
    steps_per_cycle=None,
    max_periods=_D["lyapunov"]["max_periods"],
    d0=_D["lyapunov"]["d0"],
    set=None,
    progress=False,
    **params,
):
    """Top Lyapunov exponent (``geardyn lyapunov``).

    Without ``periods`` the variational run doubles its length (from 200 excitation periods, at
    most ``max_periods``) until ``|TLE(N) - TLE(N/2)|`` and the standard error are below the
    tolerance; with ``periods`` it runs exactly that long.

    Parameters
    ----------
    preset, config, set, **params
        Where the configuration comes from (see the module documentation).
    method : {"both", "variational", "two-trajectory"}
        Variational with saltation matrices, two nearby trajectories, or both.
    periods, transient : int, optional
        Measured and discarded excitation periods.
    integrator : {"dopri", "rk4"}, optional
    steps_per_cycle : int, optional
        RK4 steps per mesh cycle.
    max_periods : int
        Largest run length while converging (at least 20, at most the longest run geardyn
        accepts; a value outside is refused with the allowed range).
    d0 : float
        Initial distance of the two-trajectory method, in (0, 0.01).

    Returns
    -------
    LyapunovResult
        ``value``, ``stderr``, ``method``, ``converged``, ``rounds``, ``history``, ...
    """
    d = _geardyn.lyapunov(
        _source(preset, config, set, params),
        _sim(periods, transient, integrator, steps_per_cycle),
        str(method),
        _count("max_periods", max_periods),
        float(d0),
        bool(progress),
    )
    var, two = d["variational"], d["two_trajectory"]
    for r in (var, two):
        if r is not None:
            r["history"] = np.asarray(r["history"], dtype=np.float64)
    main = two if d["method"] == "two-trajectory" else var
    rounds = d["rounds"]
    if rounds is not None:
        rounds = {
            "periods": np.asarray([r["periods"] for r in rounds], dtype=np.int64),
            "tle": np.asarray([r["tle"] for r in rounds], dtype=np.float64),
            "half": np.asarray([r["half"] for r in rounds], dtype=np.float64),
            "stderr": np.asarray([r["stderr"] for r in rounds], dtype=np.float64),
        }

    def num(x):
        return float("nan") if x is None else float(x)

    return LyapunovResult(
        value=num(main["tle"]),
        stderr=num(main["spread"]),
        method=d["method"],
        periods=d["periods"],
        converged=d["converged"],
        tol=d["tol"],
        rounds=rounds,
        history=main["history"],
        annihilated=main["annihilated"],
        variational=var,
        two_trajectory=two,
        integrated=d["integrated"],
        d0=d["d0"],
        config=d["config"],
    )


class _Partial:
    """Turns the raw partial result of an interrupted call (``KeyboardInterrupt.partial``) into
    the call's result type."""

    def __init__(self, wrap):
        self.wrap = wrap

    def __enter__(self):
        return self

    def __exit__(self, et, e, tb):
        if et is not None and issubclass(et, KeyboardInterrupt):
            if getattr(e, "partial", None) is not None:
                e.partial = self.wrap(e.partial)
        return False


def _sweep_partial(param):
    """The partial result of an interrupted sweep as a :class:`SweepResult` (its finished values;
    ``values``, ``settings`` and ``config`` are ``None``)."""
    return lambda p: _sweep_result({"param": param, "values": None, "settings": None, "config": None, **p})


def _sweep_result(d):
    d["points"] = _table(d["points"])
    d["runs"] = _table(d["runs"])
    d["impact_force"] = _table(d["impact_force"])
    r = SweepResult(**d)
    if "jumps" in d:
        r._fields = SweepResult._fields + ("jumps",)
    return r


def bifurcation(
    preset=None,
    config=None,
    *,
    param=_D["bifurcation"]["param"],
    values=None,
    range=None,
    mode=_D["bifurcation"]["mode"],
    ics=_D["bifurcation"]["ics"],
    seed=_D["bifurcation"]["seed"],
    x0_range=None,
    v0_range=None,
    sections=("strobe",),
    lyapunov=False,
    periods=None,
    transient=None,
    integrator=None,
    steps_per_cycle=None,
    set=None,
    progress=False,
    out=None,
    **params,
):
    """Bifurcation diagram over a parameter (``geardyn bifurcation``).

    Parameters
    ----------
    preset, config, set, **params
        Where the configuration comes from (see the module documentation).
    param : str
        Swept parameter: any parameter name, or a ``pair.*`` field.
    values : array_like, optional
        Parameter values, in order.
    range : (start, stop, count), optional
        Instead of ``values``: ``count`` equally spaced values (the CLI's ``--range``; default
        ``(0.5, 2, 200)``).
    mode : {"fixed", "sweep", "multi"}
        Same initial state for every value, continuation up and down, or ``ics`` seeded initial
        states per value.
    ics, seed : int
        Initial states per value and their seed (multi).
    x0_range, v0_range : (min, max)
        Box of the initial states (multi); by default the attractor region ``x0 ∈ ±(D + 3 l)``,
        ``v0 ∈ ±3 l`` (``D`` the largest half backlash, ``l = max(D, 1)``), as the CLI.
    sections : str or sequence of str
        From ``strobe``, ``ds_up``, ``ds_down``, ``dd_up``, ``dd_down``, ``impact``.
    lyapunov : bool
        Also compute the TLE of every run.
    periods, transient, integrator, steps_per_cycle
        Integration settings of every run.
    progress : bool
        Print progress on ``sys.stderr``.
    out : str or os.PathLike, optional
        Also write the folder ``geardyn bifurcation --out`` writes there (config.toml, run.json,
        checkpoint.jsonl, bifurcation.csv, runs.csv, impact_force.csv, the figures), with its
        rules: a new or empty folder or one geardyn made, locked while the sweep runs. Every
        finished value is kept in its checkpoint as it finishes, so a sweep that was interrupted
        (Ctrl-C, a killed process) resumes there: the same call (or the same CLI command) with
        the same ``out`` computes only the values that had not finished. Other settings in the
        same folder are refused, naming the folder.

    Returns
    -------
    SweepResult
        ``points`` (value, branch, ic, section, x, v, label) and ``runs``.
    """
    vals, rng = _values(values, range, (0.5, 2.0, 200))
    if isinstance(sections, str):
        sections = sections.split(",")
    with _Partial(_sweep_partial(param)):
        d = _geardyn.bifurcation(
            _source(preset, config, set, params),
            _sim(periods, transient, integrator, steps_per_cycle),
            str(param),
            vals,
            rng,
            str(mode),
            _count("ics", ics),
            _count("seed", seed),
            _pair("x0_range", x0_range),
            _pair("v0_range", v0_range),
            [str(s) for s in sections],
            bool(lyapunov),
            bool(progress),
            None if out is None else os.fspath(out),
        )
    return _sweep_result(d)


def response(
    preset=None,
    config=None,
    *,
    param=_D["bifurcation"]["param"],
    values=None,
    range=None,
    periods=None,
    transient=None,
    integrator=None,
    steps_per_cycle=None,
    set=None,
    progress=False,
    **params,
):
    """Frequency response: continuation up and down, amplitudes and jumps (``geardyn response``).

    Parameters
    ----------
    param, values, range
        As :func:`bifurcation` (default range ``(0.5, 2, 150)``).

    Returns
    -------
    SweepResult
        ``runs`` holds the amplitudes of both branches (``branch`` ``up``/``down``); ``jumps``
        the jumps (jumps.json).
    """
    vals, rng = _values(values, range, (0.5, 2.0, 150))
    with _Partial(_sweep_partial(param)):
        d = _geardyn.response(
            _source(preset, config, set, params),
            _sim(periods, transient, integrator, steps_per_cycle),
            str(param),
            vals,
            rng,
            bool(progress),
        )
    return _sweep_result(d)


def basins(
    preset=None,
    config=None,
    *,
    x=None,
    v=None,
    phase=0.0,
    capture_tol=_D["identify"]["capture_tol"],
    early_stop=_D["identify"]["early_stop"],
    ident_rtol=_D["identify"]["ident_rtol"],
    periods=None,
    transient=None,
    integrator=None,
    steps_per_cycle=None,
    set=None,
    progress=False,
    **params,
):
    """Basins of attraction on a grid of initial states (``geardyn basins``, without the files).

    Parameters
    ----------
    preset, config, set, **params
        Where the configuration comes from (see the module documentation).
    x : (min, max, n), optional
        Displacement axis; default ``(-2 D_s, 2 D_s, 200)``.
    v : (min, max, n), optional
        Velocity axis; default ``(-1.5, 1.5, 200)``.
    phase : float
        Phase of the initial states as a fraction of the excitation period, in [0, 1).
    capture_tol : float
        Early-capture tolerance (state units); matching uses ten times it.
    early_stop : bool
        Stop a cell early on a known attractor (the CLI's default; ``--no-early-stop`` is
        ``early_stop=False``).
    ident_rtol : float
        Relative tolerance of the adaptive integrator during identification.
    periods, transient, integrator, steps_per_cycle
        Integration settings (``transient`` is the most before recording a new attractor).
    progress : bool
        Print progress (cells done) on ``sys.stderr``.

    Returns
    -------
    BasinsResult
        ``cells`` (int64, n_v x n_x), ``x``, ``v``, ``attractors``, ...
    """
    d = _geardyn.basins(
        _source(preset, config, set, params),
        _sim(periods, transient, integrator, steps_per_cycle),
        _ident(capture_tol, early_stop, ident_rtol),
        _triple("x", x),
        _triple("v", v),
        float(phase),
        bool(progress),
    )
    atts = []
    for a in d["attractors"]:
        desc = a["descriptor"]
        atts.append(
            {
                "id": a["id"],
                "label": desc["label"],
                "period": desc["period"],
                "healthy": desc["healthy"],
                "fraction": a["fraction"],
                "cells": a["cells"],
                "points": np.asarray(desc["points"], dtype=np.float64).reshape(-1, 2),
                "bbox": desc["bbox"],
                "max_force": desc["max_force"],
                "p_id": desc["p_id"],
            }
        )
    d["attractors"] = atts
    for k in ("x_axis", "v_axis", "elapsed_s"):
        d.pop(k, None)
    return BasinsResult(**d)


def continuation(
    preset=None,
    config=None,
    *,
    param=_D["bifurcation"]["param"],
    values=None,
    range=None,
    ics=_D["continuation"]["ics"],
    seed=_D["continuation"]["seed"],
    x0_range=None,
    v0_range=None,
    phase=0.0,
    capture_tol=_D["identify"]["capture_tol"],
    early_stop=_D["identify"]["early_stop"],
    ident_rtol=_D["identify"]["ident_rtol"],
    periods=None,
    transient=None,
    integrator=None,
    steps_per_cycle=None,
    set=None,
    progress=False,
    **params,
):
    """Attractor continuation along a parameter (``geardyn continuation``, without the files).

    Parameters
    ----------
    param, values, range
        As :func:`bifurcation` (default range ``(0.5, 2, 61)``).
    ics, seed : int
        Initial states per value (the same set at every value) and their seed.
    x0_range, v0_range : (min, max)
        Box of the initial states; by default the attractor region, as for :func:`bifurcation`.
    phase : float
        Phase of the initial states in ``[0, 1)`` of each value's excitation period (as
        :func:`basins`).
    capture_tol, early_stop, ident_rtol
        As :func:`basins`.

    Returns
    -------
    ContinuationResult
        ``points`` (value, branch, label, period, healthy, fraction, ...), ``events``,
        ``intervals``, ``lost``.
    """
    vals, rng = _values(values, range, (0.5, 2.0, 61))
    d = _geardyn.continuation(
        _source(preset, config, set, params),
        _sim(periods, transient, integrator, steps_per_cycle),
        _ident(capture_tol, early_stop, ident_rtol),
        str(param),
        vals,
        rng,
        _count("ics", ics),
        _count("seed", seed),
        _pair("x0_range", x0_range),
        _pair("v0_range", v0_range),
        float(phase),
        bool(progress),
    )
    d["points"] = _table(d["points"])
    return ContinuationResult(**d)


def orbits(
    preset=None,
    config=None,
    *,
    param=None,
    range=None,
    period=None,
    transient=_D["orbits"]["transient"],
    ds=_D["orbits"]["ds"],
    max_points=_D["orbits"]["max_points"],
    switch_up_to=_D["orbits"]["switch_up_to"],
    rtol=_D["orbits"]["rtol"],
    set=None,
    progress=False,
    **params,
):
    """Periodic orbits by shooting (``geardyn orbits``, without the files).

    Without ``param``: one orbit near the motion after ``transient`` periods from the initial
    state (``x0``, ``v0``), with its Floquet multipliers. With ``param`` and ``range=(start,
    stop)``: its branch (stable and unstable orbits, by pseudo-arclength continuation) and the
    bifurcations on it (period doubling, fold, torus, grazing, corner collision, and any other
    change of stability as ``stability-change``).

    Parameters
    ----------
    param : str, optional
        Parameter continued (``omega``, ``F``, ``xi``, ``c``, ``kappa``, ``pair.mu``, ...).
    range : (start, stop), optional
        The first orbit is found at ``start``.
    period : int, optional
        Excitation periods of the orbit; default: the period of the motion after the transient.
    transient : int
        Periods simulated before Newton's method starts.
    ds, max_points, switch_up_to, rtol
        Largest arclength step, most branch points, branch switching at doublings up to this
        period (0: none), relative tolerance of the integration.

    Returns
    -------
    OrbitsResult
        ``branch`` and ``bifurcations`` (the CLI's columns), ``ends``.
    """
    if (param is None) != (range is None):
        raise ValueError("param and range go together: param=NAME, range=(START, STOP)")
    start = stop = None
    if range is not None:
        start, stop = _pair("range", range)
    d = _geardyn.orbits(
        _source(preset, config, set, params),
        None if param is None else str(param),
        start,
        stop,
        None if period is None else _count("period", period, 1),
        _count("transient", transient),
        _opt_float("ds", ds),
        _count("max_points", max_points, 1),
        _count("switch_up_to", switch_up_to),
        _opt_float("rtol", rtol),
        bool(progress),
    )
    d["branch"] = _table(d["branch"])
    d["bifurcations"] = _table(d["bifurcations"])
    return OrbitsResult(**d)


def signals(
    preset=None,
    config=None,
    *,
    revolutions=_D["signals"]["revolutions"],
    transient=_D["signals"]["transient"],
    samples_per_cycle=_D["signals"]["samples_per_cycle"],
    segment_revolutions=_D["signals"]["segment_revolutions"],
    sidebands=_D["signals"]["sidebands"],
    shaft_orders=_D["signals"]["shaft_orders"],
    residual=_D["signals"]["residual"],
    na4_reference=_D["signals"]["na4_reference"],
    set=None,
    progress=False,
    **params,
):
    """Vibration signals of a broken pair and its healthy twin (``geardyn signals``, without the
    files); default preset ``breakage``.

    Both pairs start from the same initial state (``x0``, ``v0``, ``tau0``) at the same operating
    point; ``transient`` pinion revolutions are discarded and ``revolutions`` recorded with
    ``samples_per_cycle`` samples per mesh cycle. When the two settle on attractors of different
    classes, the healthy twin is recorded again from the broken pair's final state
    (``info["result"]["notes"]`` says what was done). A pair without breakage gives the healthy
    pair alone; a configuration without a physical ``[pair]`` is refused.

    Parameters
    ----------
    revolutions, transient, samples_per_cycle, segment_revolutions : int
        Recorded and discarded revolutions, samples per mesh cycle, revolutions per Welch
        segment.
    sidebands, shaft_orders : int
        Shaft sidebands of each mesh harmonic and shaft orders removed from the difference signal.
    residual : str
        ``"mesh_and_shaft"`` (Lebold et al. 2000) or ``"mesh"`` (mesh harmonics only).
    na4_reference : str
        ``"run"`` (NA4/NB4 variance averaged over the run healthy -> broken) or ``"own"``.

    Returns
    -------
    SignalsResult
    """
    if preset is None and config is None:
        preset = "breakage"
    d = _geardyn.signals(
        _source(preset, config, set, params),
        _count("revolutions", revolutions),
        _count("transient", transient),
        _count("samples_per_cycle", samples_per_cycle),
        _count("segment_revolutions", segment_revolutions),
        _count("sidebands", sidebands),
        _count("shaft_orders", shaft_orders),
        str(residual),
        str(na4_reference),
        bool(progress),
    )
    for k in ("signals", "spectrum", "indicators", "tsa", "lines"):
        d[k] = _table(d[k])
    return SignalsResult(**d)


def _signal_array(name, a):
    try:
        x = np.asarray(a, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: an array of numbers") from None
    if x.ndim != 1:
        raise ValueError(f"bad {name}: a one-dimensional array is needed, not shape {x.shape}")
    return x.tolist()


def indicators(
    array,
    *,
    samples_per_rev,
    mesh_order,
    sidebands=_D["signals"]["sidebands"],
    shaft_orders=_D["signals"]["shaft_orders"],
    residual=_D["signals"]["residual"],
    run=None,
):
    """Gear condition indicators of one signal sampled synchronously with the pinion.

    ``array`` holds whole revolutions of ``samples_per_rev`` samples each (a multiple of it);
    ``mesh_order`` is the pinion's tooth number (the mesh order). ``rms``, ``peak_to_peak``,
    ``crest_factor`` and ``kurtosis`` are of the samples as given; ``fm0``, ``fm4``, ``m6a``,
    ``m8a``, ``na4``, ``nb4``, ``er``, ``sideband_index``, ``sideband_level_factor`` of their
    time-synchronous average (definitions and sources: docs/analyses.md, "Fault signatures").
    ``run``: earlier records of the same run (each as long as ``array``), whose residual and
    envelope variances NA4 and NB4 average with this one's; default: this record alone.

    Returns
    -------
    dict
        Indicator name -> float.

    Raises
    ------
    ValueError
        NaN or infinite samples, an array shorter than a revolution, ``samples_per_rev`` not
        dividing its length, ``mesh_order`` outside the range the sampling allows (the message
        names the argument and the range).
    """
    x = _signal_array("array", array)
    runs = [] if run is None else [_signal_array(f"run[{i}]", r) for i, r in enumerate(run)]
    return _geardyn.indicators(
        x,
        _count("samples_per_rev", samples_per_rev),
        _count("mesh_order", mesh_order, lo=-_COUNT_MAX),
        _count("sidebands", sidebands),
        _count("shaft_orders", shaft_orders),
        str(residual),
        runs,
    )


def _axis(name, a):
    """``(param, start, stop, count)`` or ``(param, values)``."""
    if not isinstance(a, (tuple, list)) or len(a) not in (2, 4) or not isinstance(a[0], str):
        raise TypeError(f"{name}: (param, start, stop, count) or (param, values)")
    if len(a) == 4:
        return a[0], None, _triple(name, a[1:])
    return a[0], np.asarray(a[1], dtype=np.float64).ravel().tolist(), None


def map2d(
    preset=None,
    config=None,
    *,
    x=("xi", 0.001, 0.3, 40),
    y=("F", 0.001, 0.2, 40),
    metric=_D["map2d"]["metric"],
    periods=None,
    transient=None,
    integrator=None,
    steps_per_cycle=None,
    set=None,
    progress=False,
    out=None,
    **params,
):
    """Two-parameter map of a response (``geardyn map2d``).

    Parameters
    ----------
    x, y : (param, start, stop, count) or (param, values)
        The axes (defaults as the CLI: ``xi`` 0.001..0.3 and ``F`` 0.001..0.2, 40 values each).
    metric : str
        ``max_force``, ``min_force``, ``p_id``, ``period``, ``tle``, ``healthy`` or ``class``
        (0 healthy periodic, 1 non-healthy periodic, 2 chaotic, 3 failed, 4 quasi-periodic,
        5 unsettled).
    out : str or os.PathLike, optional
        Also write the folder ``geardyn map2d --out`` writes there (config.toml, run.json,
        checkpoint.jsonl, map.csv, map.npy, the heatmap), with its rules; every finished cell is
        kept in the checkpoint, so an interrupted map resumes there (the same call, or the same
        CLI command, with the same ``out`` computes only the missing cells).

    Returns
    -------
    MapResult
        ``values`` (float64, n_y x n_x, as map.npy), ``x``, ``y``, ``cells``.
    """
    xp, xv, xr = _axis("x", x)
    yp, yv, yr = _axis("y", y)
    d = _geardyn.map2d(
        _source(preset, config, set, params),
        _sim(periods, transient, integrator, steps_per_cycle),
        xp,
        xv,
        xr,
        yp,
        yv,
        yr,
        str(metric),
        bool(progress),
        None if out is None else os.fspath(out),
    )
    d["cells"] = _table(d["cells"])
    return MapResult(**d)


def stiffness(preset=None, config=None, *, set=None, **params):
    """Mesh stiffness, load shares, friction factors and backlash over the excitation period
    (``geardyn stiffness``, without the files).

    Returns
    -------
    StiffnessResult
        ``table`` (the columns of stiffness.csv) and ``pair``.
    """
    d = _geardyn.stiffness(_source(preset, config, set, params))
    d["table"] = _table(d["table"])
    return StiffnessResult(**d)


_ERRORS = {"ValueError": ValueError, "OSError": OSError, "RuntimeError": RuntimeError}


def report(preset="breakage", out="out/report", *, quick=False, set=None, progress=False, **params):
    """Run a preset's study plan and write the HTML report (``geardyn report``).

    The page goes to ``OUT/<preset>/index.html`` with its figures and tables; studies are cached
    and checkpointed in the folder, so rerunning the same call resumes. The report runs in a
    child process of this interpreter (same library), so Ctrl-C stops it at once; the page
    itself is written last, and a rerun continues where it stopped.

    Parameters
    ----------
    preset : {"breakage", "internal", "classic"}
    out : str or os.PathLike
        Output directory.
    quick : bool
        Coarse version of every figure.
    set, **params
        Overrides of the preset, e.g. ``F=0.12``; also ``decision_periods=``,
        ``decision_budget=`` and ``follow_steps=`` (the horizon and budget of the chaos verdicts:
        by default the full report's 10 000 periods and the quick report's 1000).
    progress : bool
        Let the report print its progress on stderr.

    Returns
    -------
    pathlib.Path
        The page, ``OUT/<preset>/index.html``.
    """
    src = _source(preset, None, set, params)
    if src["contact"] is not None:
        raise ValueError(
            "report: contact is not an option (each study sets its own contact law; "
            "the seed B studies use the linear law and show the preset's beside it)"
        )
    payload = json.dumps(
        {"preset": preset, "sets": src["sets"], "quick": bool(quick), "out": os.fspath(out)}
    )
    env = dict(os.environ)
    here = str(Path(__file__).resolve().parent.parent)
    env["PYTHONPATH"] = here + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    proc = subprocess.Popen(
        [sys.executable, "-m", "geardyn._report_child", payload],
        stdout=subprocess.PIPE,
        stderr=None if progress else subprocess.DEVNULL,
        stdin=subprocess.DEVNULL,
        env=env,
    )
    try:
        while True:
            # short waits, so that Ctrl-C is seen even when no signal interrupts the wait
            try:
                stdout, _ = proc.communicate(timeout=0.2)
                break
            except subprocess.TimeoutExpired:
                continue
    except BaseException:
        proc.kill()
        proc.wait()
        raise
    lines = stdout.decode("utf-8", "replace").strip().splitlines()
    try:
        answer = json.loads(lines[-1])
    except (IndexError, ValueError):
        raise RuntimeError(f"the report process ended without an answer (exit code {proc.returncode})") from None
    if "error" in answer:
        raise _ERRORS.get(answer["error"], RuntimeError)(answer["message"])
    return Path(answer["index"])
