#!/usr/bin/env python3
"""The size limits of the code (issue 47): no source file over 1000 lines and no function over
150 lines outside tests and generated tables. Prints what exceeds them; exit status 1 if any.

A function's length runs from its `fn` line to the line of its closing brace (found by counting
braces outside strings, chars and comments, which is enough for this code base). Tests: files
under `tests/` or `benches/`, and `#[cfg(test)]` modules, are skipped.

    scripts/code-limits.py [--files N] [--functions N] [PATH...]
"""
import argparse
import pathlib
import re
import sys

FN = re.compile(r"^\s*(pub(\([^)]*\))?\s+)?(const\s+)?(async\s+)?(unsafe\s+)?(extern\s+\"C\"\s+)?fn\s+(\w+)")


def strip(line, state):
    """The line without strings, chars and comments; `state` carries a block comment across lines."""
    out, i, n = [], 0, len(line)
    while i < n:
        if state["block"]:
            j = line.find("*/", i)
            if j < 0:
                return "".join(out)
            state["block"], i = False, j + 2
            continue
        c = line[i]
        if line.startswith("//", i):
            break
        if line.startswith("/*", i):
            state["block"], i = True, i + 2
            continue
        if c == '"':
            j = i + 1
            while j < n and line[j] != '"':
                j += 2 if line[j] == "\\" else 1
            i = j + 1
            continue
        if c == "'" and re.match(r"'(\\.|[^\\'])'", line[i:]):
            i += len(re.match(r"'(\\.|[^\\'])'", line[i:]).group(0))
            continue
        out.append(c)
        i += 1
    return "".join(out)


def functions(path):
    lines = path.read_text().splitlines()
    state = {"block": False}
    code = [strip(l, state) for l in lines]
    skip_from = None
    for i, l in enumerate(lines):
        if l.strip() == "#[cfg(test)]":
            skip_from = i
            break
    for i, l in enumerate(code):
        if skip_from is not None and i >= skip_from:
            break
        m = FN.match(l)
        if not m:
            continue
        depth, opened = 0, False
        for j in range(i, len(code)):
            if not opened and ";" in code[j] and "{" not in code[j]:
                break  # a declaration without a body
            depth += code[j].count("{") - code[j].count("}")
            opened = opened or "{" in code[j]
            if opened and depth <= 0:
                yield m.group(7), i + 1, j - i + 1
                break


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--files", type=int, default=1000)
    ap.add_argument("--functions", type=int, default=150)
    ap.add_argument("paths", nargs="*", default=["crates", "python/src", "python/geardyn", "src"])
    a = ap.parse_args()
    bad = 0
    for root in a.paths:
        for p in sorted(pathlib.Path(root).rglob("*")):
            if p.suffix not in (".rs", ".py") or any(x in ("tests", "benches", "target") for x in p.parts):
                continue
            n = len(p.read_text().splitlines())
            if n > a.files:
                print(f"file {p}: {n} lines")
                bad += 1
            if p.suffix == ".rs":
                for name, line, length in functions(p):
                    if length > a.functions:
                        print(f"fn {p}:{line} {name}: {length} lines")
                        bad += 1
    print(f"{bad} over the limits (files {a.files}, functions {a.functions} lines)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
