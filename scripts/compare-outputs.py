#!/usr/bin/env python3
"""Refactor verification for geardyn: the same commands, before and after, compared file by file.

A refactor proves itself by its outputs: every command that computes something is run with the
binary built before the change and with the binary built after it, on every preset, and the two
output trees are compared file by file. Results must be identical byte for byte; only what is
volatile by nature (timings, start times, the build's version, commit and source digest, the
command line with the binary's path, the thread count) is taken out before comparing.

Usage (Python 3.11 standard library only; run from the repository root):

    # 1. the old commit's binary (e.g. in a separate worktree, so your tree is left alone)
    git worktree add /tmp/geardyn-old <old-commit>
    (cd /tmp/geardyn-old && cargo build --release -p geardyn-cli)
    cp /tmp/geardyn-old/target/release/geardyn /tmp/geardyn_before
    python3 scripts/compare-outputs.py run /tmp/geardyn_before /tmp/cmp/before [--quick-report]

    # 2. the new binary
    cargo build --release -p geardyn-cli
    python3 scripts/compare-outputs.py run target/release/geardyn /tmp/cmp/after [--quick-report]

    # 3. compare: prints each differing file with a hint and a count; exit 0 when identical
    python3 scripts/compare-outputs.py compare /tmp/cmp/before /tmp/cmp/after

`run BINARY OUTDIR` runs the fixed suite of `suite()` below: every command that computes
something (show, stiffness, simulate, bifurcation in its fixed, sweep and multi modes with
--lyapunov on one and a `pair.*` sweep, lyapunov, response, basins, continuation, orbits (one
orbit and a branch), signals, map2d, and a map2d planned in 2 shards, run shard by shard and
merged) on every preset, with tiny grids and short runs: about 1 minute on 2 cores. With
`--quick-report` it also makes `report --quick` of each preset (classic ~6 s, internal ~0.5-1
min, breakage ~1-2 min). RAYON_NUM_THREADS is set to 2 (results depend on the thread count
through the lane batching, so both runs must use the same; --threads changes it). The commands
run inside OUTDIR with relative --out folders, so that no absolute path enters the results.
Every command's stdout goes to OUTDIR/stdout/NAME.txt (the results of show, presets, lyapunov,
status), and OUTDIR/commands.jsonl records each command line, exit code, stderr and wall time.
A failing command is a result like any other: it is recorded and the suite goes on; a command
the CLI refuses by design (signals on classic, which has no pair) is recorded as skipped. OUTDIR
must be new or empty (--clean empties a previous OUTDIR of this script). --only SUBSTRING runs
the commands whose name contains it (for a quick try; compare only runs of the same selection).

`compare DIR_A DIR_B` walks both trees: a file present on one side only is a difference;
`.json` files are compared as data after removing the volatile keys (VOLATILE_KEYS below);
report `.html` pages and stdout files after masking timings (VOLATILE_TEXT); commands.jsonl on
exit code and stderr (timings masked, lines in any order: a report's studies print as they
finish); a checkpoint.jsonl on its first line and the set of its item lines (the order items
finish in is scheduling, not a result); every other file (csv, png, svg, npy, toml, zarr chunks
and metadata, ...) byte for byte. It prints each differing file with a hint (the first differing
JSON key, text line and column, or binary size and offset) and a count; exit status 0 when the
trees are identical, 1 otherwise.

The harness's own test: two runs of one binary compare identical
(`run B /tmp/x1 && run B /tmp/x2 && compare /tmp/x1 /tmp/x2`).
"""

from __future__ import annotations

import argparse
import concurrent.futures
import json
import os
import re
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

PRESETS = ("classic", "breakage", "internal")

# commands the CLI refuses by design, with the error text that says so: these are skipped
# (recorded in commands.jsonl as skipped), any other failure is a result
REFUSED_BY_DESIGN = {
    ("signals", "classic"): "has no physical [pair]",
}

# per preset: the frequency range of its sweeps, and a `pair.*` field to sweep (rebuilding the
# pair at every value; classic has no pair)
OMEGA = {"classic": (0.6, 1.8), "breakage": (0.8, 1.6), "internal": (1.4, 1.8)}
PAIR_FIELD = {"breakage": ("pair.mu", 0.05, 0.2), "internal": ("pair.lubrication.viscosity_mpas", 15, 30)}

# run lengths of the model commands: short transients and records; the chaos decision keeps its
# default horizon (10 000 periods), so that its follow-ups are exercised too
SHORT = ["--transient", "100", "--periods", "30"]


