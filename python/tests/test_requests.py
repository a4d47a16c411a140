"""The typed requests: one class per analysis, run by geardyn.run (or .run()); the keyword
functions are built on them, so both give the same results and the same errors."""

import dataclasses
import signal
import threading

import numpy as np
import pytest

import geardyn
from geardyn._convert import _D

SHORT = {"transient_periods": 20, "record_periods": 10}


def same_tables(a, b):
    assert list(a) == list(b)
    for k in a:
        np.testing.assert_array_equal(np.asarray(a[k]), np.asarray(b[k]))


def test_every_analysis_has_a_request():
    kinds = {c.kind for c in vars(geardyn).values() if isinstance(c, type) and issubclass(c, geardyn.Request) and c.kind}
    assert kinds == {"simulate", "lyapunov", "bifurcation", "response", "basins", "continuation", "orbits",
                     "signals", "map2d"}


def test_defaults_are_the_library_defaults():
    """The fields' defaults are those of the library's requests (the CLI's flags show them)."""
    b = geardyn.BifurcationRequest()
    assert (b.param, b.mode, b.ics, b.seed) == tuple(_D["bifurcation"][k] for k in ("param", "mode", "ics", "seed"))
    c = geardyn.ContinuationRequest()
    assert (c.ics, c.seed) == (_D["continuation"]["ics"], _D["continuation"]["seed"])
    assert geardyn.BasinsRequest().capture_tol == _D["identify"]["capture_tol"]
    o = geardyn.OrbitsRequest()
    assert (o.transient, o.ds, o.max_points) == (_D["orbits"]["transient"], _D["orbits"]["ds"], _D["orbits"]["max_points"])
    s = geardyn.SignalsRequest()
    assert (s.revolutions, s.residual) == (_D["signals"]["revolutions"], _D["signals"]["residual"])
    assert geardyn.LyapunovRequest().method == _D["lyapunov"]["method"]
    assert geardyn.MapRequest().metric == _D["map2d"]["metric"]
    assert geardyn.SimulateRequest().trajectory_periods == _D["simulate"]["trajectory_periods"]


def test_simulate_request_equals_the_keyword_call():
    kw = geardyn.simulate(preset="classic", omega=0.8, transient=20, periods=10)
    req = geardyn.SimulateRequest(preset="classic", params={"omega": 0.8}, transient=20, periods=10)
    for r in (geardyn.run(req), req.run()):
        assert isinstance(r, geardyn.SimulationResult)
        np.testing.assert_array_equal(r.strobe, kw.strobe)
        assert r.description == kw.description
        assert r.config == kw.config


def test_bifurcation_request_equals_the_keyword_call():
    kw = geardyn.bifurcation(range=(0.6, 1.4, 4), mode="sweep", set=SHORT)
    req = geardyn.BifurcationRequest(range=(0.6, 1.4, 4), mode="sweep", set=SHORT)
    r = geardyn.run(req)
    assert isinstance(r, geardyn.SweepResult)
    same_tables(r.runs, kw.runs)
    same_tables(r.points, kw.points)
    assert r.settings == kw.settings
    # a changed copy is another request
    multi = dataclasses.replace(req, mode="multi", ics=2)
    assert len(multi.run().runs["omega"]) == 8


def test_other_requests_equal_the_keyword_calls():
    r = geardyn.ResponseRequest(values=[0.8, 1.2], set=SHORT).run()
    same_tables(r.runs, geardyn.response(values=[0.8, 1.2], set=SHORT).runs)
    assert r.jumps == geardyn.response(values=[0.8, 1.2], set=SHORT).jumps
    m = geardyn.MapRequest(x=("omega", 0.8, 1.2, 2), y=("F", [0.1]), set=SHORT).run()
    np.testing.assert_array_equal(m.values, geardyn.map2d(x=("omega", 0.8, 1.2, 2), y=("F", [0.1]), set=SHORT).values)
    b = geardyn.BasinsRequest(x=(-1, 1, 3), v=(-1, 1, 3), set=SHORT, params={"omega": 0.8}).run()
    np.testing.assert_array_equal(b.cells, geardyn.basins(x=(-1, 1, 3), v=(-1, 1, 3), set=SHORT, omega=0.8).cells)
    c = geardyn.ContinuationRequest(values=[0.8, 0.9], ics=2, set=SHORT).run()
    same_tables(c.points, geardyn.continuation(values=[0.8, 0.9], ics=2, set=SHORT).points)


