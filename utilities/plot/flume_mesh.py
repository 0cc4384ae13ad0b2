#!/usr/bin/python3
"""The flume's mesh study (Feng et al. 2025, Appendix C: Table C-2 and Fig. C-2) from the runs'
own output.

    flume_mesh.py LABEL=RUN [LABEL=RUN ...] [-o OUTDIR] [--times 0.4 0.8 3.0]

Each RUN is a finished run of cases/flume or one of its variants (S-1, S-2, S-4: 20, 10 and
2.5 mm cells), holding postProcessing/ (massFront/runOut.csv, surface/<time>.csv) and, when
measure/gpu-flume.sh collected it, run.log (for the points, steps and wall time). Times are
given after the gate's release (_releaseTime, 0.05 s). Writes to OUTDIR:

  table_c2.md        the table: cells, points, steps, wall time, the mass front (0.99 quantile)
                     along the flume's path from the box's back wall at each time
  table_c2.json      the same numbers
  fig_c2_surfaces.png  the free surfaces of every run at each time (Fig. C-2)

Run with Debian's /usr/bin/python3 (python3-matplotlib, python3-numpy).
"""

import argparse
import glob
import json
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from column_collapse import read_csv  # noqa: E402
from flume import X_TOP, along, axes_flume  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

RELEASE = 0.05  # s: _releaseTime of cases/flume/system/stages


def log_facts(run):
    """Points, cell size, steps and wall time from run.log (scree's header and last lines)."""
    f = {}
    p = os.path.join(run, "run.log")
    if not os.path.exists(p):
        return f
    text = open(p, errors="replace").read()
    m = re.search(r"(\d+) particles, (\d+) grid nodes", text)
    if m:
        f["points"] = int(m.group(1))
    steps = re.findall(r"step\s+(\d+)", text)
    if steps:
        f["steps"] = int(steps[-1])
    m = re.findall(r"([\d.]+) s wall", text)
    if m:
        f["wall_s"] = float(m[-1])
    return f


def surface(run, t):
    """The free surface (distance, height) written nearest to t, within 1 ms."""
    best = None
    for p in glob.glob(os.path.join(run, "postProcessing", "surface", "*.csv")):
        try:
            tt = float(os.path.basename(p)[:-4])
        except ValueError:
            continue
        if abs(tt - t) < 1e-3 and (best is None or abs(tt - t) < abs(best[0] - t)):
            best = (tt, p)
    if best is None:
        return None
    d = np.genfromtxt(best[1], delimiter=",", skip_header=1)
    return d[:, 0], d[:, 1]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="LABEL=RUN")
    ap.add_argument("-o", "--out", default="flume-mesh")
    ap.add_argument("--times", type=float, nargs="+", default=[0.4, 0.8, 3.0], help="after the release [s]")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    rows = {}
    fig, axs = plt.subplots(len(a.times), 1, figsize=(9, 3.0 * len(a.times)))
    axs = np.atleast_1d(axs)
    for spec in a.runs:
        label, run = spec.split("=", 1)
        r = log_facts(run)
        mf = os.path.join(run, "postProcessing", "massFront", "runOut.csv")
        fronts = {}
        if os.path.exists(mf):
            ro = read_csv(mf)
            tt = ro["time"] - RELEASE
            for t in a.times:
                j = int(np.argmin(np.abs(tt - t)))
                if abs(tt[j] - t) < 0.006:
                    fronts["%g" % t] = float(along(ro["runout"][j], X_TOP))
            r["end_after_release_s"] = float(tt[-1])
        r["mass_front_from_back_wall_m"] = fronts
        rows[label] = r
        for ax, t in zip(axs, a.times):
            s = surface(run, t + RELEASE)
            if s is not None:
                ax.plot(s[0], s[1], lw=1, label=label)
    for ax, t in zip(axs, a.times):
        axes_flume(ax)
        ax.set_title("free surface %g s after the release" % t, fontsize=9)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "fig_c2_surfaces.png"), dpi=140)
    with open(os.path.join(a.out, "table_c2.json"), "w") as f:
        json.dump(rows, f, indent=1)
    head = "| run | points | steps | wall [s] | " + " | ".join("front %g s [m]" % t for t in a.times) + " |"
    lines = [head, "|" + " --- |" * (4 + len(a.times))]
    for label, r in rows.items():
        fr = r["mass_front_from_back_wall_m"]
        lines.append("| %s | %s | %s | %s | %s |" % (
            label, r.get("points", ""), r.get("steps", ""), "%.0f" % r["wall_s"] if "wall_s" in r else "",
            " | ".join("%.3f" % fr[k] if k in fr else "" for k in ("%g" % t for t in a.times))))
    open(os.path.join(a.out, "table_c2.md"), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