def suite(quick_report: bool) -> list[list[dict]]:
    """The commands, as groups; a group's steps run in order (they depend on each other).

    Each step: name (unique; with `out`, also its --out folder under OUTDIR), args (after the
    binary), out (True: the command gets --out NAME), preset.
    """
    groups: list[list[dict]] = [[dict(name="presets", args=["presets"], out=False, preset=None)]]

    def step(name, args, preset, out=True):
        return dict(name=name, args=args, out=out, preset=preset)

    def one(name, args, preset, out=True):
        groups.append([step(name, args, preset, out)])

    for p in PRESETS:
        pre = ["--preset", p]
        lo, hi = OMEGA[p]
        om4, om6 = f"{lo}:{hi}:4", f"{lo}:{hi}:6"
        # show, then the printed configuration read back by simulate --config
        groups.append([
            step(f"show/{p}", ["show", *pre], p, out=False),
            step(f"simulate-config/{p}",
                 ["simulate", "--config", f"stdout/show__{p}.txt", *SHORT, "--set", f"omega={hi}"],
                 p),
        ])
        one(f"stiffness/{p}", ["stiffness", *pre], p)
        one(f"simulate/{p}", ["simulate", *pre, *SHORT, "--trajectory-periods", "3"], p)
        one(f"simulate-set/{p}", ["simulate", *pre, *SHORT, "--set", f"omega={lo}", "--set", "F=0.05",
                                  "--integrator", "rk4", "--steps-per-cycle", "256"], p)
        one(f"bifurcation-fixed/{p}",
            ["bifurcation", *pre, *SHORT, "--mode", "fixed", "--param", "omega", "--range", om6,
             "--sections", "strobe,ds_up,ds_down,dd_up,dd_down,impact", "--lyapunov"], p)
        one(f"bifurcation-sweep/{p}",
            ["bifurcation", *pre, *SHORT, "--mode", "sweep", "--param", "omega", "--range", om6], p)
        one(f"bifurcation-multi/{p}",
            ["bifurcation", *pre, *SHORT, "--mode", "multi", "--ics", "4", "--param", "F",
             "--range", "0.03:0.12:4"], p)
        if p in PAIR_FIELD:
            f, a, b = PAIR_FIELD[p]
            one(f"bifurcation-pair/{p}",
                ["bifurcation", *pre, *SHORT, "--param", f, "--range", f"{a}:{b}:3"], p)
        one(f"lyapunov/{p}", ["lyapunov", *pre, "--transient", "100", "--periods", "100"], p,
            out=False)
        one(f"lyapunov-converge/{p}", ["lyapunov", *pre, "--method", "variational",
                                       "--transient", "100", "--max-periods", "800"], p, out=False)
        one(f"response/{p}", ["response", *pre, *SHORT, "--param", "omega", "--range", om4], p)
        one(f"basins/{p}", ["basins", *pre, *SHORT, "--grid", "x:-2:2:6", "--grid", "v:-1.5:1.5:5"],
            p)
        one(f"continuation/{p}", ["continuation", *pre, *SHORT, "--param", "omega",
                                  "--range", om4, "--ics", "5"], p)
        one(f"orbits-one/{p}", ["orbits", *pre, "--transient", "100"], p)
        one(f"orbits-branch/{p}", ["orbits", *pre, "--transient", "100", "--param", "omega",
                                   "--range", f"{lo}:{hi}", "--max-points", "12",
                                   "--diagram", "8"], p)
        one(f"signals/{p}", ["signals", *pre, "--revolutions", "4", "--transient", "20"], p)
        m2 = ["--x", f"omega:{lo}:{hi}:3", "--y", "F:0.05:0.15:2"]
        one(f"map2d/{p}", ["map2d", *pre, *SHORT, *m2, "--metric", "class"], p)
        # the same map planned in two shards, computed shard by shard, merged into the store
        store = f"shards/{p}.zarr"
        groups.append([
            step(f"plan/{p}", ["plan", "map2d", *pre, *SHORT, *m2, "--metric", "class",
                               "--shards", "2", "--out", store], p, out=False),
            step(f"run-shard-1/{p}", ["run-shard", store, "--shard", "1"], p, out=False),
            step(f"status-1/{p}", ["status", store], p, out=False),
            step(f"run-shard-0/{p}", ["run-shard", store, "--shard", "0"], p, out=False),
            step(f"status/{p}", ["status", store, "--missing"], p, out=False),
            step(f"merge/{p}", ["merge", store], p, out=False),
        ])
    if quick_report:
        # one group: the presets' reports share OUTDIR/report and its index.html
        groups.append([
            step(f"report/{p}", ["report", "--quick", "--preset", p, "--out", "report"], p,
                 out=False)
            for p in PRESETS
        ])
    return groups


