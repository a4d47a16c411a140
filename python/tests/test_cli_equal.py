"""Python results equal the CLI's for the same inputs (the CLI writes numbers in shortest
round-trip form, so equality is exact)."""

import csv
import json
import re
import sys

import numpy as np
import pytest

import geardyn

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    tomllib = None


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def column(path, name, kind=float):
    header, rows = read_csv(path)
    j = header.index(name)

    def conv(s):
        if kind is float:
            return float(s) if s != "" else float("nan")
        return kind(s)

    return [conv(r[j]) for r in rows]


def header(path):
    return read_csv(path)[0]


def assert_same(a, b):
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    assert a.shape == b.shape
    np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize(
    "preset,sets,periods,transient",
    [
        ("classic", {"omega": 0.8}, 20, 100),
        ("classic", {"omega": 1.3, "F": 0.05}, 20, 100),
        ("breakage", {}, 3, 5),
        ("internal", {"omega": 1.8, "pair.lubrication.boundary_mu": 0.12}, 5, 20),
    ],
)
def test_simulate_equals_cli(cli, out, preset, sets, periods, transient):
    args = ["simulate", "--preset", preset, "--periods", periods, "--transient", transient]
    for k, v in sets.items():
        args += ["--set", f"{k}={v}"]
    cli(*args, "--out", out)
    dotted = {k: v for k, v in sets.items() if "." in k}
    plain = {k: v for k, v in sets.items() if "." not in k}
    r = geardyn.simulate(preset=preset, periods=periods, transient=transient, set=dotted, **plain)

    header, _ = read_csv(out / "strobe.csv")
    assert header == ["tau", "x", "v"]
    for j, name in enumerate(header):
        assert_same(r.strobe[:, j], column(out / "strobe.csv", name))
    for name in ["tau", "x", "v", "mesh_force"]:
        assert_same(r.trajectory[name], column(out / "trajectory.csv", name))
    assert r.trajectory["state"].tolist() == column(out / "trajectory.csv", "state", int)
    for name in ["tau", "cycle_position", "x", "v_before", "v_after", "peak_force"]:
        assert_same(r.events[name], column(out / "events.csv", name))
    assert r.events["kind"].tolist() == column(out / "events.csv", "kind", str)
    for name in ["tau", "x", "v"]:
        assert_same(r.sections[name], column(out / "sections.csv", name))
    assert r.sections["section"].tolist() == column(out / "sections.csv", "section", str)

    summary = json.loads((out / "summary.json").read_text())
    mine = dict(r.summary)
    for s in (summary, mine):
        s.pop("wall_time_s")
    assert mine == summary


def parse_tle(stdout, what):
    m = re.search(rf"TLE \({what}[^)]*\): (-?[0-9.]+) \+- ([0-9.naNinf]+)", stdout)
    assert m, stdout
    return m.group(1), m.group(2)


def test_lyapunov_fixed_length_equals_cli(cli):
    p = cli("lyapunov", "--set", "omega=1.3", "--periods", "150", "--transient", "100")
    r = geardyn.lyapunov(omega=1.3, periods=150, transient=100)
    assert r.method == "both" and r.converged is None
    assert parse_tle(p.stdout, "variational") == (f"{r.value:.6f}", f"{r.stderr:.6f}")
    two = r.two_trajectory
    assert parse_tle(p.stdout, "two-trajectory") == (f"{two['tle']:.6f}", f"{two['spread']:.6f}")


def test_lyapunov_converged_equals_cli(cli):
    p = cli("lyapunov", "--set", "omega=0.7", "--method", "variational", "--max-periods", "800")
    r = geardyn.lyapunov(omega=0.7, method="variational", max_periods=800)
    rounds = re.findall(r"^\s+(\d+) periods: TLE (-?[0-9.]+) \(at half the run (-?[0-9.]+)\)", p.stdout, re.M)
    assert [int(n) for n, _, _ in rounds] == r.rounds["periods"].tolist()
    assert [t for _, t, _ in rounds] == [f"{x:.6f}" for x in r.rounds["tle"]]
    assert [h for _, _, h in rounds] == [f"{x:.6f}" for x in r.rounds["half"]]
    assert ("converged:" in p.stdout) == r.converged
    assert parse_tle(p.stdout, "variational") == (f"{r.value:.6f}", f"{r.stderr:.6f}")
    assert r.two_trajectory is None


