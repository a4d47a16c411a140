"""Seed figure A6 (docs/seeds.md): bifurcation of the broken 40/40 pair over the load F at
omega = 1.2, with the back-side impacts, from Python.

The same study as

    geardyn bifurcation --preset breakage --set omega=1.2 --param F --range 0:0.15:97 \
        --sections strobe,impact --out out/A6

Run it as a script (``python python/examples/load_sweep_a6.py [--quick] [--out DIR]``) or cell by
cell in a notebook. It writes ``a6_load_sweep.png`` when matplotlib is installed and always
``a6_runs.csv`` (one row per load) and a text table, using numpy only. The figure shows the
stroboscopic section and the impact velocity at every back-side impact over the load.
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import geardyn

# %% settings
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--quick", action="store_true", help="coarse version (seconds)")
parser.add_argument("--out", default="out/python-a6", help="output folder")
args, _ = parser.parse_known_args()
out = Path(args.out)
out.mkdir(parents=True, exist_ok=True)

if args.quick:
    values, lengths = (0.0, 0.15, 16), dict(transient=60, periods=12)
else:
    values, lengths = (0.0, 0.15, 97), {}  # the config's 300 + 100 excitation periods

# %% the sweep (the library's threads; Ctrl-C stops it)
t = time.monotonic()
r = geardyn.bifurcation(
    preset="breakage",
    omega=1.2,
    param="F",
    range=values,
    sections=["strobe", "impact"],
    progress=sys.stderr.isatty(),
    **lengths,
)
print(f"{len(r.values)} loads in {time.monotonic() - t:.1f} s")

# %% one row per load: label, period, impacts, largest impact force
runs = r.runs
# (the runs table as the CLI writes it would be r.to_dataframe().to_csv(...) with pandas; here a
# few columns with numpy only, numbers in shortest round-trip form)
header = "F,label,period,healthy,impacts,max_impact_force,max_force"
rows = [
    f"{float(F)!r},{lab},{per},{str(h).lower()},{imp},{float(fi)!r},{float(fm)!r}"
    for F, lab, per, h, imp, fi, fm in zip(
        runs["F"], runs["label"], runs["period"], runs["healthy"], runs["impacts"],
        runs["max_impact_force"], runs["max_force"],
    )
]
(out / "a6_runs.csv").write_text(header + "\n" + "\n".join(rows) + "\n")

print(f"{'F':>8}  {'label':<32} {'impacts':>8} {'max impact force':>17}")
for F, lab, imp, fi in zip(runs["F"], runs["label"], runs["impacts"], runs["max_impact_force"]):
    print(f"{F:8.4f}  {lab:<32} {imp:8d} {fi:17.4f}")

# the seed's statement: no impacts above F = 0.1, impacts below
high = runs["F"] > 0.1
print(
    f"loads with impacts: {np.mean(runs['impacts'][~high] > 0):.0%} of F <= 0.1, "
    f"{np.mean(runs['impacts'][high] > 0):.0%} of F > 0.1"
)

# %% the figure (only if matplotlib is there)
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("matplotlib not installed: table and CSV only")
else:
    pts = r.points
    fig, ax = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
    # the stroboscopic section shows the motion; at a back-side impact x is the stop itself
    # (x = -D_s, the same number at every impact), so the impact section is drawn by the
    # impact velocity, which measures how hard the teeth strike
    m = pts["section"] == "strobe"
    ax[0].plot(pts["F"][m], pts["x"][m], ".k", ms=1.5)
    ax[0].set_ylabel("x (stroboscopic)")
    ax[0].set_title("stroboscopic section")
    m = pts["section"] == "impact"
    ax[1].plot(pts["F"][m], np.abs(pts["v"][m]), ".r", ms=2)
    ax[1].set_ylabel("|x'| at back-side impact")
    ax[1].set_title("back-side impacts")
    ax[1].set_xlabel("F")
    fig.suptitle("Broken 40/40 pair, omega = 1.2 (seed A6)")
    fig.tight_layout()
    fig.savefig(out / "a6_load_sweep.png", dpi=120)
    print(f"-> {out / 'a6_load_sweep.png'}")
