"""The keyword functions: every analysis of the CLI with keyword arguments (``geardyn.simulate(
preset="classic", omega=0.8)``). Each analysis builds its typed request (``geardyn._requests``)
and runs it; the functions that run no analysis call the Rust half directly."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from . import _geardyn
from . import _requests as Q
from ._convert import _COUNT_MAX, _D, _count, _signal_array, _source
from ._results import _stiffness_result


def _request(cls, preset, config, set_, params, **fields):
    """The request ``cls`` of a keyword call (``contact=`` is among ``**params``)."""
    params = dict(params)
    contact = params.pop("contact", None)
    return cls(preset=preset, config=config, set=set_, params=params, contact=contact, **fields)


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
    return Q._execute(
        _request(
            Q.SimulateRequest, preset, config, set, params,
            transient=transient, periods=periods, integrator=integrator,
            trajectory_periods=trajectory_periods,
        ),
        out,
        progress,
    )


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
    return Q._execute(
        _request(
            Q.LyapunovRequest, preset, config, set, params,
            method=method, periods=periods, transient=transient, integrator=integrator,
            steps_per_cycle=steps_per_cycle, max_periods=max_periods, d0=d0,
        ),
        None,
        progress,
    )


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
    return Q._execute(
        _request(
            Q.BifurcationRequest, preset, config, set, params,
            param=param, values=values, range=range, mode=mode, ics=ics, seed=seed,
            x0_range=x0_range, v0_range=v0_range, sections=sections, lyapunov=lyapunov,
            periods=periods, transient=transient, integrator=integrator,
            steps_per_cycle=steps_per_cycle,
        ),
        out,
        progress,
    )


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
    return Q._execute(
        _request(
            Q.ResponseRequest, preset, config, set, params,
            param=param, values=values, range=range, periods=periods, transient=transient,
            integrator=integrator, steps_per_cycle=steps_per_cycle,
        ),
        None,
        progress,
    )


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
    return Q._execute(
        _request(
            Q.BasinsRequest, preset, config, set, params,
            x=x, v=v, phase=phase, capture_tol=capture_tol, early_stop=early_stop,
            ident_rtol=ident_rtol, periods=periods, transient=transient, integrator=integrator,
            steps_per_cycle=steps_per_cycle,
        ),
        None,
        progress,
    )


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
    return Q._execute(
        _request(
            Q.ContinuationRequest, preset, config, set, params,
            param=param, values=values, range=range, ics=ics, seed=seed, x0_range=x0_range,
            v0_range=v0_range, phase=phase, capture_tol=capture_tol, early_stop=early_stop,
            ident_rtol=ident_rtol, periods=periods, transient=transient, integrator=integrator,
            steps_per_cycle=steps_per_cycle,
        ),
        None,
        progress,
    )


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
    return Q._execute(
        _request(
            Q.OrbitsRequest, preset, config, set, params,
            param=param, range=range, period=period, transient=transient, ds=ds,
            max_points=max_points, switch_up_to=switch_up_to, rtol=rtol,
        ),
        None,
        progress,
    )


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
    return Q._execute(
        _request(
            Q.SignalsRequest, preset, config, set, params,
            revolutions=revolutions, transient=transient, samples_per_cycle=samples_per_cycle,
            segment_revolutions=segment_revolutions, sidebands=sidebands,
            shaft_orders=shaft_orders, residual=residual, na4_reference=na4_reference,
        ),
        None,
        progress,
    )


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
    return Q._execute(
        _request(
            Q.MapRequest, preset, config, set, params,
            x=x, y=y, metric=metric, periods=periods, transient=transient,
            integrator=integrator, steps_per_cycle=steps_per_cycle,
        ),
        out,
        progress,
    )


def stiffness(preset=None, config=None, *, set=None, **params):
    """Mesh stiffness, load shares, friction factors and backlash over the excitation period
    (``geardyn stiffness``, without the files).

    Returns
    -------
    StiffnessResult
        ``table`` (the columns of stiffness.csv) and ``pair``.
    """
    return _stiffness_result(_geardyn.stiffness(_source(preset, config, set, params)))


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
        ``decision_budget=``, ``follow_steps=``, ``escape_copies=`` and ``escape_periods=`` (the
        horizon, budget and escape test of the chaos verdicts: by default the full report's
        10 000 periods and the quick report's 1000).
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