@pytest.mark.parametrize(
    "mode,extra",
    [
        ("fixed", []),
        ("sweep", []),
        ("multi", ["--ics", "3", "--seed", "7"]),
    ],
)
def test_bifurcation_equals_cli(cli, out, mode, extra):
    cli(
        "bifurcation",
        "--range", "0.6:1.8:7",
        "--periods", "16",
        "--transient", "60",
        "--mode", mode,
        "--sections", "strobe,impact,ds_up",
        *extra,
        "--out", out,
    )
    kw = {"ics": 3, "seed": 7} if mode == "multi" else {}
    r = geardyn.bifurcation(
        range=(0.6, 1.8, 7), periods=16, transient=60, mode=mode,
        sections=["strobe", "impact", "ds_up"], **kw,
    )
    path = out / "bifurcation.csv"
    # one schema: the same columns, in the same order, under the same names
    assert list(r.points) == header(path)
    assert list(r.runs) == header(out / "runs.csv")
    assert list(r.impact_force) == header(out / "impact_force.csv")
    assert_same(r.points["omega"], column(path, "omega"))
    for name in ["x", "v"]:
        assert_same(r.points[name], column(path, name))
    assert r.points["ic"].tolist() == column(path, "ic", int)
    for name in ["branch", "section", "label"]:
        assert r.points[name].tolist() == column(path, name, str)
    runs = out / "runs.csv"
    for name in ["x0", "v0", "p_id", "max_force", "min_force", "max_impact_force", "rms_x",
                 "p2p_x", "rms_force", "p2p_force"]:
        assert_same(r.runs[name], column(runs, name))
    assert r.runs["label"].tolist() == column(runs, "label", str)
    assert r.runs["period"].tolist() == column(runs, "period", int)
    assert r.runs["healthy"].tolist() == [s == "true" for s in column(runs, "healthy", str)]
    # the decision's record: one schema in both
    for name in ["class", "decided_by", "reason"]:
        assert r.runs[name].tolist() == column(runs, name, str)
    # labels carry no numbers: runs group by them
    assert not any(ch.isdigit() for lab, p in zip(r.runs["label"], r.runs["period"]) if p == 0
                   for ch in lab)
    for name in ["p_rate", "q_rate", "decision_tle", "final_x", "final_v"]:
        assert_same(r.runs[name], column(runs, name))
    assert r.runs["periods_integrated"].tolist() == column(runs, "periods_integrated", int)


def test_bifurcation_lyapunov_and_pair_param_equal_cli(cli, out):
    cli(
        "bifurcation", "--preset", "internal", "--param", "pair.lubrication.boundary_mu",
        "--range", "0.02:0.1:3",
        "--periods", "8", "--transient", "20", "--lyapunov", "--out", out,
    )
    r = geardyn.bifurcation(
        preset="internal", param="pair.lubrication.boundary_mu", range=(0.02, 0.1, 3), periods=8,
        transient=20,
        lyapunov=True,
    )
    assert_same(r.runs["tle"], column(out / "runs.csv", "tle"))
    assert_same(r.points["x"], column(out / "bifurcation.csv", "x"))


def test_response_equals_cli(cli, out):
    cli("response", "--range", "0.6:1.8:6", "--periods", "16", "--transient", "60", "--out", out)
    r = geardyn.response(range=(0.6, 1.8, 6), periods=16, transient=60)
    path = out / "response.csv"
    for name in ["mean_x", "rms_x", "p2p_x", "mean_force", "rms_force", "p2p_force", "max_force",
                 "p_id"]:
        assert_same(r.runs[name], column(path, name))
    assert r.runs["branch"].tolist() == column(path, "branch", str)
    jumps = json.loads((out / "jumps.json").read_text())
    assert r.jumps == jumps


