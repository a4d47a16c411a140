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
    ``record_periods``, the decision's horizon, work budget and follow resolution
    ``decision_periods``, ``decision_budget``, ``follow_steps``, and its escape test
    ``escape_copies``, ``escape_periods``); see :func:`parameter_names` and docs/configuration.md.
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

Typed requests
--------------
Every analysis is also a request class holding its fields with the library's defaults
(:class:`SimulateRequest`, :class:`LyapunovRequest`, :class:`BifurcationRequest`,
:class:`ResponseRequest`, :class:`BasinsRequest`, :class:`ContinuationRequest`,
:class:`OrbitsRequest`, :class:`SignalsRequest`, :class:`MapRequest`), run by :func:`run` (or
the request's ``.run()``); the keyword functions build such a request and run it, so both give
the same results and the same errors::

    req = geardyn.BifurcationRequest(preset="classic", range=(0.5, 2, 50), params={"F": 0.1})
    res = geardyn.run(req, out="out/bif", progress=True)   # a SweepResult
"""

from __future__ import annotations

from . import _geardyn
from ._api import (
    basins,
    bifurcation,
    config,
    continuation,
    derived,
    indicators,
    lyapunov,
    map2d,
    orbits,
    parameter_names,
    presets,
    report,
    response,
    signals,
    simulate,
    stiffness,
)
from ._requests import (
    BasinsRequest,
    BifurcationRequest,
    ContinuationRequest,
    LyapunovRequest,
    MapRequest,
    OrbitsRequest,
    Request,
    ResponseRequest,
    SignalsRequest,
    SimulateRequest,
    run,
)
from ._results import (
    BasinsResult,
    ContinuationResult,
    LyapunovResult,
    MapResult,
    OrbitsResult,
    Result,
    SignalsResult,
    SimulationResult,
    StiffnessResult,
    SweepResult,
)

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
    "run",
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