def stdout_file(outdir: Path, name: str) -> Path:
    return outdir / "stdout" / (name.replace("/", "__") + ".txt")


def run_step(binary: str, outdir: Path, step: dict, env: dict, timeout: float) -> dict:
    args = list(step["args"])
    if step["out"]:
        args += ["--out", step["name"]]
    rec = {"name": step["name"], "binary": binary, "argv": ["BINARY", *args]}
    t = time.monotonic()
    try:
        p = subprocess.run([binary, *args], cwd=outdir, env=env, capture_output=True,
                           timeout=timeout)
        rc, out, err = p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired as e:
        rc, out, err = "timeout", e.stdout or b"", (e.stderr or b"") + b"\n[timed out]"
    rec["elapsed_s"] = round(time.monotonic() - t, 3)
    rec["exit"] = rc
    rec["stderr"] = err.decode("utf-8", "replace")
    key = (step["name"].split("/")[0], step["preset"])
    why = REFUSED_BY_DESIGN.get(key)
    if why and rc != 0 and why in rec["stderr"]:
        rec["skipped"] = f"refused by design: {why}"
    f = stdout_file(outdir, step["name"])
    f.parent.mkdir(parents=True, exist_ok=True)
    f.write_bytes(out)
    return rec


def cmd_run(a) -> int:
    binary = str(Path(a.binary).resolve())
    if not os.access(binary, os.X_OK):
        sys.exit(f"compare-outputs: {a.binary} is not an executable")
    outdir = Path(a.outdir).resolve()
    if outdir.exists() and any(outdir.iterdir()):
        if a.clean and (outdir / "commands.jsonl").exists():
            shutil.rmtree(outdir)
        else:
            sys.exit(f"compare-outputs: {outdir} is not empty (geardyn would resume from its "
                     "checkpoints); give a new folder, or --clean for a previous OUTDIR of this script")
    outdir.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ)
    env["RAYON_NUM_THREADS"] = str(a.threads)
    env.pop("SLURM_ARRAY_TASK_ID", None)
    env["LC_ALL"] = "C"
    groups = suite(a.quick_report)
    if a.only:
        groups = [[s for s in g if any(o in s["name"] for o in a.only)] for g in groups]
        groups = [g for g in groups if g]
    log = outdir / "commands.jsonl"
    lock = threading.Lock()
    failed = []

    def run_group(g):
        for step in g:
            rec = run_step(binary, outdir, step, env, a.timeout)
            with lock:
                status = "skipped" if rec.get("skipped") else rec["exit"]
                print(f"{rec['elapsed_s']:7.1f} s  exit {status!s:<7} {step['name']}", flush=True)
                if rec["exit"] != 0 and not rec.get("skipped"):
                    failed.append(step["name"])
                with log.open("a") as fh:
                    fh.write(json.dumps(rec) + "\n")

    t = time.monotonic()
    with log.open("w"):
        pass
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        for f in [pool.submit(run_group, g) for g in groups]:
            f.result()
    # commands.jsonl in suite order, whatever order the jobs finished in
    order = {s["name"]: i for i, s in enumerate(x for g in groups for x in g)}
    lines = sorted(log.read_text().splitlines(), key=lambda l: order[json.loads(l)["name"]])
    log.write_text("".join(l + "\n" for l in lines))
    total = time.monotonic() - t
    print(f"{len(lines)} commands in {total:.0f} s with {binary} (RAYON_NUM_THREADS={a.threads}, "
          f"{a.jobs} at a time) -> {outdir}; failed: {', '.join(failed) or 'none'}")
    return 0


# ---------------------------------------------------------------------------------------------
# compare

# JSON keys that vary between two runs of one binary, or between two builds of the same code,
# and say nothing about the results, by file name: the paths of the keys removed before comparing
# (a section.json is three JSON lines: the cache key, the files' digests, the section)
VOLATILE_KEYS = {
    "run.json": [
        ("elapsed_s",),       # wall time
        ("started_unix_s",),  # start time
        ("git_commit",),      # the build's commit
        ("version",),         # geardyn version
        ("command",),         # argv, with the binary's path
        ("threads",),         # worker threads (fixed by the harness anyway)
    ],
    "summary.json": [("wall_time_s",)],  # simulate: wall time
    "zarr.json": [  # a plan's store: who planned it
        ("attributes", "geardyn", "git_commit"),
        ("attributes", "geardyn", "version"),
    ],
    "section.json": [  # a report's cached study
        (0, "source"),   # cache key: digest of the library's source (changes with any edit)
        (0, "geardyn"),  # cache key: geardyn version
        (2, "seconds"),  # the study's wall time
    ],
}

