"""The Python API: shapes, dtypes, configuration round trips, errors, Ctrl-C, the GIL."""

import json
import sys
import signal
import threading
import time

import numpy as np
import pytest

import geardyn


def test_must_show_period_one():
    assert geardyn.simulate(preset="classic", omega=0.8).summary["period"] == 1


def test_presets_and_names():
    p = geardyn.presets()
    assert set(p) == {"classic", "breakage", "internal"}
    assert all(isinstance(v, str) and v for v in p.values())
    names = geardyn.parameter_names()
    assert {"omega", "F", "xi", "D", "x0", "record_periods"} <= set(names)


def test_simulate_shapes_and_dtypes():
    r = geardyn.simulate(omega=1.3, periods=12, transient=50, trajectory_periods=2)
    assert r.strobe.dtype == np.float64 and r.strobe.shape == (12, 3)
    n = len(r.trajectory["tau"])
    assert n > 2 * 128
    for k in ["tau", "x", "v", "mesh_force"]:
        assert r.trajectory[k].dtype == np.float64 and r.trajectory[k].shape == (n,)
    assert r.trajectory["state"].dtype == np.int8
    assert set(np.unique(r.trajectory["state"])) <= {1, 0, -1, -2}
    # only the last two excitation periods are kept
    assert r.trajectory["tau"][-1] - r.trajectory["tau"][0] <= 2 * r.excitation_period + 1e-9
    m = len(r.events["tau"])
    assert r.events["kind"].dtype.kind == "U" and r.events["kind"].shape == (m,)
    assert r.events["peak_force"].dtype == np.float64
    assert r.sections["section"].dtype.kind == "U"
    assert r.summary["record_periods"] == 12 and r.summary["transient_requested"] == 50
    assert r.summary["parameters"]["omega"] == 1.3
    assert r.impact_force_per_period.shape == (12,)
    assert r.mesh_strobe.shape == (0, 2)
    assert "strobe" in repr(r)
    # the strobe is once per excitation period
    np.testing.assert_allclose(np.diff(r.strobe[:, 0]), r.excitation_period)


def test_simulate_all_trajectory_and_integrator():
    r = geardyn.simulate(omega=0.8, periods=4, transient=20, trajectory_periods=None, integrator="rk4",
                         steps_per_cycle=256)
    assert r.summary["method"] == {"method": "rk4", "steps_per_cycle": 256}
    assert r.trajectory["tau"][-1] - r.trajectory["tau"][0] > 3.9 * r.excitation_period


def test_breakage_has_mesh_strobe():
    r = geardyn.simulate(preset="breakage", periods=2, transient=2)
    cyc = r.summary["parameters"]["cycles_per_period"]
    # a record too short to decide is lengthened (at least three orbit periods when periodic)
    assert cyc > 1 and r.strobe.shape[0] >= 2
    assert r.mesh_strobe.shape == (r.strobe.shape[0] * cyc, 2)


def test_config_round_trips(tmp_path):
    sets = {"pair.lubrication.boundary_mu": 0.12}
    cfg = geardyn.config(preset="internal", set=sets, omega=1.8)
    assert cfg["pair"]["lubrication"]["boundary_mu"] == 0.12 and cfg["set"]["omega"] == 1.8
    a = geardyn.simulate(preset="internal", set=sets, omega=1.8, periods=3, transient=5)
    b = geardyn.simulate(config=cfg, periods=3, transient=5)
    np.testing.assert_array_equal(a.strobe, b.strobe)
    path = tmp_path / "my.toml"
    path.write_text(geardyn.config(config=cfg, as_toml=True))
    c = geardyn.simulate(config=path, periods=3, transient=5)
    np.testing.assert_array_equal(a.strobe, c.strobe)
    assert geardyn.config(config=str(path)) == cfg
    # simulation settings as parameters
    assert geardyn.config(x0=0.5, record_periods=7)["simulation"]["record_periods"] == 7
    # the contact law as the CLI's --contact
    lin = geardyn.config(preset="internal", contact="linear")
    assert lin["model"]["contact"] == {"law": "linear"}
    assert cfg["model"]["contact"]["law"] == "lankarani_nikravesh"


