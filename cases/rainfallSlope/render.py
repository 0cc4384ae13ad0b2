#!/usr/bin/python3
"""Pictures of cases/rainfallSlope from the run's own output (VTK series, postProcessing/).

    /usr/bin/python3 cases/rainfallSlope/render.py [CASE] [--times t0 t1 ...] [--out DIR]

CASE defaults to this script's directory, DIR to CASE/figures. Writes
  saturation.png    S_l of every point at SATURATION_TIMES (below; or --times), the write
                    times nearest them
  displacement.png  |u| of every point at DISPLACEMENT_TIMES (or --times), log scale
  history.png       displacement of the probes, kinetic energy and the water taken in
Points are drawn as squares of their initial spacing in their current positions (matplotlib,
no window: the Agg backend).
"""
import argparse
import csv
import glob
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import colors  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
import numpy as np  # noqa: E402
import vtk  # noqa: E402
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402

from balance import stored  # noqa: E402  (beside this script)

HERE = os.path.dirname(os.path.abspath(__file__))
RAIN_START = 0.5      # system/stages: _rainStart [s]
RAIN = 1e-2           # _rainIntensity [m/s]
RAIN_WIDTH = 3.1      # horizontal width under the rain box: crest 1.5 m + face 1.6 m [m]
SPACING = 0.05        # initial point spacing: cellSize 0.1 / particlesPerCell 2 [m]
SATURATION_TIMES = (0, 2, 5, 10, 14, 16)       # [s] before the rain, the front going down, failure
DISPLACEMENT_TIMES = (10, 15, 16, 17, 18, 30)  # [s] creep, the slide starting, running, at rest


def series(case):
    files = glob.glob(os.path.join(case, "VTK", "particles_*.vtp"))
    if not files:
        raise SystemExit(f"no VTK/particles_*.vtp under {case}: run the case first")
    return sorted(files, key=lambda f: int(f.rsplit("_", 1)[1][:-4]))


def read(path):
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    o = r.GetOutput()
    d = {"x": vtk_to_numpy(o.GetPoints().GetData())[:, :2]}
    for n in ("saturation", "displacement", "porePressure"):
        d[n] = vtk_to_numpy(o.GetPointData().GetArray(n))
    d["time"] = float(vtk_to_numpy(o.GetFieldData().GetArray("TimeValue"))[0])
    return d


def pick(files, times):
    """The files nearest the requested times."""
    # The .pvd has the times without reading the points.
    pvd = os.path.join(os.path.dirname(files[0]), "particles.pvd")
    t_of = {}
    with open(pvd) as fh:
        for line in fh:
            if "<DataSet" in line:
                t = float(line.split('timestep="')[1].split('"')[0])
                name = line.split('file="')[1].split('"')[0]
                t_of[os.path.basename(name)] = t
    ts = np.array([t_of[os.path.basename(f)] for f in files])
    idx = sorted({int(np.argmin(np.abs(ts - t))) for t in times})
    return [files[i] for i in idx]


def panels(snaps, field, label, cmap, norm, out, title):
    n = len(snaps)
    cols = 2 if n > 1 else 1
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(5.2 * cols, 1.9 * rows + 0.6), squeeze=False,
                             constrained_layout=True)
    for ax, d in zip(axes.flat, snaps):
        # Each point a square of its initial spacing (h / 2), centred on its current position.
        sq = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * SPACING / 2
        sc = PolyCollection(d["x"][:, None, :] + sq[None], array=field(d), cmap=cmap, norm=norm, linewidths=0,
                            rasterized=True)
        ax.add_collection(sc)
        ax.set_xlim(0, 6)
        ax.set_ylim(0, 3.0)
        ax.set_aspect("equal")
        ax.set_title(f"t = {d['time']:.1f} s" + ("  (rain from 0.5 s)" if d["time"] == 0 else ""), fontsize=9)
        ax.tick_params(labelsize=7)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    fig.colorbar(sc, ax=axes, shrink=0.8, label=label)
    fig.suptitle(title, fontsize=10)
    fig.savefig(out, dpi=90)
    plt.close(fig)


def read_csv(path):
    with open(path) as fh:
        rows = list(csv.reader(fh))
    head = rows[0]
    data = np.array([[float(c) for c in r] for r in rows[1:]])
    return {h: data[:, i] for i, h in enumerate(head)}


def history(case, out):
    pp = os.path.join(case, "postProcessing")
    fig, ax = plt.subplots(3, 1, figsize=(7, 7.2), sharex=True, constrained_layout=True)
    for name in ("crest", "crestEdge", "midFace", "toe"):
        f = os.path.join(pp, "probes", name + ".csv")
        if os.path.exists(f):
            c = read_csv(f)
            u = np.hypot(c["displacement_x [m]"], c["displacement_y [m]"])
            ax[0].semilogy(c["time [s]"], np.maximum(u, 1e-5), label=name)
    ax[0].set_ylabel("|u| of probe [m]")
    ax[0].legend(fontsize=8)
    f = os.path.join(pp, "energy", "energies.csv")
    if os.path.exists(f):
        c = read_csv(f)
        ax[1].semilogy(c["time [s]"], np.maximum(c["kinetic [J/m]"], 1e-6))
    ax[1].set_ylabel("kinetic energy [J/m]")
    f = os.path.join(pp, "water", "waterBalance.csv")
    if os.path.exists(f):
        c = read_csv(f)
        t = c["time [s]"]
        ax[2].plot(t, c["inflowSurface [kg/m]"], label="in through the surfaces (solver's count)")
        w = [stored(f) for f in series(case)]
        ax[2].plot([x[0] for x in w], [x[1] - w[0][1] for x in w], "k.-", ms=3,
                   label="stored in the slope, change (VTK, balance.py)")
        ax[2].plot(t, 1000 * RAIN * RAIN_WIDTH * np.maximum(t - RAIN_START, 0), "--",
                   label=f"rain falling on the box: {RAIN:g} m/s x {RAIN_WIDTH} m")
    ax[2].set_ylabel("water [kg/m]")
    ax[2].set_xlabel("t [s]")
    ax[2].legend(fontsize=8)
    for a in ax:
        a.axvline(RAIN_START, color="0.6", lw=0.8)
        a.grid(alpha=0.3)
    fig.savefig(out, dpi=90)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case", nargs="?", default=HERE)
    ap.add_argument("--times", type=float, nargs="*", default=None)
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    out = a.out or os.path.join(a.case, "figures")
    os.makedirs(out, exist_ok=True)
    files = series(a.case)
    snaps = [read(f) for f in pick(files, a.times or SATURATION_TIMES)]
    panels(snaps, lambda d: d["saturation"], "degree of saturation S_l [-]", "viridis_r",
           colors.Normalize(0.55, 1.0), os.path.join(out, "saturation.png"), "Saturation")
    snaps = [read(f) for f in pick(files, a.times or DISPLACEMENT_TIMES)]
    panels(snaps, lambda d: np.maximum(np.hypot(d["displacement"][:, 0], d["displacement"][:, 1]), 1e-4),
           "|u| [m]", "magma_r", colors.LogNorm(1e-3, 1.0), os.path.join(out, "displacement.png"),
           "Displacement magnitude")
    history(a.case, os.path.join(out, "history.png"))
    for f in ("saturation.png", "displacement.png", "history.png"):
        p = os.path.join(out, f)
        print(p, os.path.getsize(p) // 1024, "KB")


if __name__ == "__main__":
    main()
