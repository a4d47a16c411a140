"""Typed requests: one class per analysis, holding its fields with the library's defaults, and
one way to run them, :func:`run` (or the request's own :meth:`Request.run`).

A request is a plain dataclass: build it, print it, change it (``dataclasses.replace(req,
mode="multi")``; the model parameters are in ``params``: ``params={"omega": 1.2}``), keep it.
Nothing is checked when it is built: the Rust half checks it once, when it runs, with the CLI's
messages (a bad field is named in the ``ValueError``); only the types are checked on the way
there (``TypeError``).

>>> req = geardyn.BifurcationRequest(preset="classic", range=(0.5, 2, 50), mode="sweep")
>>> res = geardyn.run(req, progress=True)        # or req.run(); a SweepResult
>>> geardyn.bifurcation(preset="classic", range=(0.5, 2, 50), mode="sweep")  # the same
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass, field
from typing import Any, ClassVar, Dict, Mapping, Optional, Sequence, Tuple, Union

from . import _geardyn
from . import _results as R
from ._convert import (
    _D,
    _axis,
    _count,
    _ident,
    _opt_float,
    _pair,
    _sim,
    _source,
    _triple,
    _values,
)

__all__ = [
    "Request",
    "SimulateRequest",
    "LyapunovRequest",
    "BifurcationRequest",
    "ResponseRequest",
    "BasinsRequest",
    "ContinuationRequest",
    "OrbitsRequest",
    "SignalsRequest",
    "MapRequest",
    "run",
]

Triple = Tuple[float, float, int]
Pair = Tuple[float, float]


@dataclass
class Request:
    """Base of the requests: where the configuration comes from.

    Attributes
    ----------
    preset : str, optional
        Built-in preset (default ``"classic"``; ``"breakage"`` for :class:`SignalsRequest`).
    config : str, os.PathLike or dict, optional
        A TOML file or a dict from :func:`geardyn.config`; excludes ``preset``.
    set : dict, optional
        Overrides ``{name: value}`` applied in order (``--set NAME=VALUE``).
    params : dict
        Overrides by name applied after ``set`` (the ``**params`` of the keyword functions:
        ``{"omega": 0.8, "F": 0.1}``).
    contact : str, optional
        The contact law of both flanks, ``LAW[:EXPONENT[:RESTITUTION]]`` (``--contact``).
    """

    preset: Optional[str] = None
    config: Any = None
    set: Optional[Mapping[str, Any]] = None
    params: Dict[str, Any] = field(default_factory=dict)
    contact: Optional[str] = None

    #: the analysis' name (the CLI's command)
    kind: ClassVar[str] = ""
    #: whether ``out=`` writes the CLI's folder
    takes_out: ClassVar[bool] = False

    def run(self, out=None, progress=False):
        """Runs the request: :func:`run` ``(self, out=out, progress=progress)``."""
        return _execute(self, out, progress)

    def _src(self):
        params = dict(self.params)
        if self.contact is not None:
            params["contact"] = self.contact
        return _source(self.preset, self.config, self.set, params)

    def _payload(self):
        raise NotImplementedError

    def _result(self, d):
        raise NotImplementedError


@dataclass
class _Sim(Request):
    """A request with the integration settings of every run (``None``: the configuration's)."""

    periods: Optional[float] = None
    transient: Optional[float] = None
    integrator: Optional[str] = None
    steps_per_cycle: Optional[float] = None

    def _sim(self):
        return _sim(self.periods, self.transient, self.integrator, self.steps_per_cycle)


@dataclass
class SimulateRequest(Request):
    """One simulation (``geardyn simulate``); fields as the keywords of :func:`geardyn.simulate`."""

    transient: Optional[float] = None
    periods: Optional[float] = None
    integrator: Optional[str] = None
    trajectory_periods: Optional[int] = _D["simulate"]["trajectory_periods"]

    kind: ClassVar[str] = "simulate"
    takes_out: ClassVar[bool] = True

    def _payload(self):
        tp = self.trajectory_periods
        if tp is not None:
            tp = _count("trajectory_periods", tp)
        return {
            "src": self._src(),
            "periods": _opt_float("periods", self.periods),
            "transient": _opt_float("transient", self.transient),
            "integrator": self.integrator,
            "trajectory_periods": tp,
        }

    def _result(self, d):
        return R._simulation_result(d, stacklevel=4)


@dataclass
class LyapunovRequest(_Sim):
    """The top Lyapunov exponent (``geardyn lyapunov``); fields as the keywords of
    :func:`geardyn.lyapunov`."""

    method: str = _D["lyapunov"]["method"]
    max_periods: int = _D["lyapunov"]["max_periods"]
    d0: float = _D["lyapunov"]["d0"]

    kind: ClassVar[str] = "lyapunov"

    def _payload(self):
        return {
            "src": self._src(),
            "sim": self._sim(),
            "method": str(self.method),
            "max_periods": _count("max_periods", self.max_periods),
            "d0": float(self.d0),
        }

    def _result(self, d):
        return R._lyapunov_result(d)


@dataclass
class BifurcationRequest(_Sim):
    """A bifurcation diagram (``geardyn bifurcation``); fields as the keywords of
    :func:`geardyn.bifurcation` (``values`` and ``range`` both ``None``: ``range=(0.5, 2,
    200)``)."""

    param: str = _D["bifurcation"]["param"]
    values: Optional[Sequence[float]] = None
    range: Optional[Triple] = None
    mode: str = _D["bifurcation"]["mode"]
    ics: int = _D["bifurcation"]["ics"]
    seed: int = _D["bifurcation"]["seed"]
    x0_range: Optional[Pair] = None
    v0_range: Optional[Pair] = None
    sections: Union[str, Sequence[str]] = ("strobe",)
    lyapunov: bool = False

    kind: ClassVar[str] = "bifurcation"
    takes_out: ClassVar[bool] = True
    default_range: ClassVar[Triple] = (0.5, 2.0, 200)

    def _payload(self):
        vals, rng = _values(self.values, self.range, self.default_range)
        sections = self.sections
        if isinstance(sections, str):
            sections = sections.split(",")
        return {
            "src": self._src(),
            "sim": self._sim(),
            "param": str(self.param),
            "values": vals,
            "range": rng,
            "mode": str(self.mode),
            "ics": _count("ics", self.ics),
            "seed": _count("seed", self.seed),
            "x0_range": _pair("x0_range", self.x0_range),
            "v0_range": _pair("v0_range", self.v0_range),
            "sections": [str(s) for s in sections],
            "lyapunov": bool(self.lyapunov),
        }

    def _partial(self):
        return R._sweep_partial(self.param)

    def _result(self, d):
        return R._sweep_result(d)


@dataclass
class ResponseRequest(_Sim):
    """A frequency response (``geardyn response``); fields as the keywords of
    :func:`geardyn.response` (``values`` and ``range`` both ``None``: ``range=(0.5, 2,
    150)``)."""

    param: str = _D["bifurcation"]["param"]
    values: Optional[Sequence[float]] = None
    range: Optional[Triple] = None

    kind: ClassVar[str] = "response"
    default_range: ClassVar[Triple] = (0.5, 2.0, 150)

    def _payload(self):
        vals, rng = _values(self.values, self.range, self.default_range)
        return {
            "src": self._src(),
            "sim": self._sim(),
            "param": str(self.param),
            "values": vals,
            "range": rng,
        }

    def _partial(self):
        return R._sweep_partial(self.param)

    def _result(self, d):
        return R._sweep_result(d)


@dataclass
class _Ident(_Sim):
    """A request that identifies attractors (basins, continuation)."""

    phase: float = 0.0
    capture_tol: float = _D["identify"]["capture_tol"]
    early_stop: bool = _D["identify"]["early_stop"]
    ident_rtol: float = _D["identify"]["ident_rtol"]

    def _ident(self):
        return _ident(self.capture_tol, self.early_stop, self.ident_rtol)


@dataclass
class BasinsRequest(_Ident):
    """Basins of attraction (``geardyn basins``); fields as the keywords of
    :func:`geardyn.basins`."""

    x: Optional[Triple] = None
    v: Optional[Triple] = None

    kind: ClassVar[str] = "basins"

    def _payload(self):
        return {
            "src": self._src(),
            "sim": self._sim(),
            "ident": self._ident(),
            "x": _triple("x", self.x),
            "v": _triple("v", self.v),
            "phase": float(self.phase),
        }

    def _result(self, d):
        return R._basins_result(d)


@dataclass
class ContinuationRequest(_Ident):
    """Attractor continuation (``geardyn continuation``); fields as the keywords of
    :func:`geardyn.continuation` (``values`` and ``range`` both ``None``: ``range=(0.5, 2,
    61)``)."""

    param: str = _D["bifurcation"]["param"]
    values: Optional[Sequence[float]] = None
    range: Optional[Triple] = None
    ics: int = _D["continuation"]["ics"]
    seed: int = _D["continuation"]["seed"]
    x0_range: Optional[Pair] = None
    v0_range: Optional[Pair] = None

    kind: ClassVar[str] = "continuation"
    default_range: ClassVar[Triple] = (0.5, 2.0, 61)

    def _payload(self):
        vals, rng = _values(self.values, self.range, self.default_range)
        return {
            "src": self._src(),
            "sim": self._sim(),
            "ident": self._ident(),
            "param": str(self.param),
            "values": vals,
            "range": rng,
            "ics": _count("ics", self.ics),
            "seed": _count("seed", self.seed),
            "x0_range": _pair("x0_range", self.x0_range),
            "v0_range": _pair("v0_range", self.v0_range),
            "phase": float(self.phase),
        }

    def _result(self, d):
        return R._continuation_result(d)


@dataclass
class OrbitsRequest(Request):
    """Periodic orbits by shooting (``geardyn orbits``); fields as the keywords of
    :func:`geardyn.orbits` (``param`` and ``range=(start, stop)`` go together)."""

    param: Optional[str] = None
    range: Optional[Pair] = None
    period: Optional[int] = None
    transient: int = _D["orbits"]["transient"]
    ds: float = _D["orbits"]["ds"]
    max_points: int = _D["orbits"]["max_points"]
    switch_up_to: int = _D["orbits"]["switch_up_to"]
    rtol: float = _D["orbits"]["rtol"]

    kind: ClassVar[str] = "orbits"

    def _payload(self):
        if (self.param is None) != (self.range is None):
            raise ValueError("param and range go together: param=NAME, range=(START, STOP)")
        start = stop = None
        if self.range is not None:
            start, stop = _pair("range", self.range)
        return {
            "src": self._src(),
            "param": None if self.param is None else str(self.param),
            "start": start,
            "stop": stop,
            "period": None if self.period is None else _count("period", self.period, 1),
            "transient": _count("transient", self.transient),
            "ds": _opt_float("ds", self.ds),
            "max_points": _count("max_points", self.max_points, 1),
            "switch_up_to": _count("switch_up_to", self.switch_up_to),
            "rtol": _opt_float("rtol", self.rtol),
        }

    def _result(self, d):
        return R._orbits_result(d)


@dataclass
class SignalsRequest(Request):
    """Vibration signals of a broken pair and its healthy twin (``geardyn signals``); fields as
    the keywords of :func:`geardyn.signals` (without ``preset`` and ``config``: the preset
    ``breakage``)."""

    revolutions: int = _D["signals"]["revolutions"]
    transient: int = _D["signals"]["transient"]
    samples_per_cycle: int = _D["signals"]["samples_per_cycle"]
    segment_revolutions: int = _D["signals"]["segment_revolutions"]
    sidebands: int = _D["signals"]["sidebands"]
    shaft_orders: int = _D["signals"]["shaft_orders"]
    residual: str = _D["signals"]["residual"]
    na4_reference: str = _D["signals"]["na4_reference"]

    kind: ClassVar[str] = "signals"

    def _src(self):
        if self.preset is None and self.config is None:
            return dataclasses.replace(self, preset="breakage")._src()
        return super()._src()

    def _payload(self):
        return {
            "src": self._src(),
            "revolutions": _count("revolutions", self.revolutions),
            "transient": _count("transient", self.transient),
            "samples_per_cycle": _count("samples_per_cycle", self.samples_per_cycle),
            "segment_revolutions": _count("segment_revolutions", self.segment_revolutions),
            "sidebands": _count("sidebands", self.sidebands),
            "shaft_orders": _count("shaft_orders", self.shaft_orders),
            "residual": str(self.residual),
            "na4_reference": str(self.na4_reference),
        }

    def _result(self, d):
        return R._signals_result(d)


@dataclass
class MapRequest(_Sim):
    """A two-parameter map (``geardyn map2d``); fields as the keywords of :func:`geardyn.map2d`:
    each axis ``(param, start, stop, count)`` or ``(param, values)``."""

    x: Tuple = ("xi", 0.001, 0.3, 40)
    y: Tuple = ("F", 0.001, 0.2, 40)
    metric: str = _D["map2d"]["metric"]

    kind: ClassVar[str] = "map2d"
    takes_out: ClassVar[bool] = True

    def _payload(self):
        xp, xv, xr = _axis("x", self.x)
        yp, yv, yr = _axis("y", self.y)
        return {
            "src": self._src(),
            "sim": self._sim(),
            "x_param": xp,
            "x_values": xv,
            "x_range": xr,
            "y_param": yp,
            "y_values": yv,
            "y_range": yr,
            "metric": str(self.metric),
        }

    def _result(self, d):
        return R._map_result(d)


class _Partial:
    """Turns the raw partial result of an interrupted call (``KeyboardInterrupt.partial``) into
    the call's result type."""

    def __init__(self, wrap):
        self.wrap = wrap

    def __enter__(self):
        return self

    def __exit__(self, et, e, tb):
        if et is not None and issubclass(et, KeyboardInterrupt) and self.wrap is not None:
            if getattr(e, "partial", None) is not None:
                e.partial = self.wrap(e.partial)
        return False


def _execute(request, out, progress):
    if not isinstance(request, Request) or type(request) in (Request, _Sim, _Ident):
        raise TypeError(
            "run: a request of one analysis (geardyn.SimulateRequest, BifurcationRequest, ...), "
            f"not {type(request).__name__}"
        )
    payload = request._payload()
    if out is not None:
        out = os.fspath(out)
    partial = getattr(request, "_partial", None)
    with _Partial(partial() if partial else None):
        d = _geardyn.run(request.kind, payload, bool(progress), out)
    return request._result(d)


def run(request, out=None, progress=False):
    """Runs a typed request (:class:`SimulateRequest`, :class:`BifurcationRequest`, ...).

    Parameters
    ----------
    request : Request
        What to run; checked here, by the library, with the CLI's messages.
    out : str or os.PathLike, optional
        Also write the CLI's folder there (``SimulateRequest``, ``BifurcationRequest``,
        ``MapRequest``; the sweeps resume from it), as the keyword functions' ``out=``.
    progress : bool
        Print progress on ``sys.stderr`` (a tqdm bar when tqdm is installed).

    Returns
    -------
    Result
        The analysis' result (:class:`SimulationResult`, :class:`SweepResult`, ...), exactly as
        the keyword function of the same name returns it; Ctrl-C raises ``KeyboardInterrupt``
        with the finished items in its ``partial``, as there.
    """
    return _execute(request, out, progress)

