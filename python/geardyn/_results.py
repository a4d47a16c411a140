"""The result objects of the analyses (:class:`SimulationResult`, :class:`SweepResult`, ...)
and how each is made from the dict the Rust half returns."""

from __future__ import annotations

import warnings

import numpy as np

from ._convert import _table

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
        basins.npy): index into ``attractors``, -1 divergent, -2 failed, -3 inadmissible (behind
        the rigid back stop of the impact law: not a state of the model, not integrated).
    x, v : ndarray, float64
        Cell centres of the displacement (length n_x) and velocity (length n_v) axes.
    attractors : list of dict
        ``id``, ``label``, ``period``, ``healthy``, ``fraction`` (basin fraction), ``cells``,
        ``points`` (float64 array (k, 2) of stroboscopic points), ``bbox``, ``max_force``,
        ``p_id``. Ids are canonical: healthy first, then by period and position.
    diverged, failed, boundary_fraction : float
        Fractions of the admissible cells (as every ``fraction``).
    inadmissible : float
        Fraction of the grid's cells behind the rigid back stop, left out of every share.
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
        "inadmissible",
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
                "inadmissible": -3,
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




# --------------------------------------------------------------------------- from the Rust dicts


def _simulation_result(d, stacklevel=2):
    d["events"] = _table(d["events"])
    d["sections"] = _table(d["sections"])
    if d["summary"]["motion"].get("class") == "diverged":
        # the CLI writes the files, then ends with this message as an error
        warnings.warn(d["description"], RuntimeWarning, stacklevel=stacklevel + 1)
    return SimulationResult(**d)


def _lyapunov_result(d):
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


def _sweep_result(d):
    d["points"] = _table(d["points"])
    d["runs"] = _table(d["runs"])
    d["impact_force"] = _table(d["impact_force"])
    r = SweepResult(**d)
    if "jumps" in d:
        r._fields = SweepResult._fields + ("jumps",)
    return r


def _sweep_partial(param):
    """The partial result of an interrupted sweep as a :class:`SweepResult` (its finished values;
    ``values``, ``settings`` and ``config`` are ``None``)."""
    return lambda p: _sweep_result({"param": param, "values": None, "settings": None, "config": None, **p})


def _basins_result(d):
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


def _continuation_result(d):
    d["points"] = _table(d["points"])
    return ContinuationResult(**d)


def _orbits_result(d):
    d["branch"] = _table(d["branch"])
    d["bifurcations"] = _table(d["bifurcations"])
    return OrbitsResult(**d)


def _signals_result(d):
    for k in ("signals", "spectrum", "indicators", "tsa", "lines"):
        d[k] = _table(d[k])
    return SignalsResult(**d)


def _map_result(d):
    d["cells"] = _table(d["cells"])
    return MapResult(**d)


def _stiffness_result(d):
    d["table"] = _table(d["table"])
    return StiffnessResult(**d)