def test_derived():
    d = geardyn.derived(preset="internal")
    assert d["pair"]["k_av_n_per_m"] > 0 and d["pair"]["omega_n_rad_per_s"] > 0
    assert d["parameters"]["physical_pair"] is True
    assert any("omega_n" in line for line in d["text"])
    c = geardyn.derived(preset="classic", omega=2)
    assert c["pair"] is None and c["parameters"]["omega"] == 2
    assert c["excitation_period"] == pytest.approx(2 * np.pi / 2)


def test_lyapunov_fields():
    r = geardyn.lyapunov(omega=1.3, periods=60, transient=40, method="variational")
    assert isinstance(r.value, float) and r.history.shape == (60,) and r.history.dtype == np.float64
    assert r.periods == 60 and r.two_trajectory is None and r.rounds is None
    t = geardyn.lyapunov(omega=1.3, periods=60, transient=40, method="two-trajectory")
    assert t.variational is None and t.value == t.two_trajectory["tle"]


def test_bifurcation_shapes():
    r = geardyn.bifurcation(values=[0.8, 1.2, 1.6], periods=8, transient=30, mode="multi", ics=2,
                            sections="strobe,impact")
    n = len(r.points["omega"])
    for k, kind in [("omega", "f"), ("branch", "U"), ("ic", "i"), ("section", "U"), ("x", "f"),
                    ("v", "f"), ("label", "U")]:
        assert r.points[k].shape == (n,) and r.points[k].dtype.kind == kind, k
    assert r.runs["omega"].shape == (6,)
    assert r.runs["healthy"].dtype == np.bool_
    assert np.isnan(r.runs["tle"]).all()
    assert set(r.points["branch"]) == {"none"}
    np.testing.assert_array_equal(r.values, [0.8, 1.2, 1.6])
    # each run records at least the 8 strobe points asked for (more where 8 could not decide
    # the motion: whole orbit periods, at least three, or the lengthened record of an undecided
    # run)
    strobe = r.points["section"] == "strobe"
    for value, ic in zip(r.runs["omega"], r.runs["ic"]):
        mine = strobe & (r.points["omega"] == value) & (r.points["ic"] == ic)
        assert mine.sum() >= 8, (value, ic)


def test_range_is_the_cli_linspace():
    r = geardyn.bifurcation(range=(0.5, 2, 4), periods=2, transient=2)
    np.testing.assert_array_equal(r.values, [0.5, 1.0, 1.5, 2.0])


def test_basins_shapes():
    r = geardyn.basins(omega=1.8, x=(-2, 2, 6), v=(-1.5, 1.5, 4), transient=100, periods=32)
    assert r.cells.shape == (4, 6) and r.cells.dtype == np.int64
    assert r.x.shape == (6,) and r.v.shape == (4,)
    assert r.cells.min() >= -2 and r.cells.max() < len(r.attractors)
    total = sum(a["fraction"] for a in r.attractors) + r.diverged + r.failed
    assert total == pytest.approx(1.0)
    for a in r.attractors:
        assert {"label", "period", "healthy", "fraction", "points"} <= set(a)
        assert a["points"].ndim == 2 and a["points"].shape[1] == 2


def test_continuation_and_map_shapes():
    c = geardyn.continuation(range=(1.7, 1.8, 2), ics=4, transient=100, periods=32)
    assert c.points["branch"].dtype == np.int64 and c.lost.shape == (2, 2)
    m = geardyn.map2d(x=("omega", [0.8, 1.0]), y=("xi", 0.1, 0.2, 3), metric="period", periods=8,
                      transient=30)
    assert m.values.shape == (3, 2) and m.values.dtype == np.float64
    assert m.cells["label"].shape == (6,)