def test_contact_field_is_the_contact_keyword():
    a = geardyn.SimulateRequest(contact="power:1.5", transient=10, periods=3).run()
    b = geardyn.simulate(contact="power:1.5", transient=10, periods=3)
    assert a.config == b.config
    np.testing.assert_array_equal(a.strobe, b.strobe)


@pytest.mark.parametrize(
    "request_, call",
    [
        (geardyn.BifurcationRequest(mode="zigzag"), lambda: geardyn.bifurcation(mode="zigzag")),
        (geardyn.BifurcationRequest(values=[1.0], range=(0.5, 2, 3)),
         lambda: geardyn.bifurcation(values=[1.0], range=(0.5, 2, 3))),
        (geardyn.BifurcationRequest(sections=["nowhere"]), lambda: geardyn.bifurcation(sections=["nowhere"])),
        (geardyn.ContinuationRequest(ics=0), lambda: geardyn.continuation(ics=0)),
        (geardyn.BasinsRequest(phase=1.5), lambda: geardyn.basins(phase=1.5)),
        (geardyn.BasinsRequest(capture_tol=2), lambda: geardyn.basins(capture_tol=2)),
        (geardyn.LyapunovRequest(method="qr"), lambda: geardyn.lyapunov(method="qr")),
        (geardyn.LyapunovRequest(max_periods=5), lambda: geardyn.lyapunov(max_periods=5)),
        (geardyn.MapRequest(metric="beauty"), lambda: geardyn.map2d(metric="beauty")),
        (geardyn.SignalsRequest(residual="all"), lambda: geardyn.signals(residual="all")),
        (geardyn.OrbitsRequest(param="omega"), lambda: geardyn.orbits(param="omega")),
        (geardyn.SimulateRequest(params={"omega": -1}), lambda: geardyn.simulate(omega=-1)),
        (geardyn.SimulateRequest(preset="nope"), lambda: geardyn.simulate(preset="nope")),
    ],
)
def test_a_bad_field_gives_the_keyword_calls_error(request_, call):
    with pytest.raises(ValueError) as a:
        geardyn.run(request_)
    with pytest.raises(ValueError) as b:
        call()
    assert str(a.value) == str(b.value)
    assert "\n" not in str(a.value)


@pytest.mark.parametrize(
    "request_, text",
    [
        (geardyn.BifurcationRequest(mode="zigzag"), "zigzag"),
        (geardyn.ContinuationRequest(ics=0), "ics"),
        (geardyn.BasinsRequest(phase=1.5), "phase"),
        (geardyn.LyapunovRequest(method="qr"), "method"),
        (geardyn.MapRequest(metric="beauty"), "metric"),
    ],
)
def test_a_bad_field_is_named(request_, text):
    with pytest.raises(ValueError, match=text):
        request_.run()


def test_types_are_checked_on_the_way():
    with pytest.raises(TypeError, match="ics: an integer"):
        geardyn.BifurcationRequest(ics="many").run()
    with pytest.raises(TypeError, match="x: a triple"):
        geardyn.BasinsRequest(x=3).run()
    with pytest.raises(TypeError, match="contact"):
        geardyn.SimulateRequest(contact=1.5).run()
    with pytest.raises(TypeError, match="a request of one analysis"):
        geardyn.run({"kind": "simulate"})
    with pytest.raises(TypeError, match="a request of one analysis"):
        geardyn.run(geardyn.Request())


def test_out_only_where_the_cli_writes_a_folder(tmp_path):
    with pytest.raises(ValueError, match="out is not an option"):
        geardyn.run(geardyn.BasinsRequest(), out=tmp_path / "b")
    assert not (tmp_path / "b").exists()
    r = geardyn.SimulateRequest(transient=10, periods=3).run(out=tmp_path / "s")
    assert (tmp_path / "s" / "summary.json").is_file() and r.strobe.shape[0] >= 3


def test_an_interrupted_request_has_its_partial_result():
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    main = threading.main_thread().ident
    timer = threading.Timer(1.0, lambda: signal.pthread_kill(main, signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt) as e:
            geardyn.BifurcationRequest(range=(0.5, 2, 2000), integrator="rk4", periods=400).run()
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, old)
    assert isinstance(e.value.partial, geardyn.SweepResult)
    assert e.value.partial.param == "omega"