def test_basins_equal_cli(cli, out):
    cli(
        "basins", "--set", "omega=1.8", "--grid", "x:-2:2:12", "--grid", "v:-1.5:1.5:10",
        "--transient", "150", "--periods", "32", "--phase", "0.25", "--out", out,
    )
    r = geardyn.basins(omega=1.8, x=(-2, 2, 12), v=(-1.5, 1.5, 10), transient=150, periods=32,
                       phase=0.25)
    cells = np.load(out / "basins.npy")
    assert r.cells.dtype == cells.dtype == np.int64
    np.testing.assert_array_equal(r.cells, cells)
    att = json.loads((out / "attractors.json").read_text())
    assert [a["descriptor"]["label"] for a in att["attractors"]] == [a["label"] for a in r.attractors]
    assert [a["fraction"] for a in att["attractors"]] == [a["fraction"] for a in r.attractors]
    for a, b in zip(att["attractors"], r.attractors):
        np.testing.assert_array_equal(np.asarray(a["descriptor"]["points"]).reshape(-1, 2), b["points"])
    assert att["boundary_fraction"] == r.boundary_fraction
    assert_same(r.x, sorted(set(column(out / "basins.csv", "x0"))))


def test_continuation_equals_cli(cli, out):
    cli(
        "continuation", "--range", "1.6:1.9:3", "--ics", "6", "--transient", "120", "--periods",
        "32", "--out", out,
    )
    r = geardyn.continuation(range=(1.6, 1.9, 3), ics=6, transient=120, periods=32)
    path = out / "continuation.csv"
    for name in ["fraction", "max_force", "x", "v"]:
        assert_same(r.points[name], column(path, name))
    assert r.points["label"].tolist() == column(path, "label", str)
    assert r.points["branch"].tolist() == column(path, "branch", int)
    saved = json.loads((out / "continuation.json").read_text())
    assert saved["events"] == r.events
    assert saved["intervals"] == r.intervals


def test_map2d_equals_cli(cli, out):
    cli(
        "map2d", "--x", "omega:0.7:1.5:3", "--y", "F:0.05:0.15:2", "--metric", "class",
        "--periods", "16", "--transient", "60", "--out", out,
    )
    r = geardyn.map2d(x=("omega", 0.7, 1.5, 3), y=("F", 0.05, 0.15, 2), metric="class",
                      periods=16, transient=60)
    values = np.load(out / "map.npy")
    assert r.values.shape == values.shape == (2, 3)
    np.testing.assert_array_equal(r.values, values)
    assert_same(r.cells["max_force"], column(out / "map.csv", "max_force"))


@pytest.mark.parametrize("preset", ["classic", "breakage"])
def test_stiffness_equals_cli(cli, out, preset):
    cli("stiffness", "--preset", preset, "--out", out)
    r = geardyn.stiffness(preset=preset)
    header, _ = read_csv(out / "stiffness.csv")
    assert list(r.table) == header
    for name in header:
        if r.table[name].dtype.kind == "U":
            assert r.table[name].tolist() == column(out / "stiffness.csv", name, str)
        else:
            assert_same(r.table[name], column(out / "stiffness.csv", name))


@pytest.mark.skipif(tomllib is None, reason="tomllib needs Python 3.11")
@pytest.mark.parametrize("preset,sets", [("classic", {"omega": 1.3}), ("internal", {"omega": 2.0, "pair.lubrication.boundary_mu": 0.12})])
def test_config_equals_show(cli, preset, sets):
    args = ["show", "--preset", preset]
    for k, v in sets.items():
        args += ["--set", f"{k}={v}"]
    p = cli(*args)
    assert tomllib.loads(p.stdout) == geardyn.config(preset=preset, set=sets)
    toml_part = "".join(l for l in p.stdout.splitlines(True) if not l.startswith("#"))
    assert geardyn.config(preset=preset, set=sets, as_toml=True) == toml_part
    derived = geardyn.derived(preset=preset, set=sets)
    comments = [l[1:].strip() for l in p.stdout.splitlines() if l.startswith("#") and "---" not in l]
    assert derived["text"] == comments