def test_grids_as_xarray():
    xr = pytest.importorskip("xarray")
    m = geardyn.map2d(x=("omega", [0.8, 1.0]), y=("xi", 0.1, 0.2, 3), metric="period", periods=8,
                      transient=30)
    ds = m.to_xarray()
    assert isinstance(ds, xr.Dataset) and ds["period"].dims == ("xi", "omega")
    # the metric's grid is the map's own `values`, cell by cell, under the parameters' names
    np.testing.assert_array_equal(ds["period"].values, m.values)
    assert ds["period"].sel(omega=1.0, xi=0.2).item() == m.values[2, 1]
    b = geardyn.basins(omega=1.8, x=(-2, 2, 6), v=(-1.5, 1.5, 4), transient=100, periods=32)
    a = b.to_xarray()
    assert a.dims == ("v", "x") and a.shape == (4, 6)
    np.testing.assert_array_equal(a.sel(x=b.x[5], v=b.v[0]).item(), b.cells[0, 5])


def test_stiffness_tables():
    s = geardyn.stiffness()
    assert s.pair is None and s.table["k_dimensionless"].shape == (1024,)
    b = geardyn.stiffness(preset="breakage")
    assert b.pair["eps_b"] is not None and b.table["zone"].dtype.kind == "U"


def _nested(depth):
    d = cur = {}
    for _ in range(depth):
        cur["a"] = {}
        cur = cur["a"]
    return d


@pytest.mark.parametrize(
    "call,exc,text",
    [
        (lambda: geardyn.simulate(D=-1), ValueError, "invalid D_d = -1"),
        (lambda: geardyn.simulate(omega="fast"), ValueError, "bad --set 'omega=fast'"),
        (lambda: geardyn.simulate(omega=None), TypeError, "omega"),
        (lambda: geardyn.simulate(omega=True), TypeError, "omega"),
        (lambda: geardyn.simulate(preset="classic", config={"model": {}}), ValueError, "exclude"),
        (lambda: geardyn.simulate(config="/nonexistent/geardyn.toml"), OSError, "cannot read"),
        (lambda: geardyn.simulate(periods=0), ValueError, "record_periods"),
        (lambda: geardyn.simulate(periods=1.5), ValueError, "record_periods"),
        (lambda: geardyn.simulate(integrator="euler"), ValueError, "method"),
        (lambda: geardyn.simulate(follow_steps=3), ValueError, "follow_steps"),
        (lambda: geardyn.simulate(set={"pair.mu": 0.1}), ValueError, "pair"),
        (lambda: geardyn.bifurcation(mode="both"), ValueError, "mode"),
        (lambda: geardyn.bifurcation(sections="strobe,nope"), ValueError, "unknown section 'nope'"),
        (lambda: geardyn.bifurcation(values=[]), ValueError, "values"),
        (lambda: geardyn.bifurcation(values=[1.0], range=(1, 2, 3)), ValueError, "exclude"),
        (lambda: geardyn.bifurcation(ics=-1, mode="multi"), ValueError, "ics"),
        (lambda: geardyn.basins(x=(1, -1, 10)), ValueError, "bad x"),
        (lambda: geardyn.basins(capture_tol=2), ValueError, "capture-tol"),
        (lambda: geardyn.lyapunov(method="qr"), ValueError, "method"),
        (lambda: geardyn.lyapunov(max_periods=5), ValueError, "max-periods"),
        (lambda: geardyn.map2d(x=("xi",)), TypeError, "x"),
        (lambda: geardyn.report(preset="nope", out="/tmp/never"), ValueError, "nope"),
        (lambda: geardyn.simulate(contact="power:1.5:0.3"), ValueError, "--contact"),
        (lambda: geardyn.simulate(contact=1.5), TypeError, "contact"),
        (lambda: geardyn.report(contact="linear", out="/tmp/never"), ValueError, "contact"),
        # a field given twice: refused, not silently overridden (issue 28, item 11)
        (lambda: geardyn.simulate(periods=5, set={"record_periods": 7}), ValueError, "given twice"),
        (lambda: geardyn.bifurcation(transient=5, transient_periods=7), ValueError, "given twice"),
        # a deeply nested dict: the documented ValueError, not RecursionError
        (lambda: geardyn.simulate(config=_nested(100_000)), ValueError, "nested too deeply"),
        # huge integers: the field named, not a bare OverflowError
        (lambda: geardyn.bifurcation(range=(0.5, 2, 10**30)), ValueError, "range count"),
        (lambda: geardyn.bifurcation(mode="multi", ics=10**30), ValueError, "ics"),
        (lambda: geardyn.basins(x=(-2, 2, 10**20)), ValueError, "x count"),
        # a huge number is printed as one, not with 300 digits
        (lambda: geardyn.basins(x=(1e300, -1e300, 10)), ValueError, "bad x axis (1e300, -1e300, 10)"),
    ],
)
def test_bad_input_raises(call, exc, text):
    with pytest.raises(exc) as e:
        call()
    assert text in str(e.value)
    assert "\n" not in str(e.value)