# a report's study data cache (`.cache/PRESET/STUDY.data.json`, three JSON lines: the cache key,
# the study's wall time, the data): the key's build fields (the wall time line is dropped)
DATA_CACHE_KEYS = [(0, "source"), (0, "geardyn"), (0, "version")]

# volatile fragments of text outputs (report pages, stdout, stderr): (pattern, replacement)
VOLATILE_TEXT = [
    (re.compile(rb"\d+(?:\.\d+)? s\b"), b"<T> s"),             # "in 0.25 s", "(1.3 s)"
    (re.compile(rb"\d+(?:\.\d+)? cells/s\b"), b"<R> cells/s"),  # basins' rate
    (re.compile(rb"Generated by geardyn [^ <]+"), b"Generated by geardyn <V>"),  # version
    # a report's folder size: it counts run.json, whose timing digits vary in length
    (re.compile(rb"This folder: [\d.]+ MB"), b"This folder: <S> MB"),
]


def strip_json(v, paths):
    """`v` without the keys at `paths` (tuples of keys and list indices)."""
    for path in paths:
        node = v
        for k in path[:-1]:
            ok = isinstance(node, dict) and k in node or (
                isinstance(node, list) and isinstance(k, int) and k < len(node))
            if not ok:
                break
            node = node[k]
        else:
            if isinstance(node, dict):
                node.pop(path[-1], None)
    return v


def load_json_text(data: bytes):
    """A .json file: one document, or (a report's section.json) one document per line."""
    text = data.decode("utf-8")
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return [json.loads(line) for line in text.splitlines() if line.strip()]