@pytest.mark.parametrize(
    "args,call",
    [
        (["simulate", "--set", "D=-1"], lambda: geardyn.simulate(D=-1)),
        (["simulate", "--set", "omgea=1"], lambda: geardyn.simulate(omgea=1)),
        (["simulate", "--preset", "internal", "--set", "mu=0.1"], lambda: geardyn.simulate(preset="internal", mu=0.1)),
        (["simulate", "--preset", "nope"], lambda: geardyn.simulate(preset="nope")),
        (["simulate", "--set", "omega=5000"], lambda: geardyn.simulate(omega=5000)),
        (["lyapunov", "--d0", "0.5"], lambda: geardyn.lyapunov(d0=0.5)),
        (["bifurcation", "--param", "eps", "--preset", "breakage", "--range", "1:2:3"],
         lambda: geardyn.bifurcation(param="eps", preset="breakage", range=(1, 2, 3))),
        (["basins", "--phase", "1.5"], lambda: geardyn.basins(phase=1.5)),
        (["basins", "--grid", "x:-2:2:0"], lambda: geardyn.basins(x=(-2, 2, 0))),
        (["basins", "--grid", "x:-2:2:5000"], lambda: geardyn.basins(x=(-2, 2, 5000))),
        (["basins", "--grid", "x:nan:2:10"], lambda: geardyn.basins(x=(float("nan"), 2, 10))),
        (["bifurcation", "--range", "0.6:nan:9"], lambda: geardyn.bifurcation(range=(0.6, float("nan"), 9))),
        (["map2d", "--x", "omega:0.5:1:0"], lambda: geardyn.map2d(x=("omega", 0.5, 1, 0))),
        (["lyapunov", "--method", "qr"], lambda: geardyn.lyapunov(method="qr")),
        (["simulate", "--integrator", "euler"], lambda: geardyn.simulate(integrator="euler")),
        (["continuation", "--phase", "1.5"], lambda: geardyn.continuation(phase=1.5)),
        (["map2d", "--metric", "nope"], lambda: geardyn.map2d(metric="nope")),
        (["show", "--set", "pair.mu=0.1"], lambda: geardyn.config(set={"pair.mu": 0.1})),
    ],
)
def test_errors_have_the_cli_message(cli, out, args, call):
    p = cli(*args, *(["--out", out] if args[0] not in ("lyapunov", "show") else []), check=False)
    assert p.returncode != 0
    line = p.stderr.strip().splitlines()[-1]
    assert line.startswith("error: ")
    with pytest.raises(ValueError) as e:
        call()
    assert str(e.value) == line[len("error: "):]


def test_report_equals_cli(cli, tmp_path):
    cli("report", "--preset", "classic", "--quick", "--set", "F=0.12", "--out", tmp_path / "cli")
    index = geardyn.report(preset="classic", quick=True, F=0.12, out=tmp_path / "py")
    assert index == tmp_path / "py" / "classic" / "index.html"
    for name in ["claims.csv", "config.toml"]:
        a = (tmp_path / "cli" / "classic" / name).read_text()
        b = (tmp_path / "py" / "classic" / name).read_text()
        assert a == b, name


@pytest.mark.parametrize(
    "command,func",
    [
        ("simulate", geardyn.simulate),
        ("lyapunov", geardyn.lyapunov),
        ("bifurcation", geardyn.bifurcation),
        ("basins", geardyn.basins),
        ("continuation", geardyn.continuation),
        ("orbits", geardyn.orbits),
        ("signals", geardyn.signals),
        ("map2d", geardyn.map2d),
    ],
)
def test_keyword_defaults_are_the_cli_defaults(cli, command, func):
    """Every keyword whose flag shows a default in ``--help`` has that default in Python."""
    import inspect

    help_text = cli(command, "--help").stdout
    flags = {}
    for block in re.split(r"\n\s+--", help_text)[1:]:
        name = block.split()[0].split("=")[0].replace("-", "_")
        m = re.search(r"\[default: ([^\]]+)\]", block)
        if m:
            flags[name] = m.group(1)
    params = inspect.signature(func).parameters
    # Python's `early_stop` is the CLI's `--no-early-stop` inverted (a switch has no default shown)
    compared = 0
    for name, shown in flags.items():
        if name in params and params[name].default is not inspect.Parameter.empty:
            d = params[name].default
            if isinstance(d, bool) or d is None or name == "out":
                continue
            # a tuple is the CLI's `A:B:C` (an axis) or `A,B` (a list)
            want = list(d) if isinstance(d, (tuple, list)) else [d]
            got = re.split(r"[:,]", shown) if len(want) > 1 or isinstance(d, (tuple, list)) else [shown]
            assert len(got) == len(want), (command, name, d, shown)
            for w, g in zip(want, got):
                if isinstance(w, str):
                    assert w == g, (command, name, d, shown)
                else:
                    assert float(w) == float(g), (command, name, d, shown)
            compared += 1
    assert compared >= 1, (command, flags)