@pytest.fixture()
def sigint():
    """Python's own SIGINT handler, as in an interactive session (a process started in the
    background by a non-interactive shell inherits SIGINT ignored, and Python keeps that)."""
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, old)


def ctrl_c_after(seconds):
    """Sends SIGINT to the main thread after a while, as Ctrl-C in a terminal does."""
    main = threading.main_thread().ident
    timer = threading.Timer(seconds, lambda: signal.pthread_kill(main, signal.SIGINT))
    timer.start()
    return timer


@pytest.mark.parametrize(
    "call",
    [
        # the case: multi-initial on the broken pair (was honoured after 10-40 s)
        lambda: geardyn.bifurcation(preset="breakage", mode="multi", range=(0.8, 1.6, 16), ics=4),
        lambda: geardyn.bifurcation(range=(0.5, 2, 2000), integrator="rk4", periods=400),
        lambda: geardyn.basins(omega=1.8, x=(-2, 2, 800), v=(-1.5, 1.5, 800)),
        lambda: geardyn.simulate(preset="breakage", periods=10_000_000),
        lambda: geardyn.lyapunov(preset="breakage", periods=10_000_000, max_periods=100_000_000),
        lambda: geardyn.map2d(x=("omega", 0.5, 2, 60), y=("F", 0.05, 0.2, 60)),
        lambda: geardyn.continuation(preset="breakage", range=(0.8, 1.6, 20)),
    ],
)
def test_ctrl_c_stops_within_a_second(sigint, call):
    """KeyboardInterrupt (as from Ctrl-C) ends every long call within a second of the signal,
    with the finished items in the exception's `partial` (None for single runs)."""
    t = time.monotonic()
    timer = ctrl_c_after(1.0)
    with pytest.raises(KeyboardInterrupt) as e:
        call()
    assert time.monotonic() - t < 2.0
    timer.cancel()
    assert hasattr(e.value, "partial")
    # the package still works afterwards
    # (2 recorded periods cannot show a period: the decided period-1 orbit is recorded over 3)
    assert geardyn.simulate(omega=0.8, periods=2, transient=10).strobe.shape == (3, 3)


def test_ctrl_c_keeps_the_finished_values(sigint):
    """The partial result of an interrupted sweep holds whole, decided values only, with the
    same numbers as an uninterrupted sweep of those values."""
    timer = ctrl_c_after(1.5)
    kw = dict(integrator="rk4", periods=100, transient=100, decision_periods=1000)
    with pytest.raises(KeyboardInterrupt) as e:
        geardyn.bifurcation(range=(0.5, 2, 4000), **kw)
    timer.cancel()
    runs = e.value.partial.runs
    n = len(runs["omega"])
    assert 0 < n < 4000
    assert "error" not in set(runs["decided_by"])
    v = sorted(set(runs["omega"]))[:3]
    again = geardyn.bifurcation(values=v, **kw).runs
    for i, x in enumerate(runs["omega"]):
        if x in v:
            j = list(again["omega"]).index(x)
            assert runs["label"][i] == again["label"][j]
            assert runs["max_force"][i] == again["max_force"][j]


