#!/usr/bin/python3
"""The 3D flume (cases/flume3D) against the 2D one (cases/flume): how much do the side
walls change the front? Each run is LABEL=DIR (DIR holds the run's postProcessing/); the
2D run is given with --2d, e.g.

  flume3d.py slip=runs/slip friction=runs/friction --2d runs/S-2 -o figures

Reads postProcessing/massFront/runOut.csv (the 0.99 quantile of x, turned into the
distance along the flume's path from the box's back wall with flume.py's along(), as the 2D
case's README reports it) and, for the 3D runs, the height fields
postProcessing/surface/<time>.csv (x, z, height): the front of the layer at least one cell
thick in each strip across the width, next to the walls and in the middle.
Writes front_history.png, plan_<label>.png, summary.json.

Run with Debian's /usr/bin/python3 (python3-numpy, python3-matplotlib).
"""
import argparse
import glob
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from axisymmetric import read_csv  # noqa: E402
from flume import PAPER_FRONT, X_GATE, X_TOP, COS, along  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

RELEASE = 0.05  # s: cases/flume/system/stages
TIMES = (0.4, 0.8)  # s after the release: the paper's front positions
WIDTH = 0.3  # m: the flume's width (cases/flume3D/system/gridDict)


def front_from_back_wall(ro, t):
    """The mass front at t after the release, from the box's back wall along the path."""
    i = int(np.argmin(abs(ro["time"] - (t + RELEASE))))
    return float(along(ro["runout"][i], X_GATE) + (X_GATE - X_TOP) / COS), float(ro["time"][i] - RELEASE)


def surface_at(run, t):
    files = glob.glob(os.path.join(run, "postProcessing", "surface", "*.csv"))
    if not files:
        return None
    tt, f = min((abs(float(os.path.basename(p)[:-4]) - (t + RELEASE)), p) for p in files)
    return read_csv(f) if tt < 1e-3 else None


def strip_fronts(surf, cell, strips=((0.0, 0.03), (0.12, 0.18), (0.27, 0.30))):
    """For each strip of z, the largest x where the sand is at least one cell thick, as the
    distance along the path from the back wall."""
    x, z, h = surf["x"], surf["z"], surf["height"]
    out = {}
    for z0, z1 in strips:
        sel = (z >= z0) & (z <= z1) & np.isfinite(h)
        if not sel.any():
            continue
        # the sand's thickness: height above the bed (the slope x + y = X_TOE, or the floor)
        bed = np.maximum(1.826346 - x[sel], 0.0)
        thick = h[sel] - bed
        xs = x[sel][thick >= cell]
        if len(xs):
            out["z %.2f-%.2f m" % (z0, z1)] = float(along(xs.max(), X_GATE) + (X_GATE - X_TOP) / COS)
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("runs", nargs="+", help="LABEL=DIR of a 3D run")
    p.add_argument("--2d", dest="run2d", help="the 2D run's directory (the same cell size)")
    p.add_argument("--cell", type=float, default=0.01, help="the runs' cell size [m]")
    p.add_argument("-o", "--out", default=".", help="output directory")
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)
    runs = [tuple(s.split("=", 1)) for s in args.runs]
    if args.run2d:
        runs = [("2D", args.run2d)] + runs
    summary = {"paper_front_from_back_wall_m": {"%g" % k: v for k, v in PAPER_FRONT.items()}, "runs": {}}
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for label, run in runs:
        ro = read_csv(os.path.join(run, "postProcessing", "massFront", "runOut.csv"))
        t = ro["time"] - RELEASE
        sel = t >= 0
        ax.plot(t[sel], along(ro["runout"][sel], X_GATE) + (X_GATE - X_TOP) / COS, label=label)
        rec = {}
        for tt in TIMES:
            f, at = front_from_back_wall(ro, tt)
            rec["%g s" % tt] = {"mass_front_from_back_wall_m": f, "at_s": at}
            if label != "2D":
                s = surface_at(run, tt)
                if s is not None:
                    rec["%g s" % tt]["strip_fronts_from_back_wall_m"] = strip_fronts(s, args.cell)
        summary["runs"][label] = rec
    for tt, d in PAPER_FRONT.items():
        ax.plot([tt], [d], "k*", ms=9)
    ax.plot([], [], "k*", label="paper (Feng et al. 2025)")
    ax.set_xlabel("t after the release [s]")
    ax.set_ylabel("mass front from the back wall [m]")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "front_history.png"), dpi=150)
    if "2D" in summary["runs"]:
        base = summary["runs"]["2D"]
        summary["difference_to_2D_m"] = {
            label: {k: rec[k]["mass_front_from_back_wall_m"] - base[k]["mass_front_from_back_wall_m"] for k in rec}
            for label, rec in summary["runs"].items() if label != "2D"}
    # plan views of the 3D runs' height fields at the two times
    for label, run in runs:
        if label == "2D":
            continue
        fig, axs = plt.subplots(2, 1, figsize=(8, 4.5), sharex=True)
        for axp, tt in zip(axs, TIMES):
            s = surface_at(run, tt)
            if s is None:
                continue
            bed = np.maximum(1.826346 - s["x"], 0.0)
            sc = axp.scatter(s["x"], s["z"], c=s["height"] - bed, s=4, marker="s", cmap="viridis", vmin=0)
            axp.set_ylabel("z [m]")
            axp.set_title("%s, %.1f s after the release: thickness above the bed [m]" % (label, tt), fontsize=9)
            axp.set_ylim(0, WIDTH)
            fig.colorbar(sc, ax=axp)
        axs[-1].set_xlabel("x [m]")
        fig.tight_layout()
        fig.savefig(os.path.join(args.out, "plan_%s.png" % label), dpi=150)
    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    print(json.dumps(summary, indent=1))


if __name__ == "__main__":
    main()