def first_json_diff(a, b, path="$"):
    if type(a) is not type(b):
        return f"{path}: {short(a)} vs {short(b)}"
    if isinstance(a, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                return f"{path}.{k}: only in {'B' if k not in a else 'A'}"
            d = first_json_diff(a[k], b[k], f"{path}.{k}")
            if d:
                return d
        return None
    if isinstance(a, list):
        for i, (x, y) in enumerate(zip(a, b)):
            d = first_json_diff(x, y, f"{path}[{i}]")
            if d:
                return d
        if len(a) != len(b):
            return f"{path}: length {len(a)} vs {len(b)}"
        return None
    return None if a == b else f"{path}: {short(a)} vs {short(b)}"


def short(v, n=80):
    s = json.dumps(v, ensure_ascii=False) if not isinstance(v, bytes) else v.decode("utf-8", "replace")
    return s if len(s) <= n else s[: n - 3] + "..."


def mask(data: bytes) -> bytes:
    for pat, rep in VOLATILE_TEXT:
        data = pat.sub(rep, data)
    return data


def text_hint(a: bytes, b: bytes) -> str:
    """Where two texts first differ: line, column and the two lines around that column."""
    la, lb = a.split(b"\n"), b.split(b"\n")
    for i, (x, y) in enumerate(zip(la, lb)):
        if x != y:
            c = next((j for j, (p, q) in enumerate(zip(x, y)) if p != q), min(len(x), len(y)))
            lo = max(0, c - 30)
            cut = lambda t: ("..." if lo else "") + short(t[lo:], 90)
            return f"line {i + 1}, column {c + 1}: {cut(x)} | {cut(y)}"
    return f"{len(la)} vs {len(lb)} lines"


def is_text(data: bytes) -> bool:
    if b"\0" in data[:8192]:
        return False
    try:
        data[:8192].decode("utf-8")
        return True
    except UnicodeDecodeError:
        return False


def compare_commands(a: bytes, b: bytes) -> str | None:
    def load(data):
        out = {}
        for line in data.decode("utf-8").splitlines():
            if line.strip():
                r = json.loads(line)
                # lines in any order: a report's studies run side by side and print as they end
                err = sorted(mask(r.get("stderr", "").encode()).decode().splitlines())
                out[r["name"]] = (r.get("exit"), "\n".join(err), r.get("skipped"))
        return out

    ra, rb = load(a), load(b)
    hints = []
    for name in list(ra) + [n for n in rb if n not in ra]:
        if name not in ra or name not in rb:
            hints.append(f"{name}: run on one side only ({'A' if name in ra else 'B'})")
            continue
        (ea, sa, ka), (eb, sb, kb) = ra[name], rb[name]
        if ea != eb:
            hints.append(f"{name}: exit {ea} vs {eb}")
        elif ka != kb:
            hints.append(f"{name}: skipped {ka!r} vs {kb!r}")
        elif sa != sb:
            hints.append(f"{name}: stderr (lines sorted) {text_hint(sa.encode(), sb.encode())}")
    if not hints:
        return None
    more = f" (and {len(hints) - 1} more command(s))" if len(hints) > 1 else ""
    return hints[0] + more


def compare_checkpoint(a: bytes, b: bytes) -> str | None:
    """A sweep's checkpoint: its first line (the run's identity) byte for byte, then one line per
    finished item, appended in the order the worker threads finish them. That order is
    scheduling, not a result (it differs between two runs of one binary), so the items are
    compared as a multiset of lines, each byte for byte."""
    la, lb = a.split(b"\n"), b.split(b"\n")
    if la[0] != lb[0]:
        return f"first line (the run's identity) differs: {text_hint(la[0], lb[0])}"
    sa, sb = sorted(la[1:]), sorted(lb[1:])
    if sa == sb:
        return None
    set_a, set_b = set(sa), set(sb)
    only_a = [x for x in sa if x not in set_b]
    only_b = [x for x in sb if x not in set_a]
    return (f"{len(la) - 1} vs {len(lb) - 1} item lines (order ignored); "
            f"first only in A: {short(only_a[0]) if only_a else '-'}; "
            f"first only in B: {short(only_b[0]) if only_b else '-'}")


def compare_file(rel: str, a: bytes, b: bytes) -> str | None:
    """None when equal, else a short hint."""
    if a == b:
        return None
    name = rel.rsplit("/", 1)[-1]
    if rel == "commands.jsonl":
        return compare_commands(a, b)
    if name.endswith(".json"):
        try:
            paths = VOLATILE_KEYS.get(name, [])
            ja, jb = strip_json(load_json_text(a), paths), strip_json(load_json_text(b), paths)
            if name.endswith(".data.json") and isinstance(ja, list) and isinstance(jb, list):
                # a report's data cache: the key (digest of the library's source, version), the
                # study's wall time, the data: only the data and the request count
                ja, jb = (strip_json(j, DATA_CACHE_KEYS) for j in (ja, jb))
                ja, jb = ja[:1] + ja[2:], jb[:1] + jb[2:]
        except (UnicodeDecodeError, json.JSONDecodeError) as e:
            return f"not JSON ({e}); {len(a)} vs {len(b)} bytes"
        return first_json_diff(ja, jb)
    if name == "checkpoint.jsonl":
        return compare_checkpoint(a, b)
    if name.endswith(".html") or rel.startswith("stdout/"):
        ma, mb = mask(a), mask(b)
        return None if ma == mb else text_hint(ma, mb)
    if is_text(a) and is_text(b):
        return text_hint(a, b)
    off = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
    return f"binary: {len(a)} vs {len(b)} bytes, first difference at byte {off}"


def files(root: Path) -> set[str]:
    return {p.relative_to(root).as_posix() for p in root.rglob("*") if p.is_file()}


def cmd_compare(a) -> int:
    ra, rb = Path(a.dir_a), Path(a.dir_b)
    for r in (ra, rb):
        if not r.is_dir():
            sys.exit(f"compare-outputs: {r} is not a folder")
    fa, fb = files(ra), files(rb)
    n = 0
    for rel in sorted(fa | fb):
        if rel not in fb:
            hint = "only in A"
        elif rel not in fa:
            hint = "only in B"
        else:
            hint = compare_file(rel, (ra / rel).read_bytes(), (rb / rel).read_bytes())
        if hint:
            n += 1
            print(f"DIFF {rel}: {hint}")
    print(f"{n} differing file(s) of {len(fa | fb)} ({len(fa)} in {ra}, {len(fb)} in {rb})")
    return 0 if n == 0 else 1


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="run the suite with BINARY into OUTDIR")
    r.add_argument("binary")
    r.add_argument("outdir")
    r.add_argument("--quick-report", action="store_true",
                   help="also `report --quick` of each preset (about 3 minutes in all)")
    r.add_argument("--jobs", type=int, default=1, help="commands run side by side (default 1)")
    r.add_argument("--threads", type=int, default=2, help="RAYON_NUM_THREADS (default 2)")
    r.add_argument("--timeout", type=float, default=900, help="seconds per command (default 900)")
    r.add_argument("--only", action="append", help="run only commands whose name contains this")
    r.add_argument("--clean", action="store_true",
                   help="empty OUTDIR first when it holds a previous run of this script")
    c = sub.add_parser("compare", help="compare two OUTDIRs file by file")
    c.add_argument("dir_a")
    c.add_argument("dir_b")
    a = ap.parse_args()
    return cmd_run(a) if a.cmd == "run" else cmd_compare(a)


if __name__ == "__main__":
    sys.exit(main())