def test_long_calls_release_the_gil():
    done = []
    ticks = 0
    th = threading.Thread(
        target=lambda: done.append(geardyn.bifurcation(range=(0.5, 2, 24), periods=50, transient=200))
    )
    th.start()
    while th.is_alive():
        ticks += 1
        time.sleep(0.001)
    th.join()
    assert done and ticks > 10


def test_progress_goes_to_stderr(capsys, monkeypatch):
    # without tqdm: a line rewritten on stderr
    monkeypatch.setitem(sys.modules, "tqdm", None)
    geardyn.bifurcation(range=(0.5, 2, 3), periods=4, transient=10, progress=True)
    err = capsys.readouterr().err
    assert "bifurcation: 3/3" in err
    geardyn.bifurcation(range=(0.5, 2, 3), periods=4, transient=10)
    assert capsys.readouterr().err == ""


def test_progress_is_a_tqdm_bar_when_tqdm_is_installed(capsys):
    pytest.importorskip("tqdm")
    geardyn.bifurcation(range=(0.5, 2, 3), periods=4, transient=10, progress=True)
    err = capsys.readouterr().err
    assert "bifurcation" in err and "3/3" in err and "100%" in err


def test_help_shows_docstrings():
    for f in [geardyn.simulate, geardyn.bifurcation, geardyn.basins, geardyn.lyapunov,
              geardyn.continuation, geardyn.map2d, geardyn.stiffness, geardyn.report,
              geardyn.config, geardyn.derived]:
        assert f.__doc__ and "Returns" in f.__doc__, f.__name__
    assert "ValueError" in geardyn.__doc__


def test_report_quick_and_interrupt(tmp_path, sigint):
    out = tmp_path / "rep"
    # Ctrl-C stops the report's process at once (the internal preset: its quick report takes
    # several seconds; the classic one now finishes within the second)
    t = time.monotonic()
    timer = ctrl_c_after(1.0)
    with pytest.raises(KeyboardInterrupt):
        geardyn.report(preset="internal", out=out, quick=True)
    assert time.monotonic() - t < 10
    timer.cancel()
    assert not (out / "internal" / "index.html").exists()
    # the interrupted page keeps its finished studies for a rerun to resume from (the resume
    # itself is checked on the Rust side, crates/cli/tests/scenario.rs and
    # crates/report/tests/page.rs: it is the same library call); another preset's report goes
    # beside it and the top index links it
    assert any((out / "internal").iterdir())
    index = geardyn.report(preset="classic", out=out, quick=True)
    assert index == out / "classic" / "index.html"
    assert index.is_file() and (out / "index.html").is_file()
    assert (out / "classic" / "claims.csv").is_file()
    assert not (out / "internal" / "index.html").exists()


def test_simulate_out_writes_the_cli_folder(tmp_path):
    """`simulate(out=)` writes the folder the CLI writes (run.json, summary.json, ...) and locks
    it as the CLI does: a folder of another kind is refused before any work."""
    out = tmp_path / "run"
    r = geardyn.simulate(omega=0.8, periods=5, transient=50, out=out)
    names = {p.name for p in out.iterdir()}
    for f in ["run.json", "summary.json", "config.toml", "trajectory.csv", "strobe.csv",
              "events.csv", "sections.csv", "time_history.png", "phase_portrait.svg"]:
        assert f in names, f
    assert ".geardyn.lock" not in names
    s = json.loads((out / "summary.json").read_text())
    assert s["label"] == r.summary["label"] and s["rates"] == r.summary["rates"]
    assert json.loads((out / "run.json").read_text())["kind"] == "simulate"
    # a folder of a user's own files is not geardyn's
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("mine")
    with pytest.raises(OSError):
        geardyn.simulate(omega=0.8, out=mine)
    assert (mine / "notes.txt").read_text() == "mine"