def test_bifurcation_out_writes_the_cli_folder_and_resumes(cli, tmp_path):
    """`bifurcation(out=)` writes the folder `geardyn bifurcation --out` writes, with the same
    tables; a folder whose checkpoint lost some values (an interrupted sweep) is resumed: only
    those are computed again, and the tables come out the same."""
    args = ["--range", "0.6:1.8:7", "--periods", "16", "--transient", "60"]
    cli("bifurcation", *args, "--out", tmp_path / "cli")
    py = tmp_path / "py"
    r = geardyn.bifurcation(range=(0.6, 1.8, 7), periods=16, transient=60, out=py)
    for name in ["runs.csv", "bifurcation.csv", "impact_force.csv", "config.toml"]:
        assert (py / name).read_text() == (tmp_path / "cli" / name).read_text(), name
    assert (py / "bifurcation.png").stat().st_size > 0
    assert json.loads((py / "run.json").read_text())["kind"] == "bifurcation"
    assert list(r.runs["omega"]) == column(py / "runs.csv", "omega")
    # an interrupted sweep: the checkpoint holds its header and the first three values
    cp = py / "checkpoint.jsonl"
    lines = cp.read_text().splitlines(keepends=True)
    assert len(lines) > 4
    cp.write_text("".join(lines[:4]))
    runs_before = (py / "runs.csv").read_text()
    (py / "runs.csv").unlink()
    again = geardyn.bifurcation(range=(0.6, 1.8, 7), periods=16, transient=60, out=py)
    assert (py / "runs.csv").read_text() == runs_before
    assert list(again.runs["label"]) == list(r.runs["label"])
    # the kept values were not computed again: the checkpoint gained only the missing ones
    assert cp.read_text().splitlines(keepends=True)[:4] == lines[:4]
    assert len(cp.read_text().splitlines()) == len(lines)
    # the CLI resumes the same folder too (nothing left to compute), and other settings there
    # are refused
    cli("bifurcation", *args, "--out", py)
    with pytest.raises(Exception, match="checkpoint|settings|folder"):
        geardyn.bifurcation(range=(0.6, 1.8, 8), periods=16, transient=60, out=py)


def test_map2d_out_writes_the_cli_folder_and_resumes(cli, tmp_path):
    """`map2d(out=)` writes the folder `geardyn map2d --out` writes; a checkpoint that lost some
    cells (an interrupted map) is resumed: only those are computed again."""
    args = ["--x", "omega:0.7:1.5:3", "--y", "F:0.05:0.15:2", "--metric", "class",
            "--periods", "16", "--transient", "60"]
    cli("map2d", *args, "--out", tmp_path / "cli")
    py = tmp_path / "py"
    kw = dict(x=("omega", 0.7, 1.5, 3), y=("F", 0.05, 0.15, 2), metric="class", periods=16,
              transient=60)
    r = geardyn.map2d(**kw, out=py)
    assert (py / "map.csv").read_text() == (tmp_path / "cli" / "map.csv").read_text()
    np.testing.assert_array_equal(np.load(py / "map.npy"), r.values)
    assert json.loads((py / "run.json").read_text())["kind"] == "map2d"
    cp = py / "checkpoint.jsonl"
    lines = cp.read_text().splitlines(keepends=True)
    assert len(lines) == 1 + 6
    cp.write_text("".join(lines[:3]))
    again = geardyn.map2d(**kw, out=py)
    np.testing.assert_array_equal(again.values, r.values)
    assert cp.read_text().splitlines(keepends=True)[:3] == lines[:3]
    assert len(cp.read_text().splitlines()) == len(lines)
    assert (py / "map.csv").read_text() == (tmp_path / "cli" / "map.csv").read_text()