def test_to_dataframe_has_the_runs_columns():
    pd = pytest.importorskip("pandas")
    r = geardyn.bifurcation(range=(0.5, 2, 12), periods=20, transient=100)
    df = r.to_dataframe()
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns) == list(r.runs) and len(df) == 12
    assert list(df.columns[:1]) == ["omega"]
    # labels carry no numbers: a groupby makes one group per motion, not per run
    assert df.groupby("class").size().sum() == 12
    assert set(df.loc[df["period"] == 0, "label"]) <= {"chaotic", "quasi-periodic", "unsettled"}
    assert list(r.to_dataframe("points").columns) == list(r.points)


def test_a_second_ctrl_c_leaves_the_module_working(sigint):
    """Two Ctrl-C in a row (the second stops the waiting): later calls still run and are right
    (the stop request was left up and cut every later run)."""
    main = threading.main_thread().ident
    timers = [threading.Timer(t, lambda: signal.pthread_kill(main, signal.SIGINT)) for t in (0.8, 0.86)]
    for t in timers:
        t.start()
    with pytest.raises(KeyboardInterrupt):
        geardyn.basins(omega=1.8, x=(-2, 2, 800), v=(-1.5, 1.5, 800))
        time.sleep(1)  # (the second signal may land after the call)
    for t in timers:
        t.join()
    s = geardyn.simulate(omega=0.8, periods=5, transient=50).summary
    assert s["label"] == "1-1-0" and s["decided_by"] == "period_test"
    b = geardyn.bifurcation(range=(0.5, 2, 12), periods=20, transient=100)
    assert "failed" not in set(b.runs["class"])


def test_ctrl_c_of_one_call_never_alters_another(sigint):
    """A call running in another thread while Ctrl-C stops the main thread's call either
    returns exactly what it returns undisturbed, or is interrupted too (with its finished
    values): never a result with runs cut short."""
    kw = dict(range=(0.5, 2, 600), integrator="rk4", periods=50, transient=100, decision_periods=500)
    clean = geardyn.bifurcation(**kw).runs
    box = {}

    def background():
        try:
            box["runs"] = geardyn.bifurcation(**kw).runs
        except KeyboardInterrupt as e:
            box["partial"] = e.partial

    th = threading.Thread(target=background)
    th.start()
    timer = ctrl_c_after(0.5)
    with pytest.raises(KeyboardInterrupt):
        geardyn.simulate(preset="breakage", periods=10_000_000)
    timer.cancel()
    th.join()
    if "runs" in box:
        for k in ["label", "class"]:
            assert box["runs"][k].tolist() == clean[k].tolist()
        assert_same = np.testing.assert_array_equal
        assert_same(box["runs"]["max_force"], clean["max_force"])
    else:
        p = box["partial"].runs
        assert "failed" not in set(p["class"])
        for x, lab in zip(p["omega"], p["label"]):
            assert lab == clean["label"][list(clean["omega"]).index(x)]


def test_work_above_the_cap_is_refused_at_once():
    """The CLI's cap on a call's total work holds in Python too (the call ran for days)."""
    t = time.monotonic()
    with pytest.raises(ValueError, match="max_work"):
        geardyn.simulate(periods=10**6, integrator="rk4", steps_per_cycle=10**6)
    with pytest.raises(ValueError, match="above the cap"):
        geardyn.bifurcation(range=(0.5, 2, 10**6), periods=10**6)
    with pytest.raises(ValueError, match="above the cap"):
        geardyn.basins(x=(-2, 2, 4000), v=(-1.5, 1.5, 4000), transient=10**6)
    assert time.monotonic() - t < 5


def test_an_empty_partial_has_the_columns_of_the_sweep(sigint):
    """Interrupted before any value finished: the partial result still names the swept
    parameter's column (it fell back to `value`)."""
    timer = threading.Timer(0.05, lambda: signal.pthread_kill(threading.main_thread().ident, signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt) as e:
        geardyn.bifurcation(param="F", range=(0.01, 0.2, 600), integrator="rk4", periods=50,
                            transient=100, decision_periods=500)
    timer.join()
    p = e.value.partial
    assert list(p.runs)[0] == "F" and list(p.points)[0] == "F" and p.param == "F"
